"""The Python module of a generated package (dyngen --python) against the C++ runtime (dyngen eval)
and against finite differences of its own functions.

Run by ctest (tests/python/CMakeLists.txt) with the module on PYTHONPATH and the environment:
DYNGEN_MODULE (the module's name), DYNGEN (the dyngen executable), DYNGEN_ROBOT (the robot file)
and DYNGEN_ROBOT_OPTIONS (the model options it was generated with, for dyngen eval).
"""
import importlib
import json
import os
import shlex
import subprocess

import numpy as np
import pytest

d = importlib.import_module(os.environ["DYNGEN_MODULE"])
single = d.dtype == np.float32
# a float module keeps about 7 digits, and the runtime it is compared with computes in double
relative = 2e-3 if single else 0.0


def states(n, seed=1):
    """n random states: q, v, a and tau, with unit quaternions for free joints."""
    rng = np.random.default_rng(seed)
    q = rng.uniform(-3.0, 3.0, (n, d.nq))
    for k in d.quaternion_indices:
        q[:, k:k + 4] /= np.linalg.norm(q[:, k:k + 4], axis=1, keepdims=True)
    v, a, tau = (rng.uniform(-3.0, 3.0, (n, d.nv)) for _ in range(3))
    return tuple(x.astype(d.dtype) for x in (q, v, a, tau))


def close(mine, reference, what):
    """Bit for bit (+0 and -0 equal) for double; within `relative` of the array's size for float."""
    reference = np.asarray(reference, dtype=np.float64)
    error = np.max(np.abs(mine - reference)) if mine.size else 0.0
    bound = relative * max(1.0, np.max(np.abs(reference)))
    assert error <= bound, f"{what}: off by {error:.3g}, bound {bound:.3g}"


def runtime(q, v, a, tau):
    """dyngen eval's results (the C++ runtime, in double) for the states, with derivatives."""
    listed = [{"q": q[s].tolist(), "v": v[s].tolist(), "a": a[s].tolist(), "tau": tau[s].tolist()}
              for s in range(len(q))]
    command = [os.environ["DYNGEN"], "eval", os.environ["DYNGEN_ROBOT"], "--states", "-",
               "--derivatives", *shlex.split(os.environ.get("DYNGEN_ROBOT_OPTIONS", ""))]
    out = subprocess.run(command, input=json.dumps(listed), capture_output=True, text=True,
                         check=True).stdout
    return json.loads(out)["results"]


def test_matches_the_runtime():
    q, v, a, tau = states(9)
    results = runtime(q.astype(np.float64), v.astype(np.float64), a.astype(np.float64),
                      tau.astype(np.float64))
    mine = {"tau": d.rnea(q, v, a), "qdd": d.aba(q, v, tau), "M": d.crba(q), "Minv": d.minv(q)}
    mine["dtau_dq"], mine["dtau_dv"] = d.rnea_derivatives(q, v, a)
    mine["dqdd_dq"], mine["dqdd_dv"], _ = d.aba_derivatives(q, v, tau)
    for s, result in enumerate(results):
        for key, value in mine.items():
            close(value[s], result[key], f"{key} of state {s}")


def test_one_state_and_many_states_give_the_same_bits():
    q, v, a, tau = states(2 * d.lanes + 3)  # whole batches and a partial one
    many = d.aba(q, v, tau)
    assert many.shape == (len(q), d.nv)
    for s in range(len(q)):
        assert np.array_equal(d.aba(q[s], v[s], tau[s]), many[s])
    M = d.crba(q)
    assert M.shape == (len(q), d.nv, d.nv)
    for s in range(len(q)):
        assert np.array_equal(d.crba(q[s]), M[s])


def test_threads_give_the_same_bits():
    q, v, a, tau = states(1001)
    assert np.array_equal(d.rnea(q, v, a, threads=3), d.rnea(q, v, a))
    assert np.array_equal(d.aba(q, v, tau, threads=2), d.aba(q, v, tau))


def test_results_go_into_the_arrays_given_as_out():
    q, v, a, tau = states(9)
    qdd = np.empty((9, d.nv), dtype=d.dtype)
    assert d.aba(q, v, tau, out=qdd) is qdd
    assert np.array_equal(qdd, d.aba(q, v, tau))
    dtau = (np.empty((9, d.nv, d.nv), dtype=d.dtype), np.empty((9, d.nv, d.nv), dtype=d.dtype))
    result = d.rnea_derivatives(q, v, a, out=dtau)
    assert result[0] is dtau[0] and result[1] is dtau[1]
    for mine, new in zip(dtau, d.rnea_derivatives(q, v, a)):
        assert np.array_equal(mine, new)
    with pytest.raises(ValueError, match=r"out: qdd has shape \(8, "):
        d.aba(q, v, tau, out=qdd[:8])
    with pytest.raises(TypeError, match="a tuple of 2 arrays"):
        d.rnea_derivatives(q, v, a, out=dtau[0])


def test_no_states_give_empty_results():
    q, v, a, _ = states(0)
    assert d.rnea(q, v, a).shape == (0, d.nv)


def test_strided_inputs_are_read_as_they_are():
    q, v, a, _ = states(8)
    every_other = np.repeat(q, 2, axis=0)[::2]  # not C-contiguous
    assert not every_other.flags.c_contiguous
    assert np.array_equal(d.rnea(every_other, v, a), d.rnea(q, v, a))


def test_mass_matrix_against_differences_of_rnea():
    # tau is linear in a, so central differences are exact up to rounding at any step
    q, v, a, _ = states(4)
    M = d.crba(q)
    for j in range(d.nv):
        e = np.zeros(d.nv, dtype=d.dtype)
        e[j] = 1
        column = (d.rnea(q, v, a + e) - d.rnea(q, v, a - e)) / 2
        scale = np.max(np.abs(d.rnea(q, v, a)))
        assert np.max(np.abs(column - M[:, :, j])) <= 1e3 * np.finfo(d.dtype).eps * scale


def test_velocity_derivatives_against_differences():
    # tau and qdd are quadratic in v, so central differences are exact up to rounding too
    q, v, a, tau = states(4)
    _, dtau_dv = d.rnea_derivatives(q, v, a)
    _, dqdd_dv, Minv = d.aba_derivatives(q, v, tau)
    for j in range(d.nv):
        e = np.zeros(d.nv, dtype=d.dtype)
        e[j] = 1
        for f, x, derivative in ((d.rnea, a, dtau_dv), (d.aba, tau, dqdd_dv)):
            column = (f(q, v + e, x) - f(q, v - e, x)) / 2
            scale = np.max(np.abs(f(q, v + e, x))) + np.max(np.abs(derivative))
            assert np.max(np.abs(column - derivative[:, :, j])) <= 1e3 * np.finfo(d.dtype).eps * scale
    identity = np.einsum("nij,njk->nik", Minv.astype(np.float64), d.crba(q).astype(np.float64))
    assert np.max(np.abs(identity - np.eye(d.nv))) <= 1e4 * np.finfo(d.dtype).eps


@pytest.mark.skipif(len(d.quaternion_indices) > 0 or single,
                    reason="a free joint's columns are tangent directions; float differences are noise")
def test_position_derivatives_against_differences():
    q, v, a, _ = states(4)
    dtau_dq, _ = d.rnea_derivatives(q, v, a)
    h = 1e-6
    for j in range(d.nv):
        e = np.zeros(d.nq)
        e[j] = h
        column = (d.rnea(q + e, v, a) - d.rnea(q - e, v, a)) / (2 * h)
        assert np.max(np.abs(column - dtau_dq[:, :, j])) <= 1e-6 * max(1.0, np.max(np.abs(dtau_dq)))


def test_wrong_inputs_raise_clear_errors():
    q, v, a, _ = states(5)
    other = np.float64 if single else np.float32
    with pytest.raises(TypeError, match="q: dtype"):
        d.rnea(q.astype(other), v, a)
    with pytest.raises(ValueError, match=r"v: shape \(5, 2\)"):
        d.rnea(q, v[:, :2], a)
    with pytest.raises(ValueError, match="a holds 4 states and q 5"):
        d.rnea(q, v, a[:4])
    with pytest.raises(ValueError, match="holds one state"):
        d.rnea(q, v[0], a)
    with pytest.raises(ValueError, match="threads"):
        d.rnea(q, v, a, threads=0)


def test_module_constants():
    assert len(d.joint_names) == d.nv
    assert d.total_mass > 0
    assert len(d.gravity_acceleration) == 3
    assert d.lanes in (2, 4, 8, 16)

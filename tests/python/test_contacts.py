"""The Python module's contact_dynamics and impulse_dynamics (dyngen --python --contacts) against
the C++ runtime (dyngen eval --contacts), bit for bit, and the constraint forces against the
module's own rnea: rnea(q, v, qdd) = tau + J^T lambda, with J from dyngen eval --frames; where the
module has them, contact_dynamics_derivatives against the runtime's and against central
differences of the module's contact_dynamics.

Run by ctest (tests/python/CMakeLists.txt, run_module_test.cmake) beside test_module.py, with
DYNGEN_CONTACTS the --contacts the module was generated with.
"""
import importlib
import json
import os
import shlex
import subprocess

import numpy as np
import pytest

d = importlib.import_module(os.environ["DYNGEN_MODULE"])
contacts = os.environ["DYNGEN_CONTACTS"]
links = [c.split(":")[0] for c in contacts.split(",")]
rows = [6 if c.endswith(":6d") else 3 for c in contacts.split(",")]


def states(n, seed=3):
    """n random states: q with unit quaternions, v and tau."""
    rng = np.random.default_rng(seed)
    q = rng.uniform(-3.0, 3.0, (n, d.nq))
    for k in d.quaternion_indices:
        q[:, k:k + 4] /= np.linalg.norm(q[:, k:k + 4], axis=1, keepdims=True)
    v, tau = (rng.uniform(-3.0, 3.0, (n, d.nv)) for _ in range(2))
    return tuple(x.astype(d.dtype) for x in (q, v, tau))


def runtime(states_given, *options):
    """dyngen eval --contacts (the C++ runtime, in double) at the states."""
    command = [os.environ["DYNGEN"], "eval", os.environ["DYNGEN_ROBOT"], "--states", "-",
               "--contacts", contacts, *options,
               *shlex.split(os.environ.get("DYNGEN_ROBOT_OPTIONS", ""))]
    listed = [{k: np.asarray(x, dtype=np.float64).tolist() for k, x in s.items()}
              for s in states_given]
    out = subprocess.run(command, input=json.dumps(listed), capture_output=True, text=True,
                         check=True).stdout
    return json.loads(out)


def test_constraints_are_named_as_the_runtime_names_them():
    q, v, tau = states(1)
    head = runtime([{"q": q[0], "v": v[0], "tau": tau[0]}])
    assert list(d.constraint_names) == head["constraints"]
    assert d.nc == head["nc"] == sum(rows)


def test_matches_the_runtime_bit_for_bit():
    q, v, tau = states(6)
    results = runtime([{"q": q[s], "v": v[s], "tau": tau[s]} for s in range(len(q))])["results"]
    qdd, lam = d.contact_dynamics(q, v, tau)
    v_plus, impulse = d.impulse_dynamics(q, v)
    assert lam.shape == (len(q), d.nc) and impulse.shape == (len(q), d.nc)
    for s, r in enumerate(results):
        for mine, key in ((qdd, "qdd"), (lam, "lambda"), (v_plus, "v_plus"), (impulse, "impulse")):
            reference = np.asarray(r[key], dtype=np.float64)
            if d.dtype == np.float64:
                assert np.array_equal(mine[s], reference), f"{key} of state {s}"
            else:  # the float module against the double runtime
                scale = max(1.0, np.max(np.abs(reference)))
                assert np.max(np.abs(mine[s] - reference)) <= 2e-3 * scale, f"{key} of state {s}"
    # one state gives the batch's bits
    one = d.contact_dynamics(q[2], v[2], tau[2])
    assert np.array_equal(one[0], qdd[2]) and np.array_equal(one[1], lam[2])


def test_forces_satisfy_the_dynamics_through_the_modules_rnea():
    q, v, tau = states(3, seed=5)
    qdd, lam = d.contact_dynamics(q, v, tau)
    frames = runtime([{"q": q[s], "v": v[s], "tau": tau[s]} for s in range(len(q))],
                     "--frames", ",".join(links))["results"]
    for s in range(len(q)):
        J = np.vstack([np.asarray(frames[s]["frames"][link]["J"])[:r] for link, r in zip(links, rows)])
        residual = d.rnea(q[s], v[s], qdd[s]) - tau[s] - J.T @ lam[s]
        scale = np.linalg.norm(tau[s]) + np.linalg.norm(J.T @ lam[s])
        assert np.linalg.norm(residual) <= (1e-4 if d.dtype == np.float32 else 1e-12) * scale


@pytest.mark.skipif(not hasattr(d, "contact_dynamics_derivatives"),
                    reason="the module has no contact_dynamics_derivatives")
def test_derivatives_match_the_runtime_and_central_differences():
    q, v, tau = states(2, seed=7)
    given = [{"q": q[s], "v": v[s], "tau": tau[s]} for s in range(len(q))]
    results = runtime(given, "--derivatives")["results"]
    mine = d.contact_dynamics_derivatives(q, v, tau)
    keys = ("dqdd_dq", "dqdd_dv", "dqdd_dtau", "dlambda_dq", "dlambda_dv", "dlambda_dtau")
    for s, r in enumerate(results):
        for x, key in zip(mine, keys):
            assert np.array_equal(x[s], np.asarray(r[key]).reshape(x[s].shape)), key
    # fixed base: every column is a plain partial derivative; h = 1e-6 leaves about 1e-8 (a
    # welded arm's qdd does not depend on tau: its entries are rounding, against a scale of 1)
    h = 1e-6
    for k, x in enumerate((q, v, tau)):
        for c in range(d.nv):
            up, down = ([y.copy() for y in (q, v, tau)] for _ in range(2))
            up[k][:, c] += h
            down[k][:, c] -= h
            (qdd_up, lam_up), (qdd_down, lam_down) = d.contact_dynamics(*up), d.contact_dynamics(*down)
            for got, fd in ((mine[k], (qdd_up - qdd_down) / (2 * h)),
                            (mine[3 + k], (lam_up - lam_down) / (2 * h))):
                scale = max(1.0, np.max(np.abs(got)))
                assert np.max(np.abs(got[:, :, c] - fd)) <= 1e-6 * scale, (keys[k], c)

"""The PyTorch functions of a generated package (dyngen --torch, NAME_torch.py) against finite
differences (torch.autograd.gradcheck), the module's own derivatives, the C++ runtime in double
(dyngen eval) and the robot file's joint order.

Run by ctest like test_module.py (tests/python/CMakeLists.txt), with the same environment.
"""
import importlib
import json
import os
import shlex
import subprocess
import xml.etree.ElementTree as ElementTree

import numpy as np
import pytest
import torch

d = importlib.import_module(os.environ["DYNGEN_MODULE"])
T = importlib.import_module(os.environ["DYNGEN_MODULE"].replace("_dynamics", "_torch"))
single = T.dtype == torch.float32
double_only = pytest.mark.skipif(single, reason="gradcheck's finite differences need double")
torch.set_num_threads(1)


def states(n, seed=1, stretch=1.0):
    """n random states q, v, a (or tau), with each quaternion of length stretch."""
    generator = torch.Generator().manual_seed(seed)
    q = T.random_configuration(n, generator=generator)
    for k in d.quaternion_indices:
        q[:, k:k + 4] *= stretch
    v, a = (torch.rand(n, T.nv, generator=generator, dtype=T.dtype) * 6 - 3 for _ in range(2))
    return q, v, a


def present(name):
    return pytest.param(name, marks=pytest.mark.skipif(not hasattr(T, name), reason=f"no {name}"))


INPUTS = {"aba": 3, "rnea": 3, "nle": 2, "crba": 1, "minv": 1, "gravity": 1, "frame_placements": 1}


@double_only
@pytest.mark.parametrize("name", [present(n) for n in INPUTS])
def test_gradients_are_those_of_finite_differences_in_raw_q(name):
    # quaternions of length 1.3: the functions take quat / |quat|, and so do their gradients
    inputs = tuple(x.requires_grad_() for x in states(2, stretch=1.3)[:INPUTS[name]])
    # fast_mode compares the Jacobians along random directions: nv^2 backward calls less
    assert torch.autograd.gradcheck(getattr(T, name), inputs, fast_mode=name in ("crba", "minv"))


@double_only
@pytest.mark.skipif(not hasattr(T, "com"), reason="no com")
def test_com_gradient_and_the_error_for_its_jacobians():
    q = states(2, stretch=1.3)[0].requires_grad_()
    assert torch.autograd.gradcheck(lambda q: T.com(q)[0], (q,))
    with pytest.raises(RuntimeError, match="second derivatives"):
        T.com(q)[1].sum().backward()


def test_values_are_the_modules_bit_for_bit():
    q, v, a = states(5)
    unit = T.normalize(q)  # which rounds each quaternion anew
    assert torch.equal(T.aba(q, v, a), torch.from_numpy(d.aba(unit.numpy(), v.numpy(), a.numpy())))
    assert torch.equal(T.rnea(q, v, a), torch.from_numpy(d.rnea(unit.numpy(), v.numpy(), a.numpy())))
    assert torch.equal(T.crba(q[0]), torch.from_numpy(d.crba(unit[0].numpy())))


def test_bad_inputs_are_refused_by_name():
    q, v, a = states(2)
    with pytest.raises(TypeError, match="tau: dtype"):
        T.aba(q, v, a.to(torch.float16))
    with pytest.raises(ValueError, match=r"v: shape \(2, 1\)"):
        T.aba(q, v[:, :1], a)
    with pytest.raises(TypeError, match="q: a torch.Tensor"):
        T.crba(q.numpy())


@pytest.mark.skipif(not hasattr(d, "regressor"), reason="generated without the regressor")
def test_rnea_with_parameters():
    q, v, a = states(4)
    P = torch.from_numpy(d.inertial_parameters.copy())
    reference = T.rnea(q, v, a)
    bound = (2e-3 if single else 1e-12) * reference.abs().max()
    assert (T.rnea(q, v, a, params=P) - reference).abs().max() <= bound
    if not single:
        assert torch.autograd.gradcheck(lambda P: T.rnea(q, v, a, params=P), (P.requires_grad_(),))
    with pytest.raises(RuntimeError, match="regressor's derivatives"):
        T.rnea(q.requires_grad_(), v, a, params=P).sum().backward()


def test_integrate_moves_q_along_the_derivatives_tangent_directions():
    # central differences of rnea along integrate(q, h e_k), against the runtime's tangent columns
    q, v, a = (x[0].double() for x in states(1, seed=3))
    h = 1e-3 if single else 1e-5
    reference = d.rnea_derivatives(*(x.to(T.dtype).numpy() for x in (q, v, a)))[0]
    columns = []
    for k in range(T.nv):
        e = torch.zeros(T.nv, dtype=torch.float64)
        e[k] = h
        up, down = (T.rnea(T.integrate(q, s * e).to(T.dtype), v.to(T.dtype), a.to(T.dtype))
                    for s in (1, -1))
        columns.append((up.double() - down.double()) / (2 * h))
    error = (torch.stack(columns, -1) - torch.from_numpy(reference).double()).abs().max()
    assert error <= (1e-2 if single else 1e-6) * np.abs(reference).max()


def test_difference_inverts_integrate():
    q0 = states(6, seed=4)[0].double()
    q1 = states(6, seed=5)[0].double()
    q2 = T.integrate(q0, T.difference(q0, q1))
    for k in d.quaternion_indices:  # q and -q are the same rotation
        q2[:, k:k + 4] *= torch.sign((q2[:, k:k + 4] * q1[:, k:k + 4]).sum(-1, keepdim=True))
    assert (q2 - q1).abs().max() <= 1e-12
    v = torch.rand(6, T.nv, dtype=torch.float64) - 0.5  # rotations well under pi
    assert (T.difference(q0, T.integrate(q0, v)) - v).abs().max() <= 1e-12
    assert torch.equal(T.integrate(q0, v, dt=0.5), T.integrate(q0, 0.5 * v))
    # NumPy arrays in, NumPy arrays out
    mine = T.difference(q0.numpy(), q1.numpy())
    assert isinstance(mine, np.ndarray) and np.array_equal(mine, T.difference(q0, q1).numpy())


@double_only
@pytest.mark.skipif(not hasattr(d, "integrate"), reason="the module has no generated integrate")
def test_generated_integrate_and_difference_are_these():
    # the module's generated functions (dyngen_lie.h's coefficients, series near 0) against this
    # file's (PyTorch's sin, cos and atan2), at every angle from the series to near pi
    q0, v, _ = states(8, seed=8)
    q1 = states(8, seed=9)[0]
    v[:4] *= torch.logspace(-8, 0, 4, dtype=T.dtype)[:, None]
    assert np.abs(d.integrate(q0.numpy(), v.numpy()) - T.integrate(q0, v).numpy()).max() <= 1e-13
    mine = d.difference(q0.numpy(), q1.numpy())
    assert np.abs(mine - T.difference(q0, q1).numpy()).max() <= 1e-12


def test_integrate_and_difference_are_differentiable():
    q0, v, _ = (x.double().requires_grad_() for x in states(2, seed=6))
    q1 = states(2, seed=7)[0].double().requires_grad_()
    assert torch.autograd.gradcheck(T.integrate, (q0, v))
    assert torch.autograd.gradcheck(T.difference, (q0, q1))
    # at the small angles' series too
    assert torch.autograd.gradcheck(T.integrate, (q0, (1e-6 * v).detach().requires_grad_()))


def test_random_configurations_and_neutral():
    q = T.random_configuration(1000, generator=torch.Generator().manual_seed(8))
    assert q.shape == (1000, T.nq) and q.dtype == T.dtype
    for k in d.quaternion_indices:
        assert (torch.linalg.norm(q[:, k:k + 4], dim=-1) - 1).abs().max() <= 1e-6
    assert torch.equal(T.normalize(q), q) or (T.normalize(q) - q).abs().max() <= 1e-6
    zero = T.neutral()
    assert torch.equal(T.integrate(zero, torch.zeros(T.nv, dtype=T.dtype)), zero)
    assert torch.equal(T.difference(zero, zero), torch.zeros(T.nv, dtype=T.dtype))
    bounded = T.random_configuration(50, lower=-0.1 * torch.ones(T.nq), upper=0.1 * torch.ones(T.nq))
    scalar = [k for k in range(T.nq) if not any(j <= k < j + 4 for j in d.quaternion_indices)]
    assert bounded[:, scalar].abs().max() <= 0.1


def urdf_joint_order(path):
    """The movable joints of a URDF in the order of Pinocchio's reader, computed here from the
    file: depth first from the root link, each link's child joints sorted by name."""
    root = ElementTree.parse(path).getroot()
    children, has_parent = {}, set()
    for joint in root.findall("joint"):  # not <transmission>'s
        parent, child = joint.find("parent").get("link"), joint.find("child").get("link")
        children.setdefault(parent, []).append(joint)
        has_parent.add(child)
    order = []

    def visit(link):
        for joint in sorted(children.get(link, []), key=lambda j: j.get("name").encode()):
            if joint.get("type") != "fixed" and joint.find("mimic") is None:
                order.append(joint.get("name"))
            visit(joint.find("child").get("link"))

    for link in root.findall("link"):
        if link.get("name") not in has_parent:
            visit(link.get("name"))
    return order


def test_pinocchio_order():
    q = states(3, seed=9)[0]
    assert torch.equal(T.from_pinocchio(T.to_pinocchio(q)), q)
    pin = T.to_pinocchio(q)
    for k in d.quaternion_indices:  # a quaternion's 4 entries, w last, where its joint lands
        at = int(torch.nonzero(T._PINOCCHIO_Q == k)[0])
        assert torch.equal(pin[:, at - 3:at + 1], q[:, [k + 1, k + 2, k + 3, k]])
    names = [d.joint_names[k] for k in T.to_pinocchio_v(torch.arange(T.nv)).tolist()]
    v = torch.arange(T.nv, dtype=T.dtype)
    assert torch.equal(T.from_pinocchio_v(T.to_pinocchio_v(v)), v)
    robot = os.environ["DYNGEN_ROBOT"]
    if robot.endswith(".urdf") and "hostile" not in robot:  # whose names ElementTree refuses
        order = urdf_joint_order(robot)
        assert [n for n in names if n in set(order)] == order


def runtime_derivatives(q, v, tau):
    """dqdd_dq, dqdd_dv and Minv from dyngen eval (the C++ runtime, in double)."""
    listed = [{"q": q[s].tolist(), "v": v[s].tolist(), "tau": tau[s].tolist()} for s in range(len(q))]
    command = [os.environ["DYNGEN"], "eval", os.environ["DYNGEN_ROBOT"], "--states", "-",
               "--derivatives", *shlex.split(os.environ.get("DYNGEN_ROBOT_OPTIONS", ""))]
    out = subprocess.run(command, input=json.dumps(listed), capture_output=True, text=True,
                         check=True).stdout
    results = json.loads(out)["results"]
    return (torch.tensor([r[key] for r in results], dtype=torch.float64)
            for key in ("dqdd_dq", "dqdd_dv", "Minv"))


def test_gradients_against_the_runtime_in_double():
    # in float, within float's digits of the double runtime; in double, to its rounding
    q, v, tau = states(4, seed=10)
    w = torch.rand(4, T.nv, dtype=T.dtype)
    inputs = tuple(x.clone().requires_grad_() for x in (q, v, tau))
    T.aba(*inputs).backward(w)
    dqdd_dq, dqdd_dv, Minv = runtime_derivatives(*(x.double() for x in (q, v, tau)))
    wd = w.double()
    expected = (T._coordinate_gradient(q.double(), torch.einsum("nij,ni->nj", dqdd_dq, wd)),
                torch.einsum("nij,ni->nj", dqdd_dv, wd), torch.einsum("nij,ni->nj", Minv, wd))
    for x, reference, what in zip(inputs, expected, ("q", "v", "tau")):
        error = (x.grad.double() - reference).abs().max()
        assert error <= (2e-3 if single else 1e-9) * reference.abs().max(), what

"""Plain-PyTorch batched Articulated-Body Algorithm: the benchmark peer for dyngen.

This is the forward dynamics a machine-learning user writes by hand when they do
not use dyngen: Featherstone's ABA (RBDA ch. 7) as batched tensor operations over
a leading state dimension, with autograd providing the backward.  The benchmark
times it against dyngen's generated code, so it aims to be what a competent user
writes: per-body constants precomputed as tensors, a Python loop over links (never
over states), 6x6 spatial algebra with batched matmuls.

Conventions (they match `dyngen eval`):
  * Spatial vectors are ordered (linear, angular), like Pinocchio and dyngen's
    floating-base v, so no permutation is needed anywhere.
  * Bodies: one per moving joint (revolute, continuous, prismatic); the children
    of fixed joints are merged into their parent body (with the fixed joint's
    origin), and so are links without <inertial> (zero mass).
  * q/v order: the moving joints in the order a depth-first traversal from the
    root link meets them, each link's child joints taken in URDF file order.
  * Fixed base: the root link is the world frame.  Floating base: a free joint at
    the root link, q = (p_world, quat w,x,y,z) (base->world rotation; it is used
    as given, not normalised), v = (linear velocity of the base origin, angular
    velocity), both in base coordinates; qdd of the base = the time derivative of
    that body-frame twist (the spatial acceleration in base coordinates).
  * Gravity is given in world coordinates.

Usage:  python3 bench/torch_peer.py --check [--dyngen PATH]   (compare with dyngen)
        python3 bench/torch_peer.py --bench [--n 4096]        (quick timing)
"""
import argparse
import json
import os
import subprocess
import sys
import time
import xml.etree.ElementTree as ET

import numpy as np
import torch

# ---------------------------------------------------------------- model setup (numpy, float64)


def _skew(p):
    return np.array([[0.0, -p[2], p[1]], [p[2], 0.0, -p[0]], [-p[1], p[0], 0.0]])


def _rpy(rpy):
    """URDF fixed-axis roll-pitch-yaw: R = Rz(yaw) Ry(pitch) Rx(roll)."""
    (cr, cp, cy), (sr, sp, sy) = np.cos(rpy), np.sin(rpy)
    rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    return rz @ ry @ rx


def _xform(R, p):
    """Motion transform parent -> child coordinates, child frame at (R, p) in the parent."""
    E = R.T
    X = np.zeros((6, 6))
    X[:3, :3] = E
    X[:3, 3:] = -E @ _skew(p)
    X[3:, 3:] = E
    return X


def _spatial_inertia(m, c, Ic):
    """6x6 inertia at the frame origin, (linear, angular) order; c = com, Ic about the com."""
    C = _skew(c)
    return np.block([[m * np.eye(3), -m * C], [m * C, Ic + m * C @ C.T]])


def _vec(el, attr, default):
    if el is None or el.get(attr) is None:
        return np.array(default, dtype=float)
    return np.array([float(x) for x in el.get(attr).split()])


def _origin(el):
    o = el.find("origin") if el is not None else None
    return _rpy(_vec(o, "rpy", [0, 0, 0])), _vec(o, "xyz", [0, 0, 0])


def _link_inertia(link):
    """Spatial inertia of a URDF link in its own frame (zero if it has no <inertial>)."""
    inertial = link.find("inertial")
    if inertial is None:
        return np.zeros((6, 6))
    R, c = _origin(inertial)
    m = float(inertial.find("mass").get("value"))
    i = {k: float(inertial.find("inertia").get(k, 0.0))
         for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")}
    Ic = np.array([[i["ixx"], i["ixy"], i["ixz"]],
                   [i["ixy"], i["iyy"], i["iyz"]],
                   [i["ixz"], i["iyz"], i["izz"]]])
    return _spatial_inertia(m, c, R @ Ic @ R.T)


def parse_urdf(path):
    """Bodies in depth-first order: dicts with name, parent (-1: root), kind, axis, X_tree, I.

    Also returns the root body's inertia (the root link plus everything fixed to it)."""
    robot = ET.parse(path).getroot()
    links = {l.get("name"): l for l in robot.findall("link")}
    children = {name: [] for name in links}
    child_links = set()
    for j in robot.findall("joint"):
        if j.find("mimic") is not None:
            raise ValueError(f"mimic joint {j.get('name')} not supported")
        children[j.find("parent").get("link")].append(j)
        child_links.add(j.find("child").get("link"))
    roots = [name for name in links if name not in child_links]
    if len(roots) != 1:
        raise ValueError(f"expected one root link, found {roots}")
    bodies, inertia = [], {-1: _link_inertia(links[roots[0]])}

    def visit(link_name, body, R_lb, p_lb):  # (R_lb, p_lb): link frame in the body frame
        for j in children[link_name]:
            R_o, p_o = _origin(j)
            R, p = R_lb @ R_o, R_lb @ p_o + p_lb  # joint frame in the body frame
            child, kind = j.find("child").get("link"), j.get("type")
            if kind == "fixed":
                X = _xform(R, p)
                inertia[body] = inertia[body] + X.T @ _link_inertia(links[child]) @ X
                visit(child, body, R, p)
            elif kind in ("revolute", "continuous", "prismatic"):
                axis = _vec(j.find("axis"), "xyz", [1, 0, 0])
                axis = axis / np.linalg.norm(axis)
                bodies.append(dict(name=j.get("name"), parent=body, axis=axis,
                                   kind="prismatic" if kind == "prismatic" else "revolute",
                                   X_tree=_xform(R, p)))
                k = len(bodies) - 1
                inertia[k] = _link_inertia(links[child])
                visit(child, k, np.eye(3), np.zeros(3))
            else:
                raise ValueError(f"joint type {kind} ({j.get('name')}) not supported")

    visit(roots[0], -1, np.eye(3), np.zeros(3))
    for k, b in enumerate(bodies):
        b["I"] = inertia[k]
    return bodies, inertia[-1]


# ---------------------------------------------------------------- spatial algebra (torch, batched)


def crm(m, x):
    """Motion cross product m x x, (linear, angular) order, batched over the first dim."""
    v, w = m[..., :3], m[..., 3:]
    xv, xw = x[..., :3], x[..., 3:]
    cross = torch.linalg.cross
    return torch.cat([cross(w, xv) + cross(v, xw), cross(w, xw)], dim=-1)


def crf(m, f):
    """Force cross product m x* f."""
    v, w = m[..., :3], m[..., 3:]
    fl, fa = f[..., :3], f[..., 3:]
    cross = torch.linalg.cross
    return torch.cat([cross(w, fl), cross(w, fa) + cross(v, fl)], dim=-1)


def mv(X, x):
    """(N,6,6) @ (N,6) -> (N,6)."""
    return torch.matmul(X, x.unsqueeze(-1)).squeeze(-1)


def quat_to_rot(quat):
    """(N,4) unit quaternions w,x,y,z -> (N,3,3) rotation matrices."""
    w, x, y, z = quat.unbind(-1)
    return torch.stack([
        1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),
        2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
        2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y),
    ], dim=-1).view(-1, 3, 3)


# ---------------------------------------------------------------- the peer


class PlainTorchABA:
    """Batched ABA over (N, nq) / (N, nv) tensors, differentiable by autograd."""

    def __init__(self, urdf_path, floating_base=False, dtype=torch.float64,
                 gravity=(0.0, 0.0, -9.81)):
        bodies, root_I = parse_urdf(urdf_path)
        t = lambda a: torch.tensor(np.asarray(a), dtype=dtype)
        self.floating_base = floating_base
        self.joint_names = [b["name"] for b in bodies]
        self.parent = [b["parent"] for b in bodies]
        self.prismatic = [b["kind"] == "prismatic" for b in bodies]
        self.I = [t(b["I"]) for b in bodies]
        self.root_I = t(root_I)
        self.gravity = t(gravity)
        self.eye3 = torch.eye(3, dtype=dtype)
        self.S, self.X_tree, self.K = [], [], []
        for b in bodies:
            a, Xt = b["axis"], b["X_tree"]
            K = _skew(a)
            if b["kind"] == "prismatic":
                # X_up = [[I, -q[a]x], [0, I]] X_tree = X_tree + q * [[-[a]x X_bottom], [0]]
                self.S.append(t(np.r_[a, 0, 0, 0]))
                self.K.append(t(np.vstack([-K @ Xt[3:], np.zeros((3, 6))])))
                self.X_tree.append(t(Xt))
            else:
                # X_up = blockdiag(R_J^T, R_J^T) X_tree, R_J = I + s K + (1-c) K^2
                self.S.append(t(np.r_[0, 0, 0, a]))
                self.K.append((t(K), t(K @ K)))
                # both 3x6 row blocks side by side, so R_J^T multiplies them in one matmul
                self.X_tree.append(t(np.hstack([Xt[:3], Xt[3:]])))
        n = len(bodies)
        self.nq, self.nv = (n + 7, n + 6) if floating_base else (n, n)

    def _joint_xform(self, i, qi):
        """X_up of body i (parent -> body coordinates) at joint positions qi (N,)."""
        if self.prismatic[i]:
            return self.X_tree[i] + qi[:, None, None] * self.K[i]
        K, K2 = self.K[i]
        s, c = torch.sin(qi)[:, None, None], torch.cos(qi)[:, None, None]
        RT = self.eye3 - s * K + (1 - c) * K2  # R_J^T
        X = torch.matmul(RT, self.X_tree[i])  # (N,3,12): [R_J^T X_top | R_J^T X_bottom]
        return X.view(-1, 3, 2, 6).transpose(1, 2).reshape(-1, 6, 6)

    def aba(self, q, v, tau):
        """Forward dynamics: q (N,nq), v (N,nv), tau (N,nv) -> qdd (N,nv)."""
        N = q.shape[0]
        if self.floating_base:
            g_base = torch.matmul(self.gravity, quat_to_rot(q[:, 3:7]))  # R^T g, (N,3)
            a_grav = torch.cat([-g_base, torch.zeros_like(g_base)], dim=-1)
            base = (v[:, :6], tau[:, :6])
            q, v, tau = q[:, 7:], v[:, 6:], tau[:, 6:]
        else:  # gravity as a fictitious upward acceleration of the fixed root
            a_grav = torch.cat([-self.gravity, torch.zeros_like(self.gravity)]).expand(N, 6)
            base = None
        Xup, c, pA = self._velocities(q, v, base)
        IA_root, pA_root, U, D, u = self._articulated(tau, base, Xup, c, pA)
        if base is None:
            return self._accelerations(a_grav, Xup, c, U, D, u)
        # Free root: IA a + pA = tau, a = a_grav + qdd_base (a_grav: gravity in base frame).
        a_base = torch.linalg.solve(IA_root, (base[1] - pA_root).unsqueeze(-1)).squeeze(-1)
        qdd = self._accelerations(a_base, Xup, c, U, D, u)
        return torch.cat([a_base - a_grav, qdd], dim=-1)

    def _velocities(self, q, v, base):
        """Pass 1 (root to leaves): transforms X_up, velocities, bias accelerations c, bias forces."""
        Xup, vel, c, pA = [], [], [], []
        for i, p in enumerate(self.parent):
            X = self._joint_xform(i, q[:, i])
            vJ = self.S[i] * v[:, i:i + 1]
            if p < 0 and base is None:  # child of the fixed root: v = vJ, c = vJ x vJ = 0
                vi, ci = vJ, torch.zeros_like(vJ)
            else:
                vi = mv(X, base[0] if p < 0 else vel[p]) + vJ
                ci = crm(vi, vJ)
            Xup.append(X)
            vel.append(vi)
            c.append(ci)
            pA.append(crf(vi, vi @ self.I[i].T))
        return Xup, c, pA

    def _articulated(self, tau, base, Xup, c, pA):
        """Pass 2 (leaves to root): articulated inertias IA, bias forces pA, and U, D, u."""
        n, N = len(self.parent), tau.shape[0]
        IA = [I.expand(N, 6, 6) for I in self.I]
        pA = list(pA)
        IA_root = pA_root = None
        if base is not None:
            IA_root = self.root_I.expand(N, 6, 6)
            pA_root = crf(base[0], base[0] @ self.root_I.T)
        U, D, u = [None] * n, [None] * n, [None] * n
        for i in reversed(range(n)):
            U[i] = IA[i] @ self.S[i]
            D[i] = U[i] @ self.S[i]
            u[i] = tau[:, i] - pA[i] @ self.S[i]
            p = self.parent[i]
            if p < 0 and base is None:
                continue
            Uinv = U[i] / D[i][:, None]
            Ia = IA[i] - Uinv.unsqueeze(-1) * U[i].unsqueeze(-2)
            pa = pA[i] + mv(Ia, c[i]) + Uinv * u[i][:, None]
            XT = Xup[i].transpose(-1, -2)
            dI, dp = torch.matmul(XT, torch.matmul(Ia, Xup[i])), mv(XT, pa)
            if p < 0:
                IA_root, pA_root = IA_root + dI, pA_root + dp
            else:
                IA[p], pA[p] = IA[p] + dI, pA[p] + dp
        return IA_root, pA_root, U, D, u

    def _accelerations(self, a_root, Xup, c, U, D, u):
        """Pass 3 (root to leaves): joint accelerations, given the root's (biased) acceleration."""
        qdd, acc = [], []
        for i, p in enumerate(self.parent):
            ai = mv(Xup[i], a_root if p < 0 else acc[p]) + c[i]
            qdd.append((u[i] - (U[i] * ai).sum(-1)) / D[i])
            acc.append(ai + self.S[i] * qdd[i][:, None])
        return torch.stack(qdd, dim=-1)


# ---------------------------------------------------------------- self-check and quick timing

HERE = os.path.dirname(os.path.abspath(__file__))
MODELS = os.path.join(HERE, "..", "tests", "models")
ROBOTS = [("ur5.urdf", False), ("solo12.urdf", True)]


def random_states(model, n, seed):
    """q in [-3,3] (quaternion normalised), v and tau in [-3,3], float64 numpy."""
    rng = np.random.default_rng(seed)
    q = rng.uniform(-3, 3, (n, model.nq))
    if model.floating_base:
        q[:, 3:7] /= np.linalg.norm(q[:, 3:7], axis=1, keepdims=True)
    return q, rng.uniform(-3, 3, (n, model.nv)), rng.uniform(-3, 3, (n, model.nv))


def dyngen_eval(dyngen, urdf, floating_base, q, v, tau):
    states = [dict(q=a.tolist(), v=b.tolist(), tau=c.tolist()) for a, b, c in zip(q, v, tau)]
    cmd = [dyngen, "eval", urdf, "--derivatives", "--states", "-"]
    if floating_base:
        cmd.insert(3, "--floating-base")
    out = subprocess.run(cmd, input=json.dumps(states), capture_output=True, text=True, check=True)
    return json.loads(out.stdout)


def rel_err(a, b):
    return float(np.max(np.abs(a - b)) / max(np.max(np.abs(b)), 1e-300))


def check_robot(dyngen, urdf, floating_base, n=10, tol=1e-10):
    model = PlainTorchABA(urdf, floating_base=floating_base)
    q, v, tau = random_states(model, n, seed=1)
    ref = dyngen_eval(dyngen, urdf, floating_base, q, v, tau)
    names = [j for j in ref["joints"] if not j.startswith("floating_base:")]
    assert names == model.joint_names, (names, model.joint_names)
    assert (ref["nq"], ref["nv"]) == (model.nq, model.nv)
    qdd_ref = np.array([r["qdd"] for r in ref["results"]])
    qt, vt, tt = (torch.tensor(a, requires_grad=True) for a in (q, v, tau))
    qdd = model.aba(qt, vt, tt)
    err = max(rel_err(qdd[k].detach().numpy(), qdd_ref[k]) for k in range(n))
    # Autograd: the backward runs, and its Jacobians match dyngen's analytic derivatives
    # (d/dv fully; d/dq on the joint coordinates, whose tangent is the coordinate itself).
    gq, gv, gt = torch.autograd.grad(qdd.sum(), (qt, vt, tt))
    assert all(torch.isfinite(g).all() for g in (gq, gv, gt))
    k0 = 7 if floating_base else 0
    jac_err = 0.0
    for k in range(3):
        f = lambda qq, vv: model.aba(qq[None], vv[None], tt[k:k + 1].detach())[0]
        Jq, Jv = torch.autograd.functional.jacobian(f, (qt[k].detach(), vt[k].detach()))
        r = ref["results"][k]
        jac_err = max(jac_err, rel_err(Jv.numpy(), np.array(r["dqdd_dv"])),
                      rel_err(Jq[:, k0:].numpy(), np.array(r["dqdd_dq"])[:, k0 - (k0 > 0):]))
    # float32 runs and roughly agrees.
    m32 = PlainTorchABA(urdf, floating_base=floating_base, dtype=torch.float32)
    q32 = m32.aba(*(torch.tensor(a, dtype=torch.float32) for a in (q, v, tau))).numpy()
    err32 = max(rel_err(q32[k], qdd_ref[k]) for k in range(n))
    ok = err < tol and jac_err < 1e-8 and err32 < 1e-3
    print(f"{os.path.basename(urdf):14s} floating={floating_base!s:5s} nq={model.nq} nv={model.nv} "
          f"qdd max rel err {err:.2e}  jacobian {jac_err:.2e}  float32 {err32:.2e}  "
          f"{'OK' if ok else 'FAIL'}")
    return ok


def bench(urdf, floating_base, n, dtype=torch.float64, reps=20):
    """Median seconds per call of aba forward and forward+backward at n states."""
    model = PlainTorchABA(urdf, floating_base=floating_base, dtype=dtype)
    q, v, tau = (torch.tensor(a, dtype=dtype) for a in random_states(model, n, seed=2))

    def fwd():
        with torch.no_grad():
            model.aba(q, v, tau)

    def fwd_bwd():
        qq, vv, tt = (a.clone().requires_grad_() for a in (q, v, tau))
        torch.autograd.grad(model.aba(qq, vv, tt).sum(), (qq, vv, tt))

    out = {}
    for name, fn in (("forward", fwd), ("forward+backward", fwd_bwd)):
        fn()  # warm-up
        times = []
        for _ in range(reps):
            t0 = time.perf_counter()
            fn()
            times.append(time.perf_counter() - t0)
        out[name] = float(np.median(times))
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--check", action="store_true", help="compare with dyngen eval")
    ap.add_argument("--bench", action="store_true", help="time ur5 aba at --n states")
    ap.add_argument("--dyngen", default="/work/main/build/dyngen")
    ap.add_argument("--n", type=int, default=4096)
    args = ap.parse_args(argv)
    ok = True
    if args.check or not args.bench:
        ok = all([check_robot(args.dyngen, os.path.join(MODELS, r), fb) for r, fb in ROBOTS])
    if args.bench:
        t = bench(os.path.join(MODELS, "ur5.urdf"), False, args.n)
        print(f"ur5 float64 N={args.n} threads={torch.get_num_threads()}: "
              + ", ".join(f"{k} {v * 1e3:.2f} ms" for k, v in t.items()))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())

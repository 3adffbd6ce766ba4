"""System identification with dyngen's PyTorch functions: an unknown payload on ur5's last link,
recovered from simulated trajectories by least squares on the inertial-parameter regressor Y and
by gradient descent through rnea(q, v, a, params=P).

The "measured" torques come from dyngen eval (the C++ runtime) on ur5.urdf with the payload
added as a link on a fixed joint, which dyngen merges into the last body: nothing of the
identification computes them. The trajectories are sums of sines, with v and a from their
derivatives. The payload's ten standard parameters about wrist_3_link's origin are those of
inertial_parameters' last row less the model's; on noiseless data both methods must recover them
to 1e-6 relative (exit status 1 otherwise), and the errors with noise on tau are reported.

    build/dyngen examples/ur5.urdf -o gen --torch
    cmake -S gen -B gen/build -DUR5_BUILD_CHECK=OFF && cmake --build gen/build
    PYTHONPATH=gen/build python3 examples/torch/system_identification.py ur5 \
        --urdf examples/ur5.urdf --dyngen build/dyngen
"""
import argparse
import importlib
import json
import os
import subprocess
import sys
import tempfile

import numpy as np
import torch

# the payload, in wrist_3_link's frame: a fixed joint at JOINT_XYZ, its centre of mass at
# COM_XYZ in its own frame, and its inertia about the centre of mass (kg m^2)
MASS, JOINT_XYZ, COM_XYZ = 1.7, np.array([0.0, 0.09, 0.0]), np.array([0.02, 0.04, -0.015])
INERTIA = np.array([[0.0061, 0.0004, -0.0002], [0.0004, 0.0043, 0.0003], [-0.0002, 0.0003, 0.0052]])


def payload_parameters():
    """The payload's standard parameters about wrist_3_link's origin, in Pinocchio's order: m,
    m c, then the inertia about the origin (parallel axes) Ixx, Ixy, Iyy, Ixz, Iyz, Izz."""
    c = JOINT_XYZ + COM_XYZ
    I = INERTIA + MASS * (c @ c * np.eye(3) - np.outer(c, c))
    return np.array([MASS, *(MASS * c), I[0, 0], I[0, 1], I[1, 1], I[0, 2], I[1, 2], I[2, 2]])


def urdf_with_payload(urdf):
    """ur5.urdf's text with the payload on wrist_3_link."""
    with open(urdf) as f:
        text = f.read()
    I = INERTIA
    payload = f"""
  <joint name="payload_joint" type="fixed">
    <parent link="wrist_3_link"/><child link="payload"/>
    <origin xyz="{' '.join(map(repr, JOINT_XYZ))}" rpy="0 0 0"/>
  </joint>
  <link name="payload">
    <inertial>
      <mass value="{MASS!r}"/><origin xyz="{' '.join(map(repr, COM_XYZ))}" rpy="0 0 0"/>
      <inertia ixx="{I[0, 0]!r}" ixy="{I[0, 1]!r}" ixz="{I[0, 2]!r}"
               iyy="{I[1, 1]!r}" iyz="{I[1, 2]!r}" izz="{I[2, 2]!r}"/>
    </inertial>
  </link>
</robot>"""
    return text[:text.rindex("</robot>")] + payload


def trajectories(nv, count, samples, seed=7):
    """count trajectories of sums of three sines per joint over 4 s: q, v, a (count * samples, nv)."""
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 4.0, samples)[:, None, None]
    amplitude = rng.uniform(0.2, 0.8, (count, nv, 3)) / 3
    omega = rng.uniform(0.5, 3.0, (count, nv, 3))
    phase = rng.uniform(0, 2 * np.pi, (count, nv, 3))
    angle = omega * t[..., None] + phase  # (samples, count, nv, 3)
    q = (amplitude * np.sin(angle)).sum(-1)
    v = (amplitude * omega * np.cos(angle)).sum(-1)
    a = -(amplitude * omega ** 2 * np.sin(angle)).sum(-1)
    return tuple(x.reshape(-1, nv) for x in (q, v, a))


def measured_torques(dyngen, urdf, q, v, a):
    """tau of the robot with the payload, from dyngen eval (the runtime)."""
    with tempfile.TemporaryDirectory() as scratch:
        robot = os.path.join(scratch, "ur5_payload.urdf")
        with open(robot, "w") as f:
            f.write(urdf_with_payload(urdf))
        listed = [{"q": q[s].tolist(), "v": v[s].tolist(), "a": a[s].tolist()} for s in range(len(q))]
        out = subprocess.run([dyngen, "eval", robot, "--states", "-"], input=json.dumps(listed),
                             capture_output=True, text=True, check=True).stdout
    return np.array([r["tau"] for r in json.loads(out)["results"]])


def least_squares(d, q, v, a, tau):
    """The last body's parameters by least squares on Y's last ten columns, the others known."""
    Y = d.regressor(q, v, a)  # (N, nv, 10 nbodies)
    known = d.inertial_parameters.reshape(-1).copy()
    known[-10:] = 0
    b = tau - Y @ known - np.asarray(d.armature) * a
    return np.linalg.lstsq(Y[:, :, -10:].reshape(-1, 10), b.reshape(-1), rcond=None)[0]


def gradient_descent(t, d, q, v, a, tau, iterations=60):
    """The last body's parameters by L-BFGS on the squared torque error of rnea(params=P), from
    the model's own."""
    q, v, a, tau = (torch.from_numpy(x) for x in (q, v, a, tau))
    model = torch.from_numpy(d.inertial_parameters.copy())
    last = model[-1].clone().requires_grad_()
    optimiser = torch.optim.LBFGS([last], max_iter=iterations, tolerance_grad=1e-14,
                                  tolerance_change=1e-16, line_search_fn="strong_wolfe")

    def loss():
        optimiser.zero_grad()
        P = torch.cat([model[:-1], last[None]])
        value = ((t.rnea(q, v, a, params=P) - tau) ** 2).mean()
        value.backward()
        return value

    optimiser.step(loss)
    return last.detach().numpy()


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("name", help="the package's name: NAME_torch and NAME_dynamics are imported")
    parser.add_argument("--urdf", required=True,
                        help="ur5.urdf, the robot the package was generated for")
    parser.add_argument("--dyngen", default="dyngen", help="the dyngen executable (for dyngen eval)")
    parser.add_argument("--noise", type=float, default=0.01, help="noise on tau, relative to its RMS")
    args = parser.parse_args()
    d = importlib.import_module(f"{args.name}_dynamics")
    t = importlib.import_module(f"{args.name}_torch")
    torch.set_num_threads(1)
    q, v, a = trajectories(d.nv, count=8, samples=100)
    tau = measured_torques(args.dyngen, args.urdf, q, v, a)
    truth = payload_parameters()
    model = d.inertial_parameters[-1]
    print(f"payload on {d.body_names[-1]}: m = {truth[0]} kg, m c = {truth[1:4]}, 800 states")
    rng = np.random.default_rng(11)
    noisy = tau + args.noise * np.sqrt((tau ** 2).mean()) * rng.standard_normal(tau.shape)
    failed = False
    for method in ("least squares", "gradient descent"):
        for data, label in ((tau, "noiseless"), (noisy, f"{args.noise:g} noise")):
            found = (least_squares(d, q, v, a, data) if method == "least squares"
                     else gradient_descent(t, d, q, v, a, data)) - model
            error = np.linalg.norm(found - truth) / np.linalg.norm(truth)
            print(f"{method:>16}, {label:>10}: relative error {error:.2e}, mass {found[0]:.6f} kg")
            failed |= label == "noiseless" and not error <= 1e-6
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()

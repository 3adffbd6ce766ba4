"""Trajectory optimisation by gradient with dyngen's PyTorch functions: ur5, from rest, brings its
last frame (tool0) to a target and stops there, in one second.

The controls are joint torques u_k on top of gravity compensation, tau_k = gravity(q_k) + u_k,
held over each of 40 steps of a fourth-order Runge-Kutta rollout of aba. The loss is the squared
distance of the frame from the target at the end, plus its final velocity and a small cost on u;
L-BFGS minimises it with the gradient that autograd takes through the whole rollout: the
backward of aba, gravity and frame_placements, each the generated derivatives. The loss must
fall at least 100 times (exit status 1 otherwise); the plot shows it and the frame's path.

    build/dyngen examples/ur5.urdf -o gen --torch
    cmake -S gen -B gen/build -DUR5_BUILD_CHECK=OFF && cmake --build gen/build
    PYTHONPATH=gen/build python3 examples/torch/trajectory_optimisation.py ur5 --plot reach.png
"""
import argparse
import importlib
import sys

import torch

STEPS, DT = 40, 0.025


def rollout(t, q, u):
    """States q_0 ... q_K and the final velocity of the RK4 rollout from rest at q under torques
    gravity(q_k) + u_k."""
    v = torch.zeros_like(u[0])
    path = [q]
    for k in range(STEPS):
        tau = t.gravity(q) + u[k]

        def f(q, v):
            return v, t.aba(q, v, tau)

        k1 = f(q, v)
        k2 = f(q + DT / 2 * k1[0], v + DT / 2 * k1[1])
        k3 = f(q + DT / 2 * k2[0], v + DT / 2 * k2[1])
        k4 = f(q + DT * k3[0], v + DT * k3[1])
        q = q + DT / 6 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0])
        v = v + DT / 6 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1])
        path.append(q)
    return torch.stack(path), v


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("name", help="the package's name: NAME_torch is imported (a fixed base)")
    parser.add_argument("--iterations", type=int, default=60)
    parser.add_argument("--plot", help="write the loss and the frame's path to this PNG")
    args = parser.parse_args()
    t = importlib.import_module(f"{args.name}_torch")
    torch.set_num_threads(1)
    frame = -1  # the last frame of the package's (tool0 on ur5)

    def position(q):
        return t.frame_placements(q)[1][..., frame, :]

    start = torch.tensor([0.0, -1.2, 1.4, -0.2, 1.5, 0.0], dtype=t.dtype)[:t.nv]
    target = position(torch.tensor([0.8, -0.7, 0.9, -0.6, 1.2, 0.3], dtype=t.dtype)[:t.nv])
    u = torch.zeros(STEPS, t.nv, dtype=t.dtype, requires_grad=True)
    optimiser = torch.optim.LBFGS([u], max_iter=args.iterations, line_search_fn="strong_wolfe")
    losses = []

    def loss():
        optimiser.zero_grad()
        path, v = rollout(t, start, u)
        value = (((position(path[-1]) - target) ** 2).sum() + 0.01 * (v ** 2).sum()
                 + 1e-7 * (u ** 2).sum())
        value.backward()
        losses.append(value.item())
        return value

    optimiser.step(loss)
    with torch.no_grad():
        path, v = rollout(t, start, u)
        miss = torch.linalg.norm(position(path[-1]) - target).item()
    fall = losses[0] / min(losses)
    print(f"loss {losses[0]:.3e} -> {min(losses):.3e} ({fall:.3g} times less) in {len(losses)} "
          f"rollouts; the frame ends {miss * 1e3:.3f} mm from the target, at "
          f"{torch.linalg.norm(v).item():.2e} rad/s")
    if args.plot:
        plot(args.plot, losses, position(path).detach(), target)
    sys.exit(0 if fall >= 100 else 1)


def plot(file, losses, positions, target):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    figure, (left, right) = plt.subplots(1, 2, figsize=(10, 4))
    left.semilogy(losses)
    left.set_xlabel("rollout (L-BFGS evaluation)")
    left.set_ylabel("loss")
    time = [k * DT for k in range(len(positions))]
    for axis, name in enumerate("xyz"):
        line, = right.plot(time, positions[:, axis], label=f"frame {name}")
        right.axhline(target[axis], color=line.get_color(), linestyle=":")
    right.set_xlabel("time (s)")
    right.set_ylabel("position (m); dotted: the target")
    right.legend()
    figure.tight_layout()
    figure.savefig(file)


if __name__ == "__main__":
    main()

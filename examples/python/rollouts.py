"""Rollouts of a robot in a batch, with the Python module that dyngen generates for it.

N rollouts start at random states and move freely under gravity (tau = 0), integrated together by
semi-implicit Euler: one call of the module's aba per step for all N states. Physics conserves
each rollout's energy, E = 1/2 v'M(q)v - m g.c(q) (crba for M, com for the centre of mass c);
the integrator does not, and the plot shows by how much, for three time steps: the drift shrinks
with the step, as a first-order method's does. The robot must have a fixed base (a free joint's
quaternion needs another integrator).

    build/dyngen examples/ur5.urdf -o gen --python --algorithms aba,crba,com
    cmake -S gen -B gen/build -DUR5_BUILD_CHECK=OFF && cmake --build gen/build
    PYTHONPATH=gen/build python3 examples/python/rollouts.py ur5_dynamics --plot energy.png
"""
import argparse
import importlib
import time

import numpy as np


def energy(d, q, v):
    """Kinetic plus potential energy of each state, in J."""
    M = d.crba(q)
    c, _ = d.com(q)
    kinetic = 0.5 * np.einsum("ni,nij,nj->n", v, M, v)
    return kinetic - d.total_mass * c @ np.asarray(d.gravity_acceleration)


def rollouts(d, q, v, dt, steps, threads):
    """Energy drift relative to the initial energy's scale, per step and rollout, and the states
    per second that aba ran at."""
    tau = np.zeros_like(v)
    e0 = energy(d, q, v)
    scale = np.abs(e0) + 1.0
    drift = np.empty((steps, len(q)))
    seconds = 0.0
    for step in range(steps):
        start = time.perf_counter()
        qdd = d.aba(q, v, tau, threads=threads)
        seconds += time.perf_counter() - start
        v = v + dt * qdd
        q = q + dt * v
        drift[step] = np.abs(energy(d, q, v) - e0) / scale
    return drift, steps * len(q) / seconds


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("module", help="the generated module, e.g. ur5_dynamics")
    parser.add_argument("--rollouts", type=int, default=256)
    parser.add_argument("--seconds", type=float, default=1.0, help="simulated time")
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--plot", help="write the drift plot to this image file")
    args = parser.parse_args()

    d = importlib.import_module(args.module)
    if d.quaternion_indices:
        parser.error(f"{args.module} has a free joint: this example integrates fixed bases only")
    rng = np.random.default_rng(1)
    q0 = rng.uniform(-np.pi, np.pi, (args.rollouts, d.nq)).astype(d.dtype)
    v0 = rng.uniform(-1.0, 1.0, (args.rollouts, d.nv)).astype(d.dtype)

    results = {}
    for dt in (4e-3, 2e-3, 1e-3):
        steps = round(args.seconds / dt)
        drift, rate = rollouts(d, q0, v0, dt, steps, args.threads)
        results[dt] = drift
        print(f"dt {dt:g} s, {steps} steps of {args.rollouts} rollouts: final drift median "
              f"{np.median(drift[-1]):.2e}, max {np.max(drift[-1]):.2e}; aba at "
              f"{rate / 1e6:.2f} million states/s")

    if args.plot:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        figure, axes = plt.subplots(figsize=(7, 4))
        for dt, drift in results.items():
            t = dt * np.arange(1, len(drift) + 1)
            line = axes.semilogy(t, np.median(drift, axis=1), label=f"dt = {dt:g} s, median")
            axes.semilogy(t, np.max(drift, axis=1), linestyle=":", color=line[0].get_color(),
                          label=f"dt = {dt:g} s, worst")
        axes.set_xlabel("time (s)")
        axes.set_ylabel("|E - E0| / (|E0| + 1 J)")
        axes.set_title(f"{args.module}: energy drift of {args.rollouts} rollouts, semi-implicit Euler")
        axes.legend(fontsize="small")
        figure.tight_layout()
        figure.savefig(args.plot, dpi=120)
        print(f"wrote {args.plot}")


if __name__ == "__main__":
    main()

"""Forward dynamics with gradients in PyTorch: dyngen --torch (NAME_torch.aba, whose backward
calls the generated rnea_derivatives and minv) against the peer, the plain-PyTorch batched ABA
that a learning user writes without dyngen (bench/torch_peer.py, autograd for its backward).

For each robot and dtype, and 1, 64 and 4096 states a call, the two are timed side by side in
one run: forward (under torch.no_grad for the peer, whose graph would cost it otherwise), and
forward then backward of qdd's sum (gradients in q, v and tau). Rounds alternate the four
measures; each figure is the median over rounds of the time of one call (at least 0.05 s of
calls a measure), and the ratio is the median of the rounds' ratios. Both run on one thread
(torch.set_num_threads(1), threads=1). Then the per-call overhead of one state: NAME_torch.aba,
the NumPy module's aba on the same state, and the module's call with no state, (0, n) arrays.

usage: PYTHONPATH=DIR[:DIR...] python3 bench/torch_bench.py LABEL=MODULE=URDF[=floating] ...
       [--rounds 7] [--out FILE.md]          (scripts/torch_bench.sh builds the modules)
"""
import argparse
import importlib
import os
import statistics
import sys
import time

import numpy as np
import torch

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from torch_peer import PlainTorchABA  # noqa: E402

COUNTS = (1, 64, 4096)


def per_call(call, minimum=0.05):
    """Seconds of one call, over at least `minimum` seconds of calls."""
    call()
    calls, start = 0, time.perf_counter()
    while True:
        call()
        calls += 1
        elapsed = time.perf_counter() - start
        if elapsed >= minimum:
            return elapsed / calls


def states(module, n, dtype, seed=20261129):
    """n random states (q with unit quaternions, v, tau) as tensors of dtype."""
    rng = np.random.default_rng(seed)
    q = rng.uniform(-3.0, 3.0, (n, module.nq))
    for k in module._QUATERNIONS:
        q[:, k:k + 4] /= np.linalg.norm(q[:, k:k + 4], axis=1, keepdims=True)
    v, tau = rng.uniform(-3.0, 3.0, (2, n, module.nv))
    return tuple(torch.from_numpy(x).to(dtype) for x in (q, v, tau))


def forward_backward(aba, q, v, tau):
    x = tuple(t.clone().requires_grad_() for t in (q, v, tau))
    aba(*x).sum().backward()
    return x[0].grad


def measure(torch_module, peer, n, dtype, rounds):
    """Medians of the four measures (seconds a call) and of the two ratios, peer over dyngen."""
    q, v, tau = states(torch_module, n, dtype)
    ours_aba, peer_aba = torch_module.aba, peer.aba
    if n == 1:  # the peer takes a batch
        ours_aba = lambda q, v, tau: torch_module.aba(q[0], v[0], tau[0])  # noqa: E731
    mine = ours_aba(q, v, tau).reshape(n, -1)
    with torch.no_grad():
        theirs = peer_aba(q, v, tau)
    error = ((mine - theirs).abs().max() / theirs.abs().max()).item()
    assert error <= (1e-3 if dtype == torch.float32 else 1e-9), f"the peer's qdd is off by {error:.3g}"

    def peer_forward():
        with torch.no_grad():
            peer_aba(q, v, tau)

    measures = {"peer forward": peer_forward, "dyngen forward": lambda: ours_aba(q, v, tau),
                "peer forward+backward": lambda: forward_backward(peer_aba, q, v, tau),
                "dyngen forward+backward": lambda: forward_backward(ours_aba, q, v, tau)}
    times = {name: [] for name in measures}
    for _ in range(rounds):
        for name, call in measures.items():
            times[name].append(per_call(call))
    result = {name: statistics.median(t) for name, t in times.items()}
    for kind in ("forward", "forward+backward"):
        result[f"ratio {kind}"] = statistics.median(
            p / d for p, d in zip(times[f"peer {kind}"], times[f"dyngen {kind}"]))
    result["error"] = error
    return result


def overhead(torch_module, numpy_module, dtype, rounds):
    """Medians over rounds of a one-state call: torch, NumPy, and the module with no state."""
    q, v, tau = (x[0] for x in states(torch_module, 1, dtype))
    qn, vn, taun = (x.numpy() for x in (q, v, tau))
    empty = (np.zeros((0, numpy_module.nq), qn.dtype), np.zeros((0, numpy_module.nv), qn.dtype))
    calls = {"torch aba, one state": lambda: torch_module.aba(q, v, tau),
             "torch aba forward+backward, one state":
                 lambda: forward_backward(torch_module.aba, q, v, tau),
             "NumPy module aba, one state": lambda: numpy_module.aba(qn, vn, taun),
             "NumPy module aba, no state": lambda: numpy_module.aba(empty[0], empty[1], empty[1])}
    times = {name: [] for name in calls}
    for _ in range(rounds):
        for name, call in calls.items():
            times[name].append(per_call(call, 0.02))
    return {name: statistics.median(t) for name, t in times.items()}


def milliseconds(seconds):
    return f"{seconds * 1e3:,.3f}"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("robots", nargs="+", help="LABEL=MODULE=URDF[=floating]: MODULE_torch.py "
                        "and MODULE_dynamics on PYTHONPATH")
    parser.add_argument("--rounds", type=int, default=7)
    parser.add_argument("--out", help="write the tables as Markdown here too")
    args = parser.parse_args()
    torch.set_num_threads(1)
    lines = ["| robot | dtype | states | peer forward | dyngen forward | ratio | peer fwd+bwd | "
             "dyngen fwd+bwd | ratio |", "|---|---|---:|---:|---:|---:|---:|---:|---:|"]
    costs = ["| robot | dtype | " + " | ".join(
        ("torch aba", "torch aba fwd+bwd", "NumPy module aba", "NumPy module, no state")) + " |",
             "|---|---|---:|---:|---:|---:|"]
    for entry in args.robots:
        label, name, urdf, *floating = entry.split("=")
        torch_module = importlib.import_module(f"{name}_torch")
        numpy_module = importlib.import_module(f"{name}_dynamics")
        dtype = torch_module.dtype
        peer = PlainTorchABA(urdf, floating_base=bool(floating), dtype=dtype)
        for n in COUNTS:
            r = measure(torch_module, peer, n, dtype, args.rounds)
            lines.append(f"| {label} | {str(dtype)[6:]} | {n:,} | " + " | ".join(
                [milliseconds(r["peer forward"]), milliseconds(r["dyngen forward"]),
                 f"{r['ratio forward']:.1f}", milliseconds(r["peer forward+backward"]),
                 milliseconds(r["dyngen forward+backward"]),
                 f"{r['ratio forward+backward']:.1f}"]) + " |")
            print(lines[-1], flush=True)
        o = overhead(torch_module, numpy_module, dtype, args.rounds)
        microseconds = " | ".join(f"{t * 1e6:.1f}" for t in o.values())
        costs.append(f"| {label} | {str(dtype)[6:]} | {microseconds} |")
        print(costs[-1], flush=True)
    text = ("Milliseconds a call (one thread each):\n\n" + "\n".join(lines) +
            "\n\nMicroseconds of a one-state call:\n\n" + "\n".join(costs) + "\n")
    print(text)
    if args.out:
        with open(args.out, "w") as f:
            f.write(text)


if __name__ == "__main__":
    main()

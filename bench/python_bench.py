"""Throughput of generated Python modules (dyngen --python): states per second of rnea, crba and
aba through the module for N = 1, 16, 1024 and 65536 states a call (and 65536 writing into
arrays given as out=, which spares the allocation and first touch of new ones), beside a Python
loop that calls the module once per state (one-state arrays, the scalar function), the time
of a one-state call, and the time of a call with no state (arrays of shape (0, n)): the call's
cost without the dynamics, which is what the module adds to them. States are random and change every call (a pool cycled through); each figure is
the median of 5 repetitions of at least 0.2 s.

usage: PYTHONPATH=DIR[:DIR...] python3 bench/python_bench.py MODULE [MODULE...] [--out FILE.md]
(scripts/python_bench.sh builds the modules and runs this.)
"""
import argparse
import importlib
import statistics
import time

import numpy as np

COUNTS = (1, 16, 1024, 65536)
LOOP_STATES = 1024


def pool(d, n, copies):
    """copies sets of n random states: q (unit quaternions for free joints), v and a/tau."""
    rng = np.random.default_rng(20261126)
    sets = []
    for _ in range(copies):
        q = rng.uniform(-3.0, 3.0, (n, d.nq))
        for k in d.quaternion_indices:
            q[:, k:k + 4] /= np.linalg.norm(q[:, k:k + 4], axis=1, keepdims=True)
        v, x = rng.uniform(-3.0, 3.0, (2, n, d.nv))
        sets.append(tuple(a.astype(d.dtype) for a in (q, v, x)))
    return sets


def seconds_per_call(call, arguments):
    """Median over 5 repetitions of the time of one call, cycling through the argument sets."""
    call(*arguments[0])  # first touch of the outputs' memory, imports
    medians = []
    for _ in range(5):
        calls, start = 0, time.perf_counter()
        while True:
            for args in arguments:
                call(*args)
            calls += len(arguments)
            elapsed = time.perf_counter() - start
            if elapsed >= 0.2:
                break
        medians.append(elapsed / calls)
    return statistics.median(medians)


def functions(d):
    """Each function as f(q, v, x) and as f(q, v, x, out), x being a or tau."""
    return {"rnea": (lambda q, v, x: d.rnea(q, v, x), lambda q, v, x, y: d.rnea(q, v, x, out=y)),
            "crba": (lambda q, v, x: d.crba(q), lambda q, v, x, y: d.crba(q, out=y)),
            "aba": (lambda q, v, x: d.aba(q, v, x), lambda q, v, x, y: d.aba(q, v, x, out=y))}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("modules", nargs="+")
    parser.add_argument("--out", help="also write the table to this Markdown file")
    args = parser.parse_args()

    header = ("| module | function | one-state call, ns | no-state call, ns | "
              "Python loop, M states/s | "
              + " | ".join(f"N = {n}, M states/s" for n in COUNTS)
              + f" | N = {COUNTS[-1]}, out=, M states/s |")
    lines = [header, "|" + "---|" * (header.count("|") - 1)]
    for name in args.modules:
        d = importlib.import_module(name)
        for function, (call, call_into) in functions(d).items():
            # the module's function itself, without the lambda: crba reads q alone
            used = 1 if function == "crba" else 3
            one_state = seconds_per_call(getattr(d, function),
                                         [tuple(a[0] for a in s[:used]) for s in pool(d, 1, 64)])
            no_state = seconds_per_call(getattr(d, function),
                                        [tuple(a[:0] for a in s[:used]) for s in pool(d, 1, 64)])
            states = pool(d, LOOP_STATES, 1)[0]

            def loop(q, v, x):
                for s in range(LOOP_STATES):
                    call(q[s], v[s], x[s])

            rates = [LOOP_STATES / seconds_per_call(loop, [states])]
            for n in COUNTS:
                copies = max(1, min(64, 65536 // n))
                rates.append(n / seconds_per_call(call, pool(d, n, copies)))
            n = COUNTS[-1]
            out = call(*pool(d, n, 1)[0])
            rates.append(n / seconds_per_call(lambda q, v, x: call_into(q, v, x, out), pool(d, n, 1)))
            row = (f"| {name} ({d.dtype}, {d.lanes} lanes) | {function} | {one_state * 1e9:.0f} | "
                   f"{no_state * 1e9:.0f} | "
                   + " | ".join(f"{r / 1e6:.2f}" for r in rates) + " |")
            print(row, flush=True)
            lines.append(row)
    if args.out:
        with open(args.out, "w") as out:
            out.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()

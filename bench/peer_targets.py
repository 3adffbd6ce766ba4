#!/usr/bin/env python3
"""Issue 45's speed targets against one run of dyngen_derivatives_bench (bench/README.md,
"Against Pinocchio's derivatives"): reads the run's Google Benchmark JSON and the operation
table it printed, and writes results/peer_targets.md.

The reference times are issue 45's, measured on this kind of machine in one harness beside
dyngen (Pinocchio 3.7 is not in Debian, so it cannot be measured here): Pinocchio with
CppADCodeGen (its generated C, called raw) and Pinocchio's generic algorithms, ns per call. CRBA
on the arms has no figure in issue 45; issue 16's stand for it. The targets:
- rnea_derivatives (timed with crba after it: Pinocchio's returns dtau/da = M too) and
  aba_derivatives: at most half of Pin+CG and a third of Pinocchio;
- minv: at most half of both;
- rnea, crba and aba on arms whose URDFs write rounded rotations: at most half of Pin+CG.
"""

import argparse
import json
import os
import sys

# issue 45's own table: (function, bench package, issue's robot, dyngen ns at 96a8a48, Pin+CG ns,
# Pinocchio ns), given again with this run's dyngen column; its figures are the targets' too
ISSUE_TABLE = [
    ("rnea_derivatives", "ur5 fixed", "ur5", 436, 1072, 1999),
    ("rnea_derivatives", "iiwa14 fixed", "iiwa14", 928, 1460, 2325),
    ("rnea_derivatives", "solo12 floating", "solo12 floating", 1096, 4423, 5031),
    ("rnea_derivatives", "atlas floating", "atlas floating", 7221, 13061, 12575),
    ("aba_derivatives", "ur5 fixed", "ur5", 652, 1461, 2605),
    ("aba_derivatives", "iiwa14 fixed", "iiwa14", 1370, 2001, 3163),
    ("aba_derivatives", "solo12 floating", "solo12 floating", 3170, 7510, 8226),
    ("aba_derivatives", "atlas floating", "atlas floating", 16869, 65983, 24828),
    ("minv", "ur5 fixed", "ur5", 143, 222, 861),
    ("minv", "atlas floating", "atlas floating", 4996, 5574, 6755),
    ("aba", "iiwa14 fixed", "iiwa14", 406, 636, 1435),
    ("aba", "panda fixed", "panda", 494, 866, 1843),
    ("aba", "panda fixed", "7-DoF arm with a 3-finger hand", 775, 1050, 2016),
    ("rnea", "iiwa14 fixed", "iiwa14", 104, 150, 670),
    ("rnea", "atlas fixed", "atlas", 590, 930, 3170),
]
# issue 16's figures (Pin+CG ns, Pinocchio ns) for target rows that issue 45's table lacks
ISSUE_16 = {
    ("rnea", "panda"): (299, 1064),
    ("crba", "iiwa14"): (221, 466),
    ("crba", "panda"): (310, 591),
    ("crba", "7-DoF arm with a 3-finger hand"): (587, 660),
}
QUADRUPED = "quadruped, rotated frames"
# the target rows: (function, bench package, issue's robot)
TARGET_ROWS = (
    [(f, p, r) for f in ("rnea_derivatives_with_M", "aba_derivatives", "minv")
     for p, r in (("ur5 fixed", "ur5"), ("iiwa14 fixed", "iiwa14"),
                  ("solo12 floating", "solo12 floating"), ("anymal_c floating", QUADRUPED),
                  ("atlas floating", "atlas floating"))] +
    [("rnea", "iiwa14 fixed", "iiwa14"), ("rnea", "panda fixed", "panda"),
     ("crba", "iiwa14 fixed", "iiwa14"), ("crba", "panda fixed", "panda"),
     ("crba", "panda fixed", "7-DoF arm with a 3-finger hand"),
     ("aba", "iiwa14 fixed", "iiwa14"), ("aba", "panda fixed", "panda"),
     ("aba", "panda fixed", "7-DoF arm with a 3-finger hand")])


def reference(function, package, robot):
    """(Pin+CG ns, Pinocchio ns, source issue) of a target row: issue 45's table (its
    rnea_derivatives for rnea_derivatives_with_M), else issue 16's, else no figure."""
    name = function.removesuffix("_with_M")
    for f, p, r, _, codegen, generic in ISSUE_TABLE:
        if (f, p, r) == (name, package, robot):
            return codegen, generic, 45
    if (function, robot) in ISSUE_16:
        return (*ISSUE_16[function, robot], 16)
    return None, None, 45


# (function, bench package, issue's robot, Pin+CG ns, Pinocchio ns, source)
REFERENCE = [(f, p, r, *reference(f, p, r)) for f, p, r in TARGET_ROWS]
# the factor by which dyngen must beat Pin+CG and Pinocchio (None: no target)
FACTORS = {"rnea_derivatives_with_M": (2, 3), "aba_derivatives": (2, 3), "minv": (2, 2),
           "rnea": (2, None), "crba": (2, None), "aba": (2, None)}
TOLERANCE = 1.15  # issue 16: reference times hold on this kind of machine within 15%
CACHE_MISSES = 50  # a function that fits the instruction cache misses under 10 times a call


def read_times(path):
    """{benchmark name: median CPU ns} from Google Benchmark's JSON."""
    with open(path) as f:
        runs = json.load(f)["benchmarks"]
    return {r["run_name"]: r["cpu_time"] for r in runs if r.get("aggregate_name") == "median"}


def read_operations(path):
    """{(package, function): add+mul+div+neg of the generated code} from the operation table
    that dyngen_derivatives_bench prints before its timings."""
    table = [line for line in open(path) if line.startswith("| ")]
    if not table:
        sys.exit(f"peer_targets.py: {path}: no operation table")
    header = [c.strip() for c in table[0].strip().strip("|").split("|")]
    ops = {}
    for line in table[1:]:
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        for name, cell in zip(header[1:], cells[1:]):
            ops[cells[0], name] = int(cell.split("/")[0])
    ops.update({(p, "rnea_derivatives_with_M"): ops[p, "rnea_derivatives"] + ops[p, "crba"]
                for p, _ in list(ops)})
    return ops


def read_callgrind(path):
    """{(package, function): (instructions, I1 misses) per call} from peer_targets.sh's counts."""
    counts = {}
    for line in open(path):
        package, function, ir, i1 = line.strip().split("|")
        counts[package, function] = int(ir), int(i1)
    return counts


def read_frames(path):
    """{(model, function): operations} that any choice of body frames leaves, from
    dyngen_work_counts' work_counts.json (its rounded-rotation arms, fixed base)."""
    bound = {(r["model"], r["algorithm"]): r["twists_only"]
             for r in json.load(open(path))["rounded_rotations"]}
    bound.update({(m, "rnea_derivatives_with_M"): bound[m, "rnea_derivatives"] + bound[m, "crba"]
                  for m, _ in list(bound)})
    return bound


def verdict(ns, reference, factor):
    """'yes', '**no**' or '-' (no target or no figure) for ns against reference / factor."""
    if factor is None or reference is None:
        return "-"
    return "yes" if ns * factor <= reference else "**no**"


def row(entry, times, ops, fastest, counts, frames):
    """The table's row for one target entry, and its status: 'met', 'missed' or 'no figure'."""
    function, package, robot, codegen, generic, source = entry
    ir, i1 = counts.get((package, function), (None, None))
    name = f"{package}/{function}"
    if name not in times:
        sys.exit(f"peer_targets.py: the run has no {name}")
    ns, n_ops = times[name], ops[package, function]
    fc, fg = FACTORS[function]
    met = [verdict(ns, codegen, fc), verdict(ns, generic, fg)]
    targets = [reference / f for reference, f in ((codegen, fc), (generic, fg))
               if reference is not None and f is not None]
    limit = ""
    if "**no**" in met:
        needed = n_ops / min(targets)
        limit = f"needs {needed:.2f} ops/ns, {needed / fastest:.2f} × the run's fastest"
        for peer, r, f in (("Pin+CG", codegen, fc), ("Pinocchio", generic, fg)):
            if r is not None and f is not None and r < ns * f <= TOLERANCE * r:
                limit += f"; {peer}'s within the reference's ±15%"
        if i1 is not None and i1 >= CACHE_MISSES:
            limit += f"; instruction cache ({i1} misses a call)"
        bound = frames.get((package.removesuffix(" fixed"), function))
        if bound is not None:
            limit += (f"; any body frames leave {bound} ops: {bound * ns / n_ops:.0f} ns at this "
                      f"row's rate, against {min(targets):.0f} wanted")
    ratio = lambda r: "-" if r is None else f"{r / ns:.2f}"
    figure = lambda r: "-" if r is None else str(r)
    status = "missed" if "**no**" in met else "met" if targets else "no figure"
    return (f"| {function} | {robot} | {package} | {ns:.0f} | {figure(codegen)} | {ratio(codegen)}"
            f" | {met[0]} | {figure(generic)} | {ratio(generic)} | {met[1]} | {source} | "
            f"{n_ops} | {n_ops / ns:.2f} | {figure(ir)} | {figure(i1)} | {limit} |"), status


def issue_table(times):
    """Issue 45's table, its dyngen column beside this run's (rnea_derivatives alone, as there;
    the arm with a hand is panda here, a 7-DoF arm with two fingers)."""
    text = ("## Issue 45's table, after\n\n"
            "The issue's table (ns; its dyngen column measured at 96a8a48, SSE2) with this run's "
            "dyngen beside it, and the ratios to the issue's reference times.\n\n"
            "| function | robot | dyngen, issue | dyngen, this run | Pin+CG | Pinocchio | "
            "Pin+CG / dyngen | Pinocchio / dyngen |\n|---|---|---:|---:|---:|---:|---:|---:|\n")
    for function, package, robot, before, codegen, generic in ISSUE_TABLE:
        name = f"{package}/{function}"
        if name not in times:
            sys.exit(f"peer_targets.py: the run has no {name}")
        ns = times[name]
        text += (f"| {function} | {robot} | {before} | {ns:.0f} | {codegen} | {generic} | "
                 f"{codegen / ns:.2f} | {generic / ns:.2f} |\n")
    return text


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("json", nargs="?", help="dyngen_derivatives_bench's --benchmark_out")
    parser.add_argument("operations", nargs="?", help="what it printed (its operation table)")
    parser.add_argument("--callgrind", help="peer_targets.sh's instruction counts")
    parser.add_argument("--frames", help="dyngen_work_counts' work_counts.json")
    parser.add_argument("--rows", action="store_true",
                        help="print the target rows' package|function, once each, and stop")
    parser.add_argument("--out", default="bench/results/peer_targets.md")
    args = parser.parse_args()
    if args.rows:
        print("\n".join(dict.fromkeys(f"{e[1]}|{e[0]}" for e in REFERENCE)))
        return
    if not (args.json and args.operations):
        parser.error("give the run's JSON and its printed output, or --rows")
    times, ops = read_times(args.json), read_operations(args.operations)
    counts = read_callgrind(args.callgrind) if args.callgrind else {}
    frames = read_frames(args.frames) if args.frames else {}
    fastest = max(ops[e[1], e[0]] / times[f"{e[1]}/{e[0]}"] for e in REFERENCE
                  if f"{e[1]}/{e[0]}" in times)
    rows, statuses = zip(*(row(e, times, ops, fastest, counts, frames) for e in REFERENCE))
    with open(args.out, "w") as md:
        md.write(
            "# Issue 45's targets\n\n"
            "`scripts/peer_targets.sh`: one run of `dyngen_derivatives_bench` (the median of its "
            "repetitions, CPU ns per call, states that change every call) beside issue 45's "
            "reference times for Pinocchio + CppADCodeGen (*Pin+CG*) and Pinocchio's generic "
            "algorithms on this kind of machine (*source* 16: issue 16's, where issue 45 gives "
            "none). *rnea_derivatives_with_M* is `rnea_derivatives` then `crba`, as Pinocchio's "
            "returns M too. Targets: derivatives at most half of Pin+CG and a third of "
            "Pinocchio, `minv` half of both, the arms' `rnea`, `crba` and `aba` half of Pin+CG; "
            "`-` where there is no target or no figure. *ops* are the generated code's additions, "
            "multiplications, divisions and negations per call, *ops/ns* the rate at which it "
            "did them; *Ir* and *I1 misses* are the instructions and level-1 instruction-cache "
            "misses per call under callgrind (this machine's 32 KB cache simulated; 64 calls on "
            "the bench's states, the harness's own instructions taken off). A missed row gives "
            "the rate its strictest target needs, over the "
            f"fastest rate of any row of the run ({fastest:.2f} ops/ns): above 1, only fewer "
            f"operations can meet it; the instruction cache from {CACHE_MISSES} misses a "
            "call; and on the arms with rounded rotations, the operations that any choice of "
            "body frames would still leave (bench/results/work_counts.md, \"Rounded "
            "rotations\") and the time they would take at the row's own rate.\n\n"
            "| function | issue's robot | dyngen package | dyngen | Pin+CG | Pin+CG / dyngen | "
            "met | Pinocchio | Pinocchio / dyngen | met | source | ops | ops/ns | Ir | "
            "I1 misses | limit |\n"
            "|---|---|---|---:|---:|---:|---|---:|---:|---|---:|---:|---:|---:|---:|---|\n")
        md.write("\n".join(rows) + "\n\n")
        md.write(f"Every target met: {statuses.count('met')} rows; one missed or more: "
                 f"{statuses.count('missed')}; no reference figure: "
                 f"{statuses.count('no figure')}.\n\n")
        md.write(issue_table(times))
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()

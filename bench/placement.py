#!/usr/bin/env python3
"""How much a benchmark's times depend on which physical pages hold its code (bench/README.md,
"Placement"; scripts/placement.sh runs it).

Writing a file puts its contents in new page frames, so K copies of one benchmark binary are the
same instructions at the same virtual addresses in K physical placements. The kernel hands out
recently freed frames first, so each copy is written while a random amount of other memory is
held, which makes the copies' placements independent draws. Each copy runs twice,
then twice more with its code moved to fresh pages by move_text.so (fresh pages are another
draw, which can be slow too: the faster of the two counts). A copy that is slow in both of its
runs and fast once its code is moved was slow because of where its code landed. Every run is
pinned to one CPU: the two CPUs of the machine this was written on differed by up to 1.7 times.
"""

import argparse
import json
import os
import random
import shutil
import statistics
import subprocess
import sys
import tempfile

FLAG = 1.2  # issue 16: the same code should not differ by 20% or more


def processor(cpu):
    """The processor as /proc/cpuinfo names CPU cpu: runs on different hosts of one kind of
    virtual machine differed by up to 2.5 times, and the name, family and clock tell them apart
    where anything does."""
    fields, current = {}, None
    try:
        for line in open("/proc/cpuinfo"):
            key, _, value = (part.strip() for part in line.partition(":"))
            if key == "processor":
                current = int(value)
            elif current == cpu and key in ("model name", "cpu family", "model", "cpu MHz"):
                fields[key] = value
    except OSError:
        return "not named (no /proc/cpuinfo)"
    return (f"{fields.get('model name', '?')}, family {fields.get('cpu family', '?')} model "
            f"{fields.get('model', '?')}, {fields.get('cpu MHz', '?')} MHz as the kernel reads it")


def run(binary, args, preload=None):
    """{benchmark name: CPU ns per call} of one run of binary."""
    with tempfile.NamedTemporaryFile(suffix=".json") as out:
        env = dict(os.environ)
        if preload:
            env["LD_PRELOAD"] = preload
        command = [binary, f"--benchmark_filter={args.filter}",
                   f"--benchmark_min_time={args.min_time}",
                   f"--benchmark_out={out.name}", "--benchmark_out_format=json"]
        result = subprocess.run(command, env=env, stdout=subprocess.DEVNULL,
                                stderr=subprocess.PIPE, text=True,
                                preexec_fn=lambda: os.sched_setaffinity(0, {args.cpu}))
        if result.returncode != 0:
            sys.exit(f"placement.py: {' '.join(command)} failed:\n{result.stderr}")
        if preload and "move_text: moved" not in result.stderr:
            sys.exit(f"placement.py: {preload} did not move the code:\n{result.stderr}")
        scale = {"ns": 1.0, "us": 1e3, "ms": 1e6, "s": 1e9}
        times = {}
        text = open(out.name).read()
        if not text.strip():
            sys.exit(f"placement.py: {binary} wrote no results: is it a Google Benchmark program, "
                     f"and does --benchmark_filter={args.filter!r} match anything?")
        for b in json.loads(text)["benchmarks"]:
            if b.get("run_type", "iteration") == "iteration":
                times[b["name"]] = b["cpu_time"] * scale[b["time_unit"]]
        if not times:
            sys.exit(f"placement.py: no benchmark matches {args.filter!r}")
        return times


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--binary", required=True, help="a Google Benchmark program")
    parser.add_argument("--move-text", required=True, help="libdyngen_move_text.so")
    parser.add_argument("--filter", required=True, help="--benchmark_filter of every run")
    parser.add_argument("--copies", type=int, default=10)
    parser.add_argument("--min-time", default="0.1", help="--benchmark_min_time of every run")
    parser.add_argument("--cpu", type=int, default=0,
                        help="the CPU every run is pinned to (CPUs of a virtual machine can "
                             "differ in speed)")
    parser.add_argument("--out", required=True, help="the Markdown report to write")
    args = parser.parse_args()
    for path in (args.binary, args.move_text):
        if not os.path.isfile(path):
            sys.exit(f"placement.py: {path}: no such file (scripts/placement.sh builds both)")
    move_text = os.path.abspath(args.move_text)

    with tempfile.TemporaryDirectory(prefix="dyngen-placement-") as directory:
        copies = []
        for c in range(args.copies):
            held = bytearray(4096 * random.randrange(8192))  # up to 32 MiB, every page touched
            held[::4096] = b"\1" * len(held[::4096])
            copies.append(os.path.join(directory, f"copy{c + 1}"))
            shutil.copy2(args.binary, copies[-1])
            os.sync()  # the copy's pages written back and clean, as an installed binary's
            del held
        # Passes over all copies, so that a burst of load elsewhere falls on one run of a copy,
        # not on both.
        runs = {}
        for label in ("first", "second", "moved", "moved again"):
            for c, binary in enumerate(copies):
                print(f"placement: copy {c + 1} of {len(copies)}, {label} run", flush=True)
                runs[c, label] = run(binary, args, move_text if "moved" in label else None)

    names = list(runs[0, "first"])
    flagged = 0
    rows = []
    for name in names:
        # A copy's time: the faster of its two runs (noise only ever slows a run down).
        time = [min(runs[c, "first"][name], runs[c, "second"][name]) for c in range(len(copies))]
        median = statistics.median(time)
        slow = max(range(len(copies)), key=lambda c: time[c])
        fast = min(time)
        moved = min(runs[slow, "moved"][name], runs[slow, "moved again"][name])
        spread = time[slow] / fast
        slow_copies = sum(t >= FLAG * median for t in time)
        flagged += slow_copies
        verdict = ""
        if time[slow] >= FLAG * median:
            verdict = ("**its code's pages**" if moved < FLAG * median
                       else "**slow with its code moved too**")
        rows.append(f"| {name} | {median:.1f} | {fast:.1f} | {time[slow]:.1f} | {spread:.2f} | "
                    f"{runs[slow, 'first'][name]:.1f} / {runs[slow, 'second'][name]:.1f} | "
                    f"{moved:.1f} | {slow_copies} | {verdict} |")

    with open(args.out, "w") as md:
        md.write(
            "# Placement: the same code in other physical pages\n\n"
            f"`scripts/placement.sh` ({os.path.basename(args.binary)}, "
            f"`--benchmark_filter='{args.filter}'`, `--benchmark_min_time={args.min_time}`, "
            f"every run on CPU {args.cpu}: {processor(args.cpu)}): "
            f"{len(copies)} copies of the binary, each the same instructions at the same "
            "virtual addresses in the page frames its file got when written; each ran twice "
            "(passes over all copies) and a copy's time is the faster of its two runs. CPU ns "
            "per call. The slowest copy's two runs are given, and its time with its code moved "
            "to fresh pages (move_text.so; the faster of two runs, each a new draw of pages). "
            f"A copy is flagged at {FLAG} times the median of the copies or more: "
            "\"its code's pages\" when moving its code brings it under that, "
            "so that where its code landed in physical memory made it slow.\n\n"
            "| benchmark | median | fastest | slowest | slowest / fastest | slowest copy's runs "
            "| slowest, code moved | copies flagged | why |\n"
            "|---|---:|---:|---:|---:|---|---:|---:|---|\n")
        md.write("\n".join(rows) + "\n")
        md.write(f"\n{flagged} of {len(names) * len(copies)} copies × benchmarks flagged.\n")
    print(f"wrote {args.out}: {flagged} of {len(names) * len(copies)} copies × benchmarks "
          f"at {FLAG} times their median or more")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""The names that the headers of generated packages define: the robots' names that dyngen changes.

A robot's name becomes a C++ namespace at global scope, in files that also include the standard
library, GoogleTest (and through it POSIX), the runtime, pybind11, Python.h, NumPy, Google
Benchmark, nlohmann/json, Eigen and MPFR (the check, the Python module, dyngen report's harness),
and a C prefix (NAME_rnea, NAME_NQ). This probe compiles those headers and lists, among the names
that dyngen's identifier() can produce (and names it can produce with a suffix):

- every macro they define (-E -dD, in C++ and in C, GNU modes: a user's build may use them, and
  they define more, linux and unix);
- every name they declare at global scope: after the headers, a C++ file declares
  `inline namespace N {}` for each other identifier token of the preprocessed headers, which GCC
  rejects where N is declared at global scope as anything, a namespace included, and a C file
  `enum { N };`, which GCC rejects for every ordinary identifier at file scope. One compile each;
  GCC's errors name the lines.

identifier() (generator/names.cpp) reserves a name on this list, and, for C packages, a name whose
C names (NAME_rnea, NAME_NQ, ...) are on it.

  scripts/reserved_names.py           adds what it finds to generator/reserved_names.txt
  scripts/reserved_names.py --check   exits 1, listing them, if it finds names the list lacks

The list only grows: dropping a name would rename the packages of robots that carry it. The
probe needs python3 with NumPy (for its headers), python3-dev, pybind11-dev, libgtest-dev,
libbenchmark-dev, nlohmann-json3-dev, libeigen3-dev and libmpfrc++-dev: the test dependencies,
each required, so that a missing header fails the probe rather than shortening the list.
"""
import argparse
import os
import re
import subprocess
import sys
import sysconfig
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
LIST = os.path.join(ROOT, "generator", "reserved_names.txt")

# The C and C++ standard libraries whole (a user's file may include any of them beside the
# package), then what the generated files include beyond them. <format> is C++20 but came with
# GCC 13's libstdc++: the one header allowed to be absent.
CXX_STANDARD = """algorithm any array atomic barrier bit bitset cassert cctype cerrno cfenv cfloat
charconv chrono cinttypes climits clocale cmath codecvt compare complex concepts
condition_variable coroutine csetjmp csignal cstdarg cstddef cstdint cstdio cstdlib cstring ctime
cuchar cwchar cwctype deque exception execution filesystem forward_list fstream functional future
initializer_list iomanip ios iosfwd iostream istream iterator latch limits list locale map memory
memory_resource mutex new numbers numeric optional ostream queue random ranges ratio regex
scoped_allocator semaphore set shared_mutex source_location span sstream stack stdexcept stop_token
streambuf string string_view syncstream system_error thread tuple type_traits typeindex typeinfo
unordered_map unordered_set utility valarray variant vector version""".split()
C_STANDARD = """assert complex ctype errno fenv float inttypes iso646 limits locale math setjmp
signal stdalign stdarg stdatomic stdbool stddef stdint stdio stdlib stdnoreturn string tgmath
threads time uchar wchar wctype""".split()
CXX_LIBRARIES = """gtest/gtest.h dyngen/dyngen.hpp dyngen/kernels.hpp dyngen/sincos.h
dyngen/numerics/conditioning.hpp dyngen/numerics/ldlt.hpp dyngen/numerics/random.hpp
dyngen/numerics/reference.hpp Python.h pybind11/pybind11.h pybind11/numpy.h numpy/arrayobject.h
benchmark/benchmark.h nlohmann/json.hpp""".split()

# What identifier() can return, with or without a package's suffix (_rnea, _NQ): letters and
# digits in runs joined by single underscores, starting with a letter.
PRODUCIBLE = re.compile(r"[A-Za-z][A-Za-z0-9]*(?:_[A-Za-z0-9]+)*")
TOKEN = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
ERROR_LINE = re.compile(r"^probe\.(?:cpp|c):(\d+):\d+: error:", re.M)


def producible(name):
    return PRODUCIBLE.fullmatch(name) is not None


def include_flags():
    import numpy  # the module's dependency: its headers are in the package's include path

    paths = {sysconfig.get_paths()["include"], sysconfig.get_paths()["platinclude"],
             numpy.get_include(), os.path.join(ROOT, "runtime", "include"),
             os.path.join(ROOT, "numerics", "include")}
    eigen = subprocess.run(["pkg-config", "--cflags", "eigen3"], capture_output=True, text=True)
    if eigen.returncode != 0:
        sys.exit("reserved_names.py: pkg-config finds no eigen3 (libeigen3-dev)")
    return [f"-I{p}" for p in sorted(paths)] + eigen.stdout.split()


def start(command, cwd):
    return subprocess.Popen(command, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True)


def output(job, command):
    out, err = job.communicate()
    if job.returncode != 0:
        sys.exit(f"reserved_names.py: {' '.join(command)} failed:\n{err[:4000]}")
    return out


def probe_source(include, candidates, namespaces):
    """A file that declares each candidate on a line of its own after the headers, with a
    sentinel, a fresh name, every 64 lines; and the names of those lines.

    In C++, a namespace: GCC rejects it for a name declared at global scope as anything else. A
    name that the headers use for a namespace (somewhere) is declared an inline namespace, which
    GCC rejects for an existing namespace too (not declared inline); not every name, as each
    global inline namespace slows every later lookup. Braces keep a keyword's syntax error on
    its line. In C, an enumerator: GCC rejects it for every ordinary identifier at file scope
    (struct tags, a namespace of their own, are not probed: a package's only tag is
    NAME_JointTrig, its typedef's name)."""
    names, lines = [], [f'#include "{include}"\n']
    for k, name in enumerate(candidates):
        if k % 64 == 0:
            names.append(f"dyngen_probe_sentinel_{k}")
            lines.append(f"enum {{ {names[-1]} }};\n")
        names.append(name)
        if include.endswith(".h"):
            lines.append(f"enum {{ {name} }};\n")
        else:
            inline = "inline " if name in namespaces else ""
            lines.append(f'extern "C++" {{ {inline}namespace {name} {{}} }}\n')
    return "".join(lines), names


def rejected(job, names):
    """The names whose line (2 on) the compiler rejected."""
    _, err = job.communicate()
    lines = {int(n) for n in ERROR_LINE.findall(err)}
    if not lines or min(lines) < 2:
        sys.exit(f"reserved_names.py: the headers do not compile, or the probe rejects nothing:\n"
                 f"{err[:4000]}")
    found = {names[n - 2] for n in lines}
    if any(name.startswith("dyngen_probe_sentinel_") for name in found):
        sys.exit(f"reserved_names.py: the probe's errors spilled over onto the next lines:\n"
                 f"{err[:4000]}")
    return found


def probe(cxx, cc):
    """The reserved names, and how many tokens were probed."""
    with tempfile.TemporaryDirectory() as tmp:
        with open(os.path.join(tmp, "headers.hpp"), "w") as f:
            f.write("".join(f"#include <{h}>\n" for h in CXX_STANDARD + CXX_LIBRARIES))
            f.write("#if __has_include(<format>)\n#include <format>\n#endif\n")
        with open(os.path.join(tmp, "headers.h"), "w") as f:
            f.write("".join(f"#include <{h}.h>\n" for h in C_STANDARD))
            f.write("#include <dyngen/sincos.h>\n")
        # GNU modes: a user's build may use them, and they define more (linux, unix)
        flags = include_flags() + ["-DNDEBUG", "-pthread", "-w"]
        languages = [([cxx, "-std=gnu++20", "-x", "c++", *flags], "headers.hpp", "probe.cpp"),
                     ([cc, "-std=gnu17", "-x", "c", *flags], "headers.h", "probe.c")]
        # the headers' text with every #define, in both languages at once, and what GCC
        # predefines for 32-bit x86 (i386), which a probe on x86-64 does not see otherwise
        commands = [command + ["-E", "-P", "-dD", headers] for command, headers, _ in languages]
        commands.append([cc, "-m32", "-dM", "-E", "-x", "c", os.devnull])
        jobs = [start(command, tmp) for command in commands]
        texts = [output(job, command) for job, command in zip(jobs, commands)]
        define = re.compile(r"^#define ([A-Za-z_][A-Za-z0-9_]*)", re.M)
        macros = set().union(*(define.findall(text) for text in texts))
        namespaces = set(re.findall(r"\bnamespace\s+([A-Za-z_][A-Za-z0-9_]*)", texts[0]))

        probes = []
        for (command, headers, source_name), text in zip(languages, texts):
            candidates = sorted(t for t in set(TOKEN.findall(text))
                                if producible(t) and t not in macros)
            source, names = probe_source(headers, candidates, namespaces)
            with open(os.path.join(tmp, source_name), "w") as f:
                f.write(source)
            command = command + ["-fsyntax-only", "-fmax-errors=0",
                                 "-fno-diagnostics-show-caret", source_name]
            probes.append((start(command, tmp), names, len(candidates)))
        declared = set().union(*(rejected(job, names) for job, names, _ in probes))
        # the global inline namespaces, which the probe cannot see (inner ones too: no matter)
        declared |= set(re.findall(r"\binline\s+namespace\s+([A-Za-z_][A-Za-z0-9_]*)", texts[0]))
        reserved = {name for name in macros | declared if producible(name)}
        return reserved, sum(n for _, _, n in probes)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--check", action="store_true",
                        help="do not write: fail if the probe finds names the list lacks")
    parser.add_argument("--cxx", default="g++")
    parser.add_argument("--cc", default="gcc")
    parser.add_argument("--list", default=LIST)
    args = parser.parse_args()
    began = time.monotonic()
    found, candidates = probe(args.cxx, args.cc)
    with open(args.list) as f:
        listed = {line.strip() for line in f if line.strip() and not line.startswith("#")}
    missing = sorted(found - listed)
    seconds = time.monotonic() - began
    summary = (f"{len(found)} names reserved by the probe ({candidates} tokens probed, "
               f"{seconds:.1f} s); the list has {len(listed)}")
    if args.check:
        if missing:
            print(f"{summary}; it lacks {len(missing)}: {' '.join(missing)}\n"
                  "run scripts/reserved_names.py and commit generator/reserved_names.txt",
                  file=sys.stderr)
            return 1
        print(summary)
        return 0
    with open(args.list) as f:
        header = [line for line in f if line.startswith("#")]
    with open(args.list + ".tmp", "w") as f:
        f.writelines(header)
        f.writelines(f"{name}\n" for name in sorted(listed | found))
    os.replace(args.list + ".tmp", args.list)
    print(f"{summary}; added {len(missing)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

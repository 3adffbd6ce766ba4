"""The fuzz target of the Python module's argument parsing (tests/fuzz/README.md): fuzz_python.cpp
runs run(data) in an embedded interpreter, under libFuzzer or over the corpus, with the module
Scalar_dynamics (a pendulum, tests/python/hostile_pendulum.urdf) linked in.

run(data) makes one call of one of the module's functions from the bytes: the count of states;
each input's dtype, shape, values, layout and place in memory; threads; out=. A call whose
arguments are valid (README.md, "Python") must return the bits that the function gives for
C-ordered copies of the inputs on one thread, in the arrays given as out= if any, and leave the
inputs as they were unless an output shares their memory; any other call must raise TypeError or
ValueError. Either way the arguments' reference counts must be as before the call. Another
exception, a crash or a sanitizer report is a finding.
"""
import pickle
import re
import sys
import warnings

import numpy as np

import Scalar_dynamics as d

warnings.simplefilter("ignore", RuntimeWarning)  # casts of inf and nan to integers

# each function's inputs, from its signature, and its outputs' shapes for one state
FUNCTIONS = {}
for name in dir(d):
    doc = getattr(getattr(d, name), "__doc__", None) or ""
    match = re.match(rf"{name}\((.*), \*, threads", doc)
    if match and not name.startswith("_"):
        inputs = [p.split(":")[0] for p in match.group(1).split(", ")]
        one = getattr(d, name)(*(np.zeros(d.nq if x == "q" else d.nv, d.dtype) for x in inputs))
        FUNCTIONS[name] = (inputs, [y.shape for y in (one if isinstance(one, tuple) else (one,))])
NAMES = sorted(FUNCTIONS)
COUNTS = [None, 0, 1, 2, 3, 4, 5, 7, 8, 9, 16, 17, 31, 33, 64]  # None: one state
THREADS = [1, 1, 2, 3, 4, 7, 256, 257, 100_000, 2**31 - 1, 0, -1, -2**31, 2**31, 2**63]
DTYPES = [d.dtype, d.dtype, d.dtype.newbyteorder(), np.float32, np.float64, np.float16,
          np.longdouble, np.int64, np.complex128, object]
INPUT_LAYOUTS = ["new", "pool", "pool", "pool", "strided", "reversed", "fortran", "broadcast",
                 "misaligned", "readonly", "pickled", "list", "float"]  # a list, a float: refused
OUT_LAYOUTS = ["none", "new", "pool", "pool", "pool", "strided", "fortran", "readonly",
               "misaligned", "pickled", "list", "short", "same", "number"]
POOL_ITEMS = 1024


class Choices:
    """The fuzz bytes as a series of choices, each from one byte; the first option once they
    run out."""

    def __init__(self, data):
        self.data, self.at = data, 0

    def __call__(self, options):
        byte = self.data[self.at] if self.at < len(self.data) else 0
        self.at += 1
        return options[byte % len(options)]


def misaligned(x):
    """A copy of x that starts one byte past an item boundary (x of at least one item)."""
    y = np.empty(x.nbytes + 1, dtype=np.uint8)[1:].view(x.dtype).reshape(x.shape)
    y[...] = x
    return y


def place(choose, layout, values, pool):
    """values (a C-ordered array) in the layout: a new array, a view of the pool, a strided or
    reversed view, Fortran order, stride 0, misaligned, read-only, through pickle, as a list or
    a number."""
    if layout == "pool" and values.dtype == pool.dtype:
        start = choose(range(24))  # near the other arrays, to overlap them often
        view = pool[start:start + values.size].reshape(values.shape)
        view[...] = values
        return view
    if layout == "strided" and values.ndim > 0:
        wide = np.zeros((2 * values.shape[0],) + values.shape[1:], values.dtype)
        wide[::2] = values
        return wide[::2]
    if layout == "reversed" and values.ndim > 0:
        return values[::-1].copy()[::-1]
    if layout == "fortran":
        return np.asfortranarray(values)
    if layout == "broadcast" and values.ndim > 1 and len(values) > 0:
        return np.broadcast_to(values[choose(range(len(values)))], values.shape)
    if layout == "misaligned" and values.size > 0 and values.dtype != object:
        return misaligned(values)
    if layout == "readonly":
        values.setflags(write=False)
    if layout == "pickled":
        return pickle.loads(pickle.dumps(values))
    if layout == "list":
        return values.tolist()
    if layout == "float":
        return 1.5
    return values


def states_of(a, size):
    """The count of states of input a (None for one state) whose states have size entries; or
    "invalid" if it is not a NumPy array of the module's dtype and one of its shapes."""
    if not isinstance(a, np.ndarray):
        return "invalid"
    if not (a.dtype.kind == "f" and a.dtype.itemsize == d.dtype.itemsize and a.dtype.isnative):
        return "invalid"
    if a.shape == (size,):
        return None
    return a.shape[0] if a.ndim == 2 and a.shape[1] == size else "invalid"


def valid_out(y, shape):
    return (isinstance(y, np.ndarray) and y.dtype.kind == "f" and y.dtype.isnative and
            y.dtype.itemsize == d.dtype.itemsize and y.shape == shape and y.flags.c_contiguous
            and y.flags.aligned and y.flags.writeable)


def make_inputs(choose, inputs, count, pool):
    """The inputs, most of count states (None: one state), and their common count of states or
    "invalid"."""
    rng = np.random.default_rng(choose(range(256)))
    args, counts = [], set()
    for x in inputs:
        size = d.nq if x == "q" else d.nv
        n = count if choose([True] * 7 + [False]) else choose(COUNTS)
        shape = (size,) if n is None else (n, size)
        shape = choose([shape] * 5 + [shape[:-1] + (size + 1,), (1,) + shape, shape[1:]])
        values = np.asarray(rng.uniform(-3, 3, shape))
        odd = choose([np.nan, np.inf, -np.inf, 1e300])
        values[rng.random(shape) < choose([0, 0, 0.1, 0.5])] = odd
        args.append(place(choose, choose(INPUT_LAYOUTS), values.astype(choose(DTYPES)), pool))
        counts.add(states_of(args[-1], size))
    return args, counts.pop() if len(counts) == 1 else "invalid"


def make_out(choose, shapes, pool):
    """out= for outputs of the given shapes (the states included), and whether it is valid."""
    layout = choose(OUT_LAYOUTS)
    if layout == "none":
        return None, True
    arrays = [place(choose, layout, np.zeros(s, choose(DTYPES[:4])), pool) for s in shapes]
    if layout == "number":
        arrays = [2.0] * len(shapes)
    elif layout == "same":
        arrays = [arrays[0]] * len(shapes)
    if layout == "list":
        return arrays, False
    if layout == "short":
        return tuple(arrays[1:]), False
    if len(shapes) == 1:
        return arrays[0], valid_out(arrays[0], shapes[0])
    valid = all(valid_out(y, s) for y, s in zip(arrays, shapes))
    valid = valid and not any(np.may_share_memory(a, b)
                              for k, a in enumerate(arrays) for b in arrays[k + 1:])
    return tuple(arrays), valid


def check(name, args, out, result, before):
    """That the result of a valid call has the bits of the call on C-ordered copies of the inputs
    with one thread, in the arrays of out if given, and that inputs no output shares memory with
    are as they were."""
    f = getattr(d, name)
    expected = f(*before)
    expected, result = (x if isinstance(x, tuple) else (x,) for x in (expected, result))
    outs = () if out is None else out if isinstance(out, tuple) else (out,)
    for k, (r, e) in enumerate(zip(result, expected)):
        assert r.dtype == d.dtype and r.shape == e.shape and r.tobytes() == e.tobytes(), \
            f"{name}: output {k} differs from the one-thread call on C-ordered copies"
        assert not outs or r is outs[k], f"{name}: output {k} is not the array given as out"
    for x, b in zip(args, before):
        if not any(np.may_share_memory(x, y) for y in outs):
            assert np.asarray(x, dtype=d.dtype).tobytes() == b.tobytes(), \
                f"{name}: an input changed"


def run(data):
    choose = Choices(data)
    name = choose(NAMES)
    inputs, out_shapes = FUNCTIONS[name]
    pool = np.zeros(POOL_ITEMS, d.dtype)
    args, count = make_inputs(choose, inputs, choose(COUNTS), pool)
    threads = choose(THREADS)
    states = () if count in (None, "invalid") else (count,)
    out, valid = make_out(choose, [states + s for s in out_shapes], pool)
    valid = valid and count != "invalid" and 1 <= threads < 2**31
    given = args if choose([True] * 15 + [False]) else args[:-1]  # or an input missing
    valid = valid and len(given) == len(args)
    f = getattr(d, name)
    if choose([False, True]):
        call = lambda: f(**dict(zip(inputs, given)), threads=threads, out=out)
    else:
        call = lambda: f(*given, threads=threads, out=out)
    arguments = [x for x in args + list(out if isinstance(out, (tuple, list)) else [out])
                 if isinstance(x, np.ndarray)]
    references = [sys.getrefcount(x) for x in arguments]
    if valid:
        # C-ordered copies of the inputs as they are before the call, which may write over them
        before = [np.array(x, dtype=d.dtype) for x in args]
        check(name, args, out, call(), before)
    else:
        try:
            call()
            raise AssertionError(f"{name}: invalid arguments were accepted")
        except (TypeError, ValueError):
            pass
    assert [sys.getrefcount(x) for x in arguments] == references, f"{name}: a reference leaked"

"""Threaded batches: ``Model.eval``, ``sample`` and ``pdf`` over many elements equal the same
calls element by element, whatever the layout of the inputs (transposed, strided, broadcast),
the ``out=`` buffers or the number of threads; and a long threaded call still stops on Ctrl-C.

The batches run in chunks of 4096 rows over rayon's threads, in GIL-released steps of 2^20
rows: the sizes below cross both boundaries.
"""

import hashlib
import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import fastbrdf

CHUNK, STEP = 4096, 1 << 20
MODELS = {
    "ct-ggx": lambda: fastbrdf.Model("cook-torrance", d="ggx", alpha=0.3),  # a SIMD kernel
    "ct-beckmann": lambda: fastbrdf.Model("cook-torrance", alpha=0.2, f="schlick"),
    "gold": lambda: fastbrdf.Model("cook-torrance", d="ggx", alpha=0.3, metal="gold"),  # 3 channels
    "lambert": lambda: fastbrdf.Model("lambert"),
}
DTYPES = [np.float32, np.float64]


def hemisphere(rng, n, dtype=np.float64):
    """Unit vectors, most above the horizon (a few below, and a few near it: the zero rules)."""
    v = rng.normal(size=(n, 3))
    v[:, 2] = np.abs(v[:, 2]) - 0.1
    return (v / np.linalg.norm(v, axis=1, keepdims=True)).astype(dtype)


@pytest.fixture(scope="module")
def data():
    rng = np.random.default_rng(30)
    n = 3 * CHUNK + 101
    return {dt: (hemisphere(rng, n, dt), hemisphere(rng, n, dt), rng.random((n, 2)).astype(dt)) for dt in DTYPES}


def same(a, b):
    """Equal bit for bit (NaN included), of the same shape and dtype."""
    a, b = np.asarray(a), np.asarray(b)
    assert a.shape == b.shape and a.dtype == b.dtype
    np.testing.assert_array_equal(a.reshape(-1).view(np.uint8), b.reshape(-1).view(np.uint8))


# ---------------------------------------------------------------------------------------------
# Batches equal single elements.


@pytest.mark.parametrize("name", MODELS)
@pytest.mark.parametrize("dtype", DTYPES)
def test_batches_equal_element_by_element(name, dtype, data):
    m = MODELS[name]()
    wi, wo, u = data[dtype]
    idx = np.r_[0:40, CHUNK - 20 : CHUNK + 20, len(wi) - 40 : len(wi)]
    f = m.eval(wi, wo)
    wi_s, w_s, p_s = m.sample(wo, u)
    p = m.pdf(wo, wi)
    for i in idx:
        same(f[i], m.eval(wi[i], wo[i]))
        one = m.sample(wo[i], u[i])
        same(wi_s[i], one[0])
        same(w_s[i], one[1])
        same(p_s[i], one[2])
        same(p[i], m.pdf(wo[i], wi[i]))


@pytest.mark.parametrize("dtype, n", [(np.float32, STEP + 3 * CHUNK + 5), (np.float64, 9 * CHUNK + 5)])
def test_a_batch_equals_its_pieces(dtype, n):
    """Cut at lengths that are not multiples of the chunk (in float32 over more than one
    GIL-released step): the pieces' results, joined, are the whole call's."""
    rng = np.random.default_rng(7)
    wi, wo, u = hemisphere(rng, n, dtype), hemisphere(rng, n, dtype), rng.random((n, 2)).astype(dtype)
    m = MODELS["ct-ggx"]()
    cuts = sorted({0, 1, 4097, min(70001, n - 1), min(STEP - 3, n - 1), min(STEP + 9000, n - 1), n})
    whole = (m.eval(wi, wo), *m.sample(wo, u), m.pdf(wo, wi))
    parts = [(m.eval(wi[a:b], wo[a:b]), *m.sample(wo[a:b], u[a:b]), m.pdf(wo[a:b], wi[a:b]))
             for a, b in zip(cuts, cuts[1:])]
    for k, w in enumerate(whole):
        same(w, np.concatenate([p[k] for p in parts]))


# ---------------------------------------------------------------------------------------------
# Layouts: read in place or copied, the values are those of a C-contiguous copy.


def layouts(a):
    """``a`` (N, k) in other memory layouts holding the same values, by name."""
    twice = np.repeat(a, 2, axis=0)
    return {
        "fortran": np.asfortranarray(a),
        "transposed": np.ascontiguousarray(a.T).T,
        "strided": twice[::2],
        "reversed": np.ascontiguousarray(a[::-1])[::-1],
        "big-endian": a.astype(">" + a.dtype.str[1:]),  # another byte order: one copy
    }


@pytest.mark.parametrize("name", ["ct-ggx", "gold"])
@pytest.mark.parametrize("dtype", DTYPES)
def test_layouts_give_the_same_values(name, dtype, data):
    m = MODELS[name]()
    wi, wo, u = data[dtype]
    f, s, p = m.eval(wi, wo), m.sample(wo, u), m.pdf(wo, wi)
    lwi, lwo, lu = layouts(wi), layouts(wo), layouts(u)
    for label in lwi:
        a, b, c = lwi[label], lwo[label], lu[label]
        assert np.array_equal(a, wi) and np.array_equal(b, wo) and np.array_equal(c, u), label
        same(m.eval(a, b), f)
        for x, y in zip(m.sample(b, c), s):
            same(x, y)
        same(m.pdf(b, a), p)


@pytest.mark.parametrize("dtype", DTYPES)
def test_broadcast_inputs_equal_their_full_copies(dtype, data):
    m = MODELS["ct-ggx"]()
    wi, wo, u = data[dtype]
    n = len(wi)
    one_wo, one_u = wo[5], u[9]
    full_wo, full_u = np.tile(one_wo, (n, 1)), np.tile(one_u, (n, 1))
    same(m.eval(wi, one_wo), m.eval(wi, full_wo))
    for x, y in zip(m.sample(one_wo, u), m.sample(full_wo, u)):
        same(x, y)
    for x, y in zip(m.sample(wo, one_u), m.sample(wo, full_u)):
        same(x, y)
    same(m.pdf(one_wo, wi), m.pdf(full_wo, wi))
    # (A, 1, 3) against (B, 3): a broadcast the flat rows cannot view (one copy).
    a, b = wi[:64].reshape(8, 8, 3)[:, :1], wo[:8]
    same(m.eval(a, b), m.eval(np.broadcast_to(a, (8, 8, 3)).copy(), np.broadcast_to(b, (8, 8, 3)).copy()))


# ---------------------------------------------------------------------------------------------
# out=: the same values as fresh outputs, into the caller's buffers.


@pytest.mark.parametrize("name", ["ct-ggx", "gold", "lambert"])
@pytest.mark.parametrize("dtype", DTYPES)
def test_out_equals_fresh_outputs(name, dtype, data):
    m = MODELS[name]()
    wi, wo, u = data[dtype]
    n = len(wi)
    wshape = (n, 3) if m.channels == 3 else (n,)
    bufs = (np.full((n, 3), np.nan, dtype), np.full(wshape, np.nan, dtype), np.full(n, np.nan, dtype))
    got = m.sample(wo, u, out=bufs)
    assert got is bufs
    for x, y in zip(bufs, m.sample(wo, u)):
        same(x, y)
    p = np.full(n, np.nan, dtype)
    assert m.pdf(wo, wi, out=p) is p
    same(p, m.pdf(wo, wi))
    f = np.full(wshape, np.nan, dtype)
    assert m.eval(wi, wo, out=f) is f
    same(f, m.eval(wi, wo))


@pytest.mark.parametrize("dtype", DTYPES)
def test_out_may_be_an_input(dtype, data):
    m = MODELS["ct-ggx"]()
    wi, wo, u = (x.copy() for x in data[dtype])
    want_s, want_p = m.sample(wo, u), m.pdf(wo, wi)
    w = wo.copy()
    m.sample(w, u, out=(w, np.empty(len(w), dtype), np.empty(len(w), dtype)))
    same(w, want_s[0])
    p = wi[:, 0].copy()
    m.pdf(wo, wi, out=p)
    same(p, want_p)


def test_out_is_checked():
    m = MODELS["ct-ggx"]()
    wo, u = np.zeros((4, 3)), np.zeros((4, 2))
    wo[:, 2] = 1
    good = (np.zeros((4, 3)), np.zeros(4), np.zeros(4))
    with pytest.raises(TypeError, match="^out: expected a tuple of 3 numpy arrays"):
        m.sample(wo, u, out=good[0])
    with pytest.raises(TypeError, match=r"^out\[1\]: dtype float32, the result is float64"):
        m.sample(wo, u, out=(good[0], good[1].astype(np.float32), good[2]))
    with pytest.raises(ValueError, match=r"^out\[2\]: shape \(5,\), the result has shape \(4,\)"):
        m.sample(wo, u, out=(good[0], good[1], np.empty(5)))
    with pytest.raises(ValueError, match=r"^out\[0\]: must be C-contiguous"):
        m.sample(wo, u, out=(np.empty((3, 4)).T, good[1], good[2]))
    with pytest.raises(ValueError, match="^out: shape"):
        m.pdf(wo, wo, out=np.empty(3))
    ro = np.empty(4)
    ro.flags.writeable = False
    with pytest.raises(ValueError, match="^out: is read-only"):
        m.pdf(wo, wo, out=ro)


def test_reused_buffers_allocate_nothing():
    """A loop over chunks of a large batch into the same buffers: no array is allocated per
    call beyond small temporaries."""
    import tracemalloc

    m = MODELS["ct-ggx"]()
    rng = np.random.default_rng(3)
    n = 200_000
    wo, u = hemisphere(rng, n, np.float32), rng.random((n, 2)).astype(np.float32)
    bufs = (np.empty((n, 3), np.float32), np.empty(n, np.float32), np.empty(n, np.float32))
    p = np.empty(n, np.float32)
    m.sample(wo, u, out=bufs)
    m.pdf(wo, bufs[0], out=p)
    tracemalloc.start()
    for _ in range(3):
        m.sample(wo, u, out=bufs)
        m.pdf(wo, bufs[0], out=p)
        m.eval(bufs[0], wo, out=p)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert peak < n, f"{peak} bytes allocated for {n} elements"


# ---------------------------------------------------------------------------------------------
# Threads: the same bits on 1 thread and on several.

DIGEST = """
import hashlib, numpy as np, fastbrdf
rng = np.random.default_rng(11)
n = 5 * 4096 + 77
h = hashlib.sha256()
for dt in (np.float32, np.float64):
    v = rng.normal(size=(2, n, 3)); v[..., 2] = np.abs(v[..., 2])
    wi, wo = (x.astype(dt) for x in v)
    u = rng.random((n, 2)).astype(dt)
    for m in (fastbrdf.Model("cook-torrance", d="ggx", alpha=0.3), fastbrdf.Model("ward", alpha=0.2)):
        for a in (m.eval(wi, wo), *m.sample(wo, u), m.pdf(wo, wi)):
            h.update(np.ascontiguousarray(a).tobytes())
print(h.hexdigest())
"""


def test_results_do_not_depend_on_the_thread_count():
    digests = set()
    for threads in (1, 2, 5):
        env = dict(os.environ, RAYON_NUM_THREADS=str(threads))
        p = subprocess.run([sys.executable, "-c", textwrap.dedent(DIGEST)], capture_output=True, text=True,
                           timeout=120, env=env)
        assert p.returncode == 0, p.stderr[-2000:]
        digests.add(p.stdout.strip())
    assert len(digests) == 1, digests


# ---------------------------------------------------------------------------------------------
# Ctrl-C: a long threaded sample stops between its steps.


def test_a_long_threaded_sample_stops_on_ctrl_c():
    code = """
    import os, signal, threading, time
    import numpy as np
    import fastbrdf

    m = fastbrdf.Model("cook-torrance", alpha=0.3)   # Beckmann: the scalar sampler per element
    wo, u = np.array([0.3, 0.0, 0.95]), np.array([0.3, 0.6])   # broadcast: read in place
    t0 = time.perf_counter()
    m.sample(wo, np.broadcast_to(u, (2_000_000, 2)))
    per = (time.perf_counter() - t0) / 2_000_000
    n = int(min(4e8, max(2e7, 4.0 / per)))
    u = np.broadcast_to(u, (n, 2))
    t0 = time.perf_counter()
    threading.Timer(0.2, lambda: os.kill(os.getpid(), signal.SIGINT)).start()
    try:
        m.sample(wo, u)   # untouched output pages: written only until the interrupt
    except KeyboardInterrupt:
        print("interrupted", time.perf_counter() - t0, n * per)
    else:
        print("finished", time.perf_counter() - t0, n * per)
    """
    p = subprocess.run([sys.executable, "-c", textwrap.dedent(code)], capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stderr[-2000:]
    word, seconds, whole = p.stdout.split()
    assert float(whole) > 1.0, f"the call is too short to tell ({whole} s)"
    assert word == "interrupted" and float(seconds) < 0.2 + float(whole) / 4, p.stdout

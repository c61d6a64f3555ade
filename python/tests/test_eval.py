"""Model, eval, info, models(): values against independent numpy formulas and the CLI, and
the documented array rules (dtypes, shapes, contiguity, broadcasting, NaN)."""

import json
import tracemalloc

import numpy as np
import pytest

import fastbrdf

RNG = np.random.default_rng(17)


def unit(v):
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def hemisphere(n):
    """n random directions with z >= 0.05 (f64)."""
    v = unit(RNG.normal(size=(n, 3)))
    v[:, 2] = np.abs(v[:, 2]) + 0.05
    return unit(v)


def test_models_is_the_cli_json(cli):
    rc, out, _ = cli("models", "--json")
    assert rc == 0
    assert fastbrdf.models() == json.loads(out)["models"]
    rc, out, _ = cli("models", "--json", "--kind", "brdf")
    assert fastbrdf.models("brdf") == json.loads(out)["models"]


def test_models_shape_and_info():
    ms = fastbrdf.models()
    ids = [m["id"] for m in ms]
    assert len(ids) == len(set(ids)) > 10
    m = fastbrdf.Model("ggx", alpha=0.3)
    assert m.info == next(x for x in ms if x["id"] == "ggx")
    assert {"formula", "source", "bounds", "ops", "f32_bound", "params"} <= set(m.info)
    with pytest.raises(ValueError, match="kind 'nope'"):
        fastbrdf.models("nope")


def test_pow_lobe_equals_numpy():
    c = np.linspace(0, 1, 1001)
    for n in (1, 20, 1000):
        m = fastbrdf.Model("pow", n=n)
        np.testing.assert_allclose(m.eval(c, precision="f64"), c**n, rtol=1e-12, atol=1e-300)
        c32 = c.astype(np.float32)
        ref = c32.astype(np.float64) ** n
        v32 = m.eval(c32)
        assert v32.dtype == np.float32
        err = np.abs(v32 - ref) / np.maximum(1, ref)
        assert err.max() <= m.info["f32_bound"]


def test_ggx_distribution_equals_numpy():
    a = 0.3
    c = np.linspace(0.01, 1, 500)
    d = a * a / (np.pi * (c * c * (a * a - 1) + 1) ** 2)
    np.testing.assert_allclose(fastbrdf.Model("ggx", alpha=a).eval(c, precision="f64"), d, rtol=1e-12)


def test_cook_torrance_ggx_equals_numpy():
    a = 0.25
    m = fastbrdf.Model("cook-torrance", alpha=a, d="ggx", g="smith-ggx-correlated", f="none")
    wi, wo = hemisphere(400), hemisphere(400)
    h = unit(wi + wo)

    def lam(w):
        t2 = (1 - w[:, 2] ** 2) / w[:, 2] ** 2
        return (-1 + np.sqrt(1 + a * a * t2)) / 2

    ch = h[:, 2]
    d = a * a / (np.pi * (ch * ch * (a * a - 1) + 1) ** 2)
    g = 1 / (1 + lam(wi) + lam(wo))
    ref = d * g / (4 * wi[:, 2] * wo[:, 2])
    np.testing.assert_allclose(m.eval(wi, wo, precision="f64"), ref, rtol=1e-9)
    # Unnormalised directions give the same values (the BRDF normalises).
    np.testing.assert_allclose(m.eval(3 * wi, 0.5 * wo, precision="f64"), ref, rtol=1e-9)


@pytest.mark.parametrize(
    "id, params",
    [("flog", {"n": 200}), ("cubic", {"n": 50}), ("fresnel-schlick", {}), ("beckmann", {"alpha": 0.2})],
)
def test_f32_within_documented_bound_of_f64(id, params):
    m = fastbrdf.Model(id, **params)
    c = np.linspace(0, 1, 20001, dtype=np.float32)
    v32, v64 = m.eval(c), m.eval(c.astype(np.float64), precision="f64")
    assert v32.dtype == np.float32 and v64.dtype == np.float64
    assert (np.abs(v32 - v64) / np.maximum(1, np.abs(v64))).max() <= m.info["f32_bound"]


def test_brdf_f32_within_documented_bound_of_f64():
    m = fastbrdf.Model("cook-torrance", alpha=0.2, d="ggx", g="smith-ggx-correlated", f="schlick")
    assert m.simd
    wi, wo = hemisphere(5000).astype(np.float32), hemisphere(5000).astype(np.float32)
    v32, v64 = m.eval(wi, wo), m.eval(wi.astype(np.float64), wo.astype(np.float64), precision="f64")
    assert (np.abs(v32 - v64) / np.maximum(1, np.abs(v64))).max() <= m.info["f32_bound"]


def test_eval_matches_cli(cli):
    c = [0.0, 0.5, 0.93, 0.999, 1.0]
    rc, out, _ = cli(
        "eval", "--model", "flog", "--param", "n=20", "--precision", "f64",
        stdin="cos\n" + "\n".join(map(repr, c)) + "\n",
    )
    assert rc == 0
    values = [float(line.split(",")[1]) for line in out.strip().splitlines()[1:]]
    np.testing.assert_array_equal(fastbrdf.Model("flog", n=20).eval(c, precision="f64"), values)


def test_broadcasting():
    m = fastbrdf.Model("phong", n=30)
    wi = hemisphere(4).reshape(4, 1, 3)
    wo = hemisphere(5)
    v = m.eval(wi, wo, precision="f64")
    assert v.shape == (4, 5)
    for i in range(4):
        for j in range(5):
            assert v[i, j] == m.eval(wi[i, 0], wo[j], precision="f64")
    # One direction against many; a scalar input gives a numpy scalar.
    assert m.eval([0, 0, 1], wo).shape == (5,)
    s = fastbrdf.Model("pow", n=2).eval(0.5)
    assert isinstance(s, np.float64) and s == 0.25
    s = fastbrdf.Model("pow", n=2).eval(np.float32(0.5))
    assert isinstance(s, np.float32) and s == 0.25
    # Two-input kinds broadcast too (env: cos_v, alpha).
    e = fastbrdf.Model("env-brdf-approx")
    assert e.eval(np.linspace(0.1, 1, 7)[:, None], np.array([0.1, 0.5])).shape == (7, 2)
    with pytest.raises(ValueError, match=r"shapes do not broadcast: wi \(4,\), wo \(5,\)"):
        m.eval(np.zeros((4, 3)), np.zeros((5, 3)))


def _peak_traced_bytes(f):
    tracemalloc.start()
    try:
        f()
        return tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def test_contiguous_f32_is_not_copied():
    """numpy reports its allocations to tracemalloc, the output's (numpy allocates it) among
    them: a copy of the input would show on top of the output; reading it in place does not."""
    m = fastbrdf.Model("flog", n=20)
    x = RNG.random(4_000_000, dtype=np.float32)
    wi = hemisphere(1_000_000).astype(np.float32)
    assert _peak_traced_bytes(lambda: m.eval(x)) < x.nbytes + 1_000_000
    b = fastbrdf.Model("cook-torrance", d="ggx")
    assert _peak_traced_bytes(lambda: b.eval(wi, wi)) < 4 * len(wi) + 1_000_000
    # The same measure sees the documented copies (so it can fail): half the input copied and
    # half an output; the input as float64 and a float64 output.
    assert _peak_traced_bytes(lambda: m.eval(x[::2])) >= x.nbytes
    assert _peak_traced_bytes(lambda: m.eval(x, precision="f64")) >= 4 * x.nbytes


def test_non_contiguous_input_is_copied_and_correct():
    m = fastbrdf.Model("beckmann", alpha=0.3)
    x = RNG.random(1000, dtype=np.float32)
    np.testing.assert_array_equal(m.eval(x[::3]), m.eval(np.ascontiguousarray(x[::3])))
    b = fastbrdf.Model("ward", alpha=0.3)
    w = np.asfortranarray(hemisphere(100).astype(np.float32))
    assert not w.flags.c_contiguous
    np.testing.assert_array_equal(b.eval(w, w[::-1]), b.eval(np.ascontiguousarray(w), np.ascontiguousarray(w[::-1])))


def test_dtype_rules():
    m = fastbrdf.Model("pow", n=3)
    assert m.eval(np.array([1, 0], dtype=np.int64)).tolist() == [1.0, 0.0]
    # precision=None keeps the inputs' float dtype (numpy's promotion; integers give float64).
    assert m.eval(np.array([0.5], dtype=np.float64)).dtype == np.float64
    assert m.eval(np.array([0.5], dtype=np.float32)).dtype == np.float32
    assert m.eval(np.array([0.5], dtype=np.float16)).dtype == np.float32
    assert m.eval(np.array([1], dtype=np.int32)).dtype == np.float64
    assert m.eval([0.5]).dtype == np.float64
    # The f64 path evaluates in float64: a value float32 cannot hold survives.
    tiny = np.array([1e-20])
    assert m.eval(tiny)[0] == pytest.approx(1e-60, rel=1e-12)
    assert m.eval(tiny, precision="f32")[0] == 0
    # Asked explicitly, the precision wins.
    assert m.eval(np.array([0.5], dtype=np.float64), precision="f32").dtype == np.float32
    assert m.eval(np.array([0.5], dtype=np.float32), precision="f64").dtype == np.float64
    b = fastbrdf.Model("lambert")
    d32 = np.array([[0, 0, 1]], dtype=np.float32)
    assert b.eval(d32, d32).dtype == np.float32 and b.eval(d32, d32.astype(np.float64)).dtype == np.float64
    assert b.pdf(d32, d32).dtype == np.float32 and b.sample(d32, [[0.5, 0.5]])[1].dtype == np.float32
    for bad in (np.array([True]), np.array([1j]), np.array(["0.5"]), np.array([None])):
        with pytest.raises(TypeError, match=f"cos: dtype {bad.dtype} is not supported"):
            m.eval(bad)
    with pytest.raises(ValueError, match="precision 'f16': expected f32 or f64"):
        m.eval(0.5, precision="f16")


def test_shape_rules():
    b = fastbrdf.Model("lambert")
    with pytest.raises(ValueError, match=r"wi: expected shape \(\.\.\., 3\), got \(4, 2\)"):
        b.eval(np.zeros((4, 2)), np.zeros((4, 3)))
    with pytest.raises(TypeError, match="eval\\(wi, wo\\) takes two arrays"):
        b.eval(np.zeros(3))
    with pytest.raises(TypeError, match="eval takes cos, got 2"):
        fastbrdf.Model("pow").eval(0.5, 0.5)
    assert fastbrdf.Model("pow").eval(np.zeros((0,))).shape == (0,)


def test_nan_rule():
    for precision in ("f32", "f64"):
        lobe = fastbrdf.Model("flog", n=20)
        assert lobe.eval([np.nan], precision=precision).tolist() == [0.0]
        brdf = fastbrdf.Model("cook-torrance", d="ggx")
        assert brdf.eval([np.nan, 0, 1], [0, 0, 1], precision=precision) == 0
        assert brdf.eval([0, 0, 0], [0, 0, 1], precision=precision) == 0
        assert brdf.eval([0, 0, -1], [0, 0, 1], precision=precision) == 0
        f = fastbrdf.Model("fresnel-schlick", f0=0.04)
        assert f.eval(np.nan, precision=precision) == f.eval(0.0, precision=precision)
        # Lobes clamp their cosine to [0, 1].
        assert lobe.eval(1.5, precision=precision) == lobe.eval(1.0, precision=precision)


@pytest.mark.parametrize(
    "id, params, args",
    [
        ("nope", {}, ["--model", "nope"]),
        ("flog", {"q": 1}, ["--model", "flog", "--param", "q=1"]),
        ("flog", {"n": 0}, ["--model", "flog", "--param", "n=0"]),
        ("cook-torrance", {"d": "ggx", "ms": "filament", "g": "smith"},
         ["--model", "cook-torrance", "--param", "d=ggx", "--param", "ms=filament", "--param", "g=smith"]),
    ],
)
def test_errors_carry_the_cli_message(cli, id, params, args):
    with pytest.raises(ValueError) as e:
        fastbrdf.Model(id, **params)
    rc, out, err = cli("eval", *args, stdin="cos\n1\n")
    assert rc == 2 and out == ""
    assert err.strip() == f"error: {e.value}"


def test_parameter_value_types():
    assert fastbrdf.Model("pow", n=np.float32(20)).eval(1.0) == 1.0
    with pytest.raises(TypeError, match="parameter n: expected a number or a string, got bool"):
        fastbrdf.Model("pow", n=True)
    with pytest.raises(TypeError, match="got dict"):
        fastbrdf.Model("pow", n={})
    # A list or tuple is one value per colour channel (R, G, B), as the CLI's R,G,B.
    with pytest.raises(ValueError, match=r"parameter n: a sequence is one value per colour channel \(R, G, B\): expected 3 values, got 1"):
        fastbrdf.Model("pow", n=[1])


def test_shadowing_scalar_path_equals_numpy():
    """Shadowing terms have no batch kernel: f32 and f64 both run the scalar model."""
    a = 0.4
    m = fastbrdf.Model("smith-ggx", alpha=a)
    assert m.inputs == (["cos_v"], ["cos_l"]) and not m.simd
    cv, cl = np.linspace(0.05, 1, 50), np.linspace(1, 0.05, 50)

    def g1(c):
        return 2 * c / (c + np.sqrt(a * a + (1 - a * a) * c * c))

    np.testing.assert_allclose(m.eval(cv, precision="f64"), g1(cv), rtol=1e-12)
    np.testing.assert_allclose(m.eval(cv, cl, precision="f64"), g1(cv) * g1(cl), rtol=1e-12)
    np.testing.assert_allclose(m.eval(cv, cl), g1(cv) * g1(cl), rtol=1e-6)
    assert m.eval(cv[:, None], cl[None, :]).shape == (50, 50)


def test_eval_releases_the_gil():
    """While one thread evaluates, another keeps running Python: the longest pause the main
    thread sees is far shorter than the call (holding the GIL, it would be the whole call)."""
    import threading
    import time

    m = fastbrdf.Model("cook-torrance", alpha=0.3)
    w = hemisphere(100_000)
    n = 1
    while True:  # a call long enough to see (at most 3.2e6 pairs, 77 MB)
        ws = np.tile(w, (n, 1))
        t0 = time.perf_counter()
        m.eval(ws, ws, precision="f64")
        call = time.perf_counter() - t0
        if call > 0.2 or n >= 32:
            break
        n *= 2
    assert call > 0.05
    t = threading.Thread(target=lambda: m.eval(ws, ws, precision="f64"))
    last, gap = time.perf_counter(), 0.0
    t.start()
    while t.is_alive():
        now = time.perf_counter()
        gap, last = max(gap, now - last), now
    t.join()
    assert gap < call / 3, (gap, call)

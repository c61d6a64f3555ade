"""Per-element parameters (``fastbrdf.Model(id, alpha=array)``): every element equals the
model built for its values (bit for bit, f32 and f64), broadcasting, colour channels,
checks at construction, the dtype rule, ``out=``, pickling and equality, Ctrl-C."""

import os
import pickle
import signal
import threading

import numpy as np
import pytest

import fastbrdf

RNG = np.random.default_rng(29)


def per_value(id, arrays, inputs, precision, **scalars):
    """The reference: a ``Model`` built per distinct value set, evaluated on its elements.
    ``arrays`` and ``inputs`` are already broadcast to one shape (inputs may have a last
    axis of 3)."""
    names = list(arrays)
    shape = arrays[names[0]].shape
    keys = np.stack([arrays[k].reshape(-1) for k in names], axis=-1)
    flat_in = [x.reshape(int(np.prod(shape)), -1) if x.ndim > len(shape) else x.reshape(-1) for x in inputs]
    out = None
    for key in np.unique(keys, axis=0):
        sel = np.all(keys == key, axis=-1)
        m = fastbrdf.Model(id, **scalars, **{k: float(v) for k, v in zip(names, key)})
        v = m.eval(*[x[sel] for x in flat_in], precision=precision)
        if out is None:
            out = np.empty((sel.size,) + v.shape[1:], dtype=v.dtype)
        out[sel] = v
    return out.reshape(shape + out.shape[1:])


def levels(n, count, lo, hi, dtype=np.float32):
    return np.linspace(lo, hi, count).astype(dtype)[RNG.integers(0, count, n)]


def dirs(shape, dtype):
    w = RNG.normal(size=shape + (3,)).astype(dtype)
    w[..., 2] = np.abs(w[..., 2])
    return w


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_distribution_equals_a_model_per_value(dtype):
    n = 40_000  # several blocks (16384), in parallel where the pool has threads
    alpha = levels(n, 200, 0.01, 1.0, dtype)
    cos = RNG.uniform(-0.1, 1.0, n).astype(dtype)
    got = fastbrdf.Model("ggx", alpha=alpha).eval(cos)
    assert got.dtype == dtype and got.shape == (n,)
    want = per_value("ggx", {"alpha": alpha}, [cos], None)
    np.testing.assert_array_equal(got, want)


@pytest.mark.parametrize("precision", ["f32", "f64"])
def test_lobe_shadowing_fresnel_and_all_distinct_values(precision):
    dt = np.float32 if precision == "f32" else np.float64
    n = 3000
    c = RNG.uniform(0, 1, n).astype(dt)
    for id, name, lo, hi in (("flog", "n", 1.0, 200.0), ("fresnel-schlick", "f0", 0.0, 1.0)):
        vals = RNG.uniform(lo, hi, n).astype(dt)  # all distinct
        got = fastbrdf.Model(id, **{name: vals}).eval(c)
        np.testing.assert_array_equal(got, per_value(id, {name: vals}, [c], precision))
    # A shadowing term (no kernel: the scalar model per group), two columns.
    info = [m for m in fastbrdf.models() if m["kind"] == "shadowing" and any(p["type"] == "number" for p in m["params"])]
    assert info, "a shadowing term with a numeric parameter"
    m0 = info[0]
    p = next(p for p in m0["params"] if p["type"] == "number")
    vals = levels(n, 7, p["min"] + 0.01 * (p["max"] - p["min"]), p["min"] + 0.5 * (p["max"] - p["min"]), dt)
    model = fastbrdf.Model(m0["id"], **{p["name"]: vals})
    req, _ = model.inputs
    cols = [RNG.uniform(0.05, 1, n).astype(dt) for _ in req]
    np.testing.assert_array_equal(model.eval(*cols), per_value(m0["id"], {p["name"]: vals}, cols, precision))


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_brdf_map_broadcasts_with_directions(dtype):
    h, w = 40, 30
    alpha = levels(h * w, 16, 0.05, 0.9, dtype).reshape(h, w)
    wi, wo = dirs((h, w), dtype), dirs((h, w), dtype)
    m = fastbrdf.Model("cook-torrance", d="ggx", alpha=alpha)
    got = m.eval(wi, wo)
    assert got.shape == (h, w) and got.dtype == dtype
    np.testing.assert_array_equal(got, per_value("cook-torrance", {"alpha": alpha}, [wi, wo], None, d="ggx"))
    # One direction pair against a row of values: the result takes the values' shape.
    a = alpha[0]
    one = fastbrdf.Model("cook-torrance", d="ggx", alpha=a).eval(wi[0, 0], wo[0, 0])
    assert one.shape == (w,)
    for j in (0, 7, w - 1):
        ref = fastbrdf.Model("cook-torrance", d="ggx", alpha=float(a[j])).eval(wi[0, 0], wo[0, 0])
        assert one[j] == ref


def test_two_parameters_and_exact_smith_path():
    n = 5000
    alpha = levels(n, 5, 0.1, 0.6)
    f0 = levels(n, 3, 0.02, 0.9)
    wi, wo = dirs((n,), np.float32), dirs((n,), np.float32)
    # Beckmann with the exact Smith term: a kernel with no SIMD (scalar fallback).
    m = fastbrdf.Model("cook-torrance", f="schlick", alpha=alpha, f0=f0)
    got = m.eval(wi, wo)
    want = per_value("cook-torrance", {"alpha": alpha, "f0": f0}, [wi, wo], None, f="schlick")
    np.testing.assert_array_equal(got, want)


@pytest.mark.parametrize("precision", ["f32", "f64"])
def test_metal_has_three_channels(precision):
    dt = np.float32 if precision == "f32" else np.float64
    n = 300
    alpha = levels(n, 4, 0.1, 0.5, dt)
    wi, wo = dirs((n,), dt), dirs((n,), dt)
    m = fastbrdf.Model("cook-torrance", alpha=alpha, metal="gold")
    assert m.channels == 3
    got = m.eval(wi, wo)
    assert got.shape == (n, 3)
    for v in np.unique(alpha):
        sel = alpha == v
        ref = fastbrdf.Model("cook-torrance", alpha=float(v), metal="gold").eval(wi[sel], wo[sel])
        np.testing.assert_array_equal(got[sel], ref)


def test_values_are_checked_at_construction():
    with pytest.raises(ValueError, match=r"model 'ggx': parameter alpha\[1, 2\] = 7 is invalid: expected a number in"):
        fastbrdf.Model("ggx", alpha=np.array([[0.1, 0.2, 0.3], [0.1, 0.2, 7.0]]))
    with pytest.raises(ValueError, match=r"parameter n\[3\] = NaN is invalid"):
        fastbrdf.Model("flog", n=np.array([1.0, 2.0, 3.0, np.nan, np.inf]))
    with pytest.raises(ValueError, match=r"parameter n\[0\] = 0 is invalid"):
        fastbrdf.Model("flog", n=np.zeros(3, dtype=np.float32))
    with pytest.raises(TypeError, match=r"parameter d is a choice"):
        fastbrdf.Model("cook-torrance", d=np.array([1.0, 2.0]))
    with pytest.raises(ValueError, match=r"model 'ggx' has no parameter 'q'"):
        fastbrdf.Model("ggx", q=np.array([0.1]))
    with pytest.raises(TypeError, match=r"alpha: dtype"):
        fastbrdf.Model("ggx", alpha=np.array([True, False]))
    # Every channel of a coloured model is checked (the message is the library's).
    with pytest.raises(ValueError, match=r"parameter alpha\[0\] = -1 is invalid"):
        fastbrdf.Model("cook-torrance", alpha=np.array([-1.0]), metal="gold")


def test_dtype_rule_out_and_empty():
    alpha = np.array([0.1, 0.2, 0.3], dtype=np.float32)
    c32 = np.array([0.5, 0.7, 0.9], dtype=np.float32)
    m = fastbrdf.Model("ggx", alpha=alpha)
    assert m.eval(c32).dtype == np.float32
    # The parameter arrays do not count in the dtype rule (their values are used exactly):
    # float32 directions with a float64 map evaluate in f32, each element's model built from
    # the exact float64 value.
    a64 = np.array([0.1, 0.2, 0.3])
    m64 = fastbrdf.Model("ggx", alpha=a64)
    v = m64.eval(c32)
    assert v.dtype == np.float32
    for i, a in enumerate(a64):
        assert v[i] == fastbrdf.Model("ggx", alpha=float(a)).eval(c32[i])
    assert m.eval(c32, precision="f64").dtype == np.float64
    out = np.empty(3, dtype=np.float32)
    assert m.eval(c32, out=out) is out
    np.testing.assert_array_equal(out, m.eval(c32))
    with pytest.raises(TypeError, match="out: dtype"):
        m.eval(c32, out=np.empty(3))
    with pytest.raises(ValueError, match="shapes do not broadcast"):
        m.eval(np.ones(4, dtype=np.float32))
    e = fastbrdf.Model("ggx", alpha=np.empty(0, dtype=np.float32))
    assert e.eval(np.ones(0, dtype=np.float32)).shape == (0,)


def test_pickle_equality_and_repr():
    a = np.array([[0.1, 0.2], [0.3, 0.4]], dtype=np.float32)
    m = fastbrdf.Model("cook-torrance", alpha=a, metal="gold")
    back = pickle.loads(pickle.dumps(m))
    assert back == m and hash(back) == hash(m)
    w = dirs((2, 2), np.float32)
    np.testing.assert_array_equal(back.eval(w, w), m.eval(w, w))
    assert fastbrdf.Model("ggx", alpha=a) != fastbrdf.Model("ggx", alpha=a + np.float32(0.1))
    # Equal by value: the same values in another dtype are the same model.
    assert fastbrdf.Model("ggx", alpha=a) == fastbrdf.Model("ggx", alpha=a.astype(np.float64))
    r = eval(repr(m), {"fastbrdf": fastbrdf, "np": np})
    assert r == m


def test_model_sample_and_pdf_take_arrays():
    """Model.sample and Model.pdf with a per-element alpha equal a Model per value (the hook
    of _model.py), the other colour channels' weights included."""
    alpha = np.array([0.1, 0.3, 0.6])
    wo = dirs((3,), np.float64)
    u = np.random.default_rng(3).random((3, 2))
    for metal in (None, "gold"):
        m = fastbrdf.Model("cook-torrance", d="ggx", alpha=alpha, metal=metal)
        wi, w, p = m.sample(wo, u)
        assert p.shape == (3,) and w.shape == ((3,) if metal is None else (3, 3))
        np.testing.assert_allclose(m.pdf(wo, wi), p, rtol=1e-12)  # pdf() recomputes: rounding
        for i, a in enumerate(alpha):
            one = fastbrdf.Model("cook-torrance", d="ggx", alpha=float(a), metal=metal)
            wi1, w1, p1 = one.sample(wo[i], u[i])
            np.testing.assert_allclose(wi[i], wi1, rtol=1e-12)
            np.testing.assert_allclose(p[i], p1, rtol=1e-12)
            np.testing.assert_allclose(w[i], w1, rtol=1e-12)


def test_native_checks_lengths():
    from fastbrdf import _fastbrdf as native

    h = fastbrdf.Model("ggx")._handle
    out = np.empty(3, dtype=np.float32)
    with pytest.raises(ValueError, match="params: alpha has 2 values, the output has 3"):
        native.perelement_eval_f32(h, ["alpha"], [np.ones(2) * 0.3], [np.ones(3, dtype=np.float32)], out)
    with pytest.raises(ValueError, match="cols: column 0 has 2 values"):
        native.perelement_eval_f32(h, ["alpha"], [np.ones(3) * 0.3], [np.ones(2, dtype=np.float32)], out)
    with pytest.raises(TypeError, match="cols: model 'ggx' takes"):
        native.perelement_eval_f32(h, ["alpha"], [np.ones(3) * 0.3], [], out)


def test_long_run_stops_on_ctrl_c():
    # All-distinct values build a model per element (microseconds each): 4M of them run
    # for many seconds; SIGINT after 0.3 s must stop it with KeyboardInterrupt.
    n = 1 << 22
    alpha = np.linspace(0.01, 1.0, n, dtype=np.float64)
    m = fastbrdf.Model("ggx", alpha=alpha)
    cos = np.full(n, 0.5)
    timer = threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            m.eval(cos)
    finally:
        timer.cancel()


def test_docstring_examples():
    import doctest

    from fastbrdf import _perelement

    r = doctest.testmod(_perelement, extraglobs={"np": np, "fastbrdf": fastbrdf}, optionflags=doctest.ELLIPSIS)
    assert r.failed == 0 and r.attempted >= 5


@pytest.mark.parametrize("precision", ["f32", "f64"])
def test_blocks_with_one_value(precision):
    # The first block (16384 elements) has one value, the rest another: the single-value
    # paths (columns read in place, directions deinterleaved without a scatter).
    dt = np.float32 if precision == "f32" else np.float64
    n = 20_000
    alpha = np.where(np.arange(n) < 16384, 0.2, 0.5).astype(dt)
    wi, wo = dirs((n,), dt), dirs((n,), dt)
    c = RNG.uniform(0, 1, n).astype(dt)
    np.testing.assert_array_equal(
        fastbrdf.Model("cook-torrance", d="ggx", alpha=alpha).eval(wi, wo),
        per_value("cook-torrance", {"alpha": alpha}, [wi, wo], precision, d="ggx"),
    )
    np.testing.assert_array_equal(fastbrdf.Model("ggx", alpha=alpha).eval(c), per_value("ggx", {"alpha": alpha}, [c], precision))


@pytest.mark.parametrize("precision", ["f32", "f64"])
def test_sample_and_pdf_hooks_equal_a_model_per_value(precision):
    # The hooks Model.sample / Model.pdf call with array parameters (_perelement.sample, pdf).
    from fastbrdf import _perelement

    dt = np.float32 if precision == "f32" else np.float64
    n = 3000
    alpha = levels(n, 6, 0.05, 0.8, dt)
    wo = dirs((n,), dt)
    wo /= np.linalg.norm(wo, axis=-1, keepdims=True)
    u = RNG.uniform(0, 1, (n, 2)).astype(dt)
    h = fastbrdf.Model("cook-torrance", d="ggx")._handle
    wi, w, p = _perelement.sample(h, {"alpha": alpha.astype(np.float64)}, wo, u, "auto", precision)
    wi = wi.reshape(n, 3)
    q = _perelement.pdf(h, {"alpha": alpha.astype(np.float64)}, wo, wi, "auto", precision)
    for v in np.unique(alpha):
        sel = alpha == v
        m = fastbrdf.Model("cook-torrance", d="ggx", alpha=float(v))
        rwi, rw, rp = m.sample(wo[sel], u[sel])
        np.testing.assert_array_equal(wi[sel], rwi)
        np.testing.assert_array_equal(w[sel], rw)
        np.testing.assert_array_equal(p[sel], rp)
        np.testing.assert_array_equal(q[sel], m.pdf(wo[sel], wi[sel]))
    with pytest.raises(ValueError, match=r"u: 1 \(row 0, column 0\) is outside \[0, 1\)"):
        _perelement.sample(h, {"alpha": np.full(1, 0.3)}, wo[:1], np.ones((1, 2), dt), "auto", precision)
    with pytest.raises(ValueError, match="strategy 'nope'"):
        _perelement.pdf(h, {"alpha": np.full(1, 0.3)}, wo[:1], wo[:1], "nope", precision)


def _inputs(model, n, dt):
    if model.kind == "brdf":
        return [dirs((n,), dt), dirs((n,), dt)]
    req, _ = model.inputs
    return [RNG.uniform(0.02, 1.0, n).astype(dt) for _ in req]


@pytest.mark.parametrize("precision", ["f32", "f64"])
def test_every_model_and_numeric_parameter(precision):
    # Each numeric parameter of each model, given per element (its default and two values
    # inside its range), equals a model built per value: every family's plan and kernel.
    dt = np.float32 if precision == "f32" else np.float64
    n = 64
    checked = 0
    for info in fastbrdf.models():
        for p in info["params"]:
            if p["type"] != "number" or p.get("default") is None:
                continue
            lo, hi = p["min"], p["max"]
            hi = min(hi, lo + 100.0) if np.isfinite(hi) else lo + 100.0
            vals = np.array([p["default"], lo + 0.25 * (hi - lo), lo + 0.75 * (hi - lo)], dtype=dt)
            try:
                for v in vals:
                    fastbrdf.Model(info["id"], **{p["name"]: float(v)})
            except ValueError:
                continue  # a value its configuration refuses (an optional parameter)
            arr = vals[RNG.integers(0, 3, n)]
            m = fastbrdf.Model(info["id"], **{p["name"]: arr})
            x = _inputs(m, n, dt)
            got = m.eval(*x)
            np.testing.assert_array_equal(got, per_value(info["id"], {p["name"]: arr}, x, precision), err_msg=f"{info['id']} {p['name']}")
            checked += 1
    assert checked >= 30, checked

"""Model as researchers use it (issue 29): pickling and equality by value, a repr that
round-trips, __version__, colour (R,G,B values, metals, MERL materials) equal to the CLI, the
dtype rule and ``out=``."""

import copy
import json
import os
import pathlib
import pickle
import re

import numpy as np
import pytest

import fastbrdf

ROOT = pathlib.Path(__file__).resolve().parents[2]
RNG = np.random.default_rng(29)


def hemisphere(n):
    v = RNG.normal(size=(n, 3))
    v[:, 2] = np.abs(v[:, 2]) + 0.05
    return v / np.linalg.norm(v, axis=1, keepdims=True)


MODELS = [
    fastbrdf.Model("flog", n=20),
    fastbrdf.Model("cook-torrance", alpha=0.2, d="ggx", f="schlick"),
    fastbrdf.Model("cook-torrance", alpha=0.3, metal="gold"),
    fastbrdf.Model("pow", material="gold-metallic-paint"),
    fastbrdf.Model("fresnel-schlick", f0=(0.9, 0.6, 0.3)),
]


@pytest.mark.parametrize("m", MODELS, ids=repr)
def test_pickle_deepcopy_and_repr_round_trip_by_value(m):
    for other in (pickle.loads(pickle.dumps(m)), copy.deepcopy(m), copy.copy(m), eval(repr(m))):
        assert other == m and hash(other) == hash(m) and other is not m
        assert other.channels == m.channels and other.spec == m.spec
    x = np.array([0.2, 0.9]) if m.kind != "brdf" else None
    if x is not None:
        np.testing.assert_array_equal(pickle.loads(pickle.dumps(m)).eval(x), m.eval(x))


def test_equality_is_by_resolved_value():
    assert fastbrdf.Model("flog", n=20) == fastbrdf.Model("flog", n=20.0)
    assert fastbrdf.Model("flog", n=20) != fastbrdf.Model("flog", n=21)
    assert fastbrdf.Model("flog", n=20) != fastbrdf.Model("pow", n=20)
    default = fastbrdf.Model("cook-torrance").values
    assert fastbrdf.Model("cook-torrance") == fastbrdf.Model("cook-torrance", **default)
    assert len({fastbrdf.Model("ggx", alpha=0.3), fastbrdf.Model("ggx", alpha=0.30)}) == 1
    assert fastbrdf.Model("flog", n=20) != "flog"


def test_version_is_the_workspaces():
    cargo = (ROOT / "Cargo.toml").read_text()
    version = re.search(r'^version = "([^"]+)"', cargo, re.M).group(1)
    assert fastbrdf.__version__ == version


def test_build_names_the_wheels_profile():
    # tools/test.sh says which profile it built the wheel in; elsewhere either is possible.
    expected = os.environ.get("FASTBRDF_WHEEL_PROFILE")
    if expected:
        assert fastbrdf.BUILD == expected
    assert fastbrdf.BUILD in ("dev", "release")
    assert "BUILD" in fastbrdf.__all__


def _cli_colour(cli, model, args, wi, wo):
    rows = "\n".join(",".join(repr(float(x)) for x in (*a, *b)) for a, b in zip(wi, wo))
    rc, out, err = cli("eval", "--model", model, *args, "--precision", "f64",
                       stdin="wi_x,wi_y,wi_z,wo_x,wo_y,wo_z\n" + rows + "\n")
    assert rc == 0, err
    return np.array([[float(v) for v in line.split(",")[6:]] for line in out.strip().splitlines()[1:]])


def test_a_metal_colours_the_model_as_the_cli(cli):
    wi, wo = hemisphere(40), hemisphere(40)
    m = fastbrdf.Model("cook-torrance", alpha=0.2, metal="gold")
    v = m.eval(wi, wo)
    assert m.channels == 3 and v.shape == (40, 3) and v.dtype == np.float64
    np.testing.assert_array_equal(v, _cli_colour(cli, "cook-torrance", ["--metal", "gold", "--param", "alpha=0.2"], wi, wo))
    # Each channel is the grey model with that channel's eta and k (`fastbrdf metals --json`).
    rc, out, _ = cli("metals", "--json")
    gold = next(x for x in json.loads(out)["metals"] if x["id"] == "gold")
    for c in range(3):
        grey = fastbrdf.Model("cook-torrance", alpha=0.2, f="conductor", eta=gold["eta"][c], k=gold["k"][c])
        np.testing.assert_array_equal(v[:, c], grey.eval(wi, wo))
    # float32 through the SIMD kernels, per channel, within the model's f32 bound.
    v32 = m.eval(wi.astype(np.float32), wo.astype(np.float32))
    assert v32.dtype == np.float32 and v32.shape == (40, 3)
    assert (np.abs(v32 - v) / np.maximum(1, np.abs(v))).max() <= m.info["f32_bound"]


def test_rgb_values_and_materials_as_the_cli(cli):
    wi, wo = hemisphere(20), hemisphere(20)
    m = fastbrdf.Model("cook-torrance", alpha=0.3, f="schlick", f0=(0.9, 0.6, 0.3))
    assert m == fastbrdf.Model("cook-torrance", alpha=0.3, f="schlick", f0="0.9,0.6,0.3")
    np.testing.assert_array_equal(
        m.eval(wi, wo), _cli_colour(cli, "cook-torrance", ["--param", "alpha=0.3", "--param", "f=schlick", "--param", "f0=0.9,0.6,0.3"], wi, wo)
    )
    for c, f0 in enumerate((0.9, 0.6, 0.3)):
        np.testing.assert_array_equal(m.eval(wi, wo)[:, c], fastbrdf.Model("cook-torrance", alpha=0.3, f="schlick", f0=f0).eval(wi, wo))
    # A MERL material's published fit supplies n (`fastbrdf materials --json`).
    rc, out, _ = cli("materials", "--json")
    gold = next(x for x in json.loads(out) if x["name"] == "gold-metallic-paint")
    p = fastbrdf.Model("pow", material="gold-metallic-paint")
    assert p.values["n"] == gold["blinn_phong"]["n"] and p == fastbrdf.Model("pow", n=gold["blinn_phong"]["n"])
    assert fastbrdf.Model("pow", material="gold-metallic-paint", n=7).values["n"] == 7  # given values win


def test_colour_errors_name_the_argument():
    with pytest.raises(ValueError, match="metal: unknown metal 'unobtainium'"):
        fastbrdf.Model("cook-torrance", metal="unobtainium")
    with pytest.raises(ValueError, match="metal 'gold': model 'flog' has no conductor Fresnel term"):
        fastbrdf.Model("flog", metal="gold")
    with pytest.raises(ValueError, match="material: unknown material 'gold'"):
        fastbrdf.Model("pow", material="gold")
    with pytest.raises(ValueError, match="material 'gold-metallic-paint': model 'lambert' takes none"):
        fastbrdf.Model("lambert", material="gold-metallic-paint")
    with pytest.raises(TypeError, match="metal: expected a string, got int"):
        fastbrdf.Model("cook-torrance", metal=3)


def test_a_coloured_model_samples_its_first_channel():
    m = fastbrdf.Model("cook-torrance", alpha=0.3, d="ggx", metal="copper")
    wo = np.array([0.3, 0.1, 0.95]) / np.linalg.norm([0.3, 0.1, 0.95])
    wi, w, pdf = m.sample(wo, RNG.random((500, 2)))
    assert w.shape == (500, 3) and pdf.shape == (500,)
    ok = pdf > 0
    f = m.eval(wi[ok], wo)
    np.testing.assert_allclose(w[ok], f * wi[ok, 2:3] / pdf[ok, None], rtol=1e-9)


def test_out_is_written_and_checked():
    m = fastbrdf.Model("ggx", alpha=0.3)
    x = np.linspace(0, 1, 11)
    out = np.empty(11)
    assert m.eval(x, out=out) is out
    np.testing.assert_array_equal(out, m.eval(x))
    out32 = np.empty((11,), np.float32)
    assert m.eval(x.astype(np.float32), out=out32) is out32
    # In place: the input itself (through a temporary).
    y = x.copy()
    m.eval(y, out=y)
    np.testing.assert_array_equal(y, m.eval(x))
    # A coloured model writes (..., 3).
    c = fastbrdf.Model("cook-torrance", alpha=0.3, metal="gold")
    d = hemisphere(7)
    o3 = np.empty((7, 3))
    c.eval(d, d[::-1], out=o3)
    np.testing.assert_array_equal(o3, c.eval(d, d[::-1]))
    with pytest.raises(TypeError, match="out: dtype float32, the result is float64"):
        m.eval(x, out=np.empty(11, np.float32))
    with pytest.raises(ValueError, match=r"out: shape \(10,\), the result has shape \(11,\)"):
        m.eval(x, out=np.empty(10))
    with pytest.raises(ValueError, match="out: must be C-contiguous"):
        m.eval(x, out=np.empty(22)[::2])
    ro = np.empty(11)
    ro.flags.writeable = False
    with pytest.raises(ValueError, match="out: is read-only"):
        m.eval(x, out=ro)
    with pytest.raises(TypeError, match="out: expected a numpy array, got list"):
        m.eval(x, out=[0.0] * 11)


def test_out_reused_over_a_large_input_allocates_nothing_new():
    """With ``out=`` the call allocates no output: numpy's traced peak stays far below the
    output's size."""
    import tracemalloc

    m = fastbrdf.Model("ggx", alpha=0.3)
    x = RNG.random(2_000_000, dtype=np.float32)
    out = np.empty_like(x)
    m.eval(x, out=out)
    tracemalloc.start()
    m.eval(x, out=out)
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    assert peak < x.nbytes // 10, peak


def test_per_element_values_are_copied_and_frozen():
    """A model is a value: changing the caller's array afterwards changes neither its results
    nor its hash; ``out=`` cannot write into its parameters."""
    a = np.array([0.1, 0.3])
    m = fastbrdf.Model("ggx", alpha=a)
    before = m.eval([0.9, 0.9])
    seen = {m}
    a[0] = 0.5
    np.testing.assert_array_equal(m.eval([0.9, 0.9]), before)
    assert m in seen and m == fastbrdf.Model("ggx", alpha=np.array([0.1, 0.3]))
    assert not m.params["alpha"].flags.writeable
    with pytest.raises(ValueError, match="out: is read-only"):
        m.eval([0.9, 0.9], out=m.params["alpha"])


def test_albedo_and_shader_take_material_and_metal_as_the_cli(cli):
    rc, out, _ = cli("albedo", "--model", "cook-torrance", "--material", "gold-metallic-paint",
                     "--param", "f=schlick", "--angles", "0,60", "--json")
    assert rc == 0
    assert fastbrdf.albedo("cook-torrance", material="gold-metallic-paint", f="schlick", angles=[0, 60]) == json.loads(out)
    rc, out, _ = cli("shader", "--model", "cook-torrance", "--param", "d=ggx", "--metal", "gold", "--lang", "glsl")
    assert rc == 0 and fastbrdf.shader("cook-torrance", d="ggx", metal="gold", lang="glsl") == out
    rc, out, _ = cli("shader", "--model", "pow", "--material", "gold-metallic-paint")
    assert rc == 0 and fastbrdf.shader("pow", material="gold-metallic-paint") == out

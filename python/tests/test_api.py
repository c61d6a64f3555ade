"""sample/pdf, errors, albedo, render, shader and the example script."""

import json
import pathlib
import subprocess
import sys

import numpy as np
import pytest

import fastbrdf

RNG = np.random.default_rng(15)
EXAMPLES = pathlib.Path(__file__).resolve().parents[1] / "examples"


@pytest.mark.parametrize("precision, rtol", [("f32", 2e-4), ("f64", 1e-9)])
@pytest.mark.parametrize(
    "id, params, strategy",
    [
        ("cook-torrance", {"d": "ggx", "alpha": 0.3}, "vndf"),
        ("cook-torrance", {"alpha": 0.2}, "d-cos"),
        ("phong", {"n": 40}, "auto"),
        ("lambert", {}, "cosine"),
    ],
)
def test_sample_pdf_and_weight_agree(id, params, strategy, precision, rtol):
    m = fastbrdf.Model(id, **params)
    wo = np.array([0.4, 0.1, 0.9])
    u = RNG.random((2000, 2))
    wi, weight, pdf = m.sample(wo, u, strategy=strategy, precision=precision)
    assert wi.shape == (2000, 3) and weight.shape == pdf.shape == (2000,)
    ok = pdf > 0
    assert ok.mean() > 0.5
    # No sample: zeros everywhere.
    assert np.all(wi[~ok] == 0) and np.all(weight[~ok] == 0)
    np.testing.assert_allclose(np.linalg.norm(wi[ok], axis=1), 1, rtol=1e-5)
    np.testing.assert_allclose(m.pdf(wo, wi[ok], strategy=strategy, precision=precision), pdf[ok], rtol=rtol)
    f = m.eval(wi[ok], wo, precision=precision)
    np.testing.assert_allclose(weight[ok], f * wi[ok, 2] / pdf[ok], rtol=10 * rtol)


def test_sample_matches_cli(cli):
    rc, out, _ = cli(
        "sample", "--model", "cook-torrance", "--param", "d=ggx", "--param", "alpha=0.2", "--precision", "f64",
        stdin="wo_x,wo_y,wo_z,u1,u2\n0.5,0,0.866,0.3,0.7\n0.1,0.2,0.9,0.9,0.05\n",
    )
    assert rc == 0
    rows = np.array([[float(x) for x in line.split(",")[5:]] for line in out.strip().splitlines()[1:]])
    m = fastbrdf.Model("cook-torrance", d="ggx", alpha=0.2)
    wi, w, p = m.sample([[0.5, 0, 0.866], [0.1, 0.2, 0.9]], [[0.3, 0.7], [0.9, 0.05]], precision="f64")
    np.testing.assert_array_equal(np.column_stack([wi, w, p]), rows)


def test_sampling_errors(cli):
    with pytest.raises(ValueError, match="model 'flog' is a lobe, but a brdf is needed"):
        fastbrdf.Model("flog").sample([0, 0, 1], [0.5, 0.5])
    with pytest.raises(ValueError, match="strategy 'fast': expected one of auto, cosine, lobe, d-cos, vndf, twin"):
        fastbrdf.Model("lambert").sample([0, 0, 1], [0.5, 0.5], strategy="fast")
    with pytest.raises(ValueError) as e:
        fastbrdf.Model("lambert").pdf([0, 0, 1], [0, 0, 1], strategy="vndf")
    rc, _, err = cli("sample", "--model", "lambert", "--strategy", "vndf", stdin="wo_x,wo_y,wo_z,u1,u2\n0,0,1,0.5,0.5\n")
    assert rc == 2 and err.strip() == f"error: {e.value}"
    with pytest.raises(ValueError, match=r"u: expected shape \(\.\.\., 2\)"):
        fastbrdf.Model("lambert").sample([0, 0, 1], [0.5, 0.5, 0.5])
    assert fastbrdf.Model("cook-torrance", d="ggx").strategies()[0] == "vndf"


def test_errors_rows_bound_the_model_and_match_the_cli(cli):
    rows = fastbrdf.errors("flog", "pow", n=[10, 100])
    assert [r["n"] for r in rows] == [10, 100]
    c = np.linspace(0, 1, 100001)
    for r in rows:
        diff = np.abs(
            fastbrdf.Model("flog", n=r["n"]).eval(c, precision="f64") - fastbrdf.Model("pow", n=r["n"]).eval(c, precision="f64")
        )
        # A refined maximum: never below the dense grid's, and attained where it says.
        assert diff.max() <= r["max_abs"] + 1e-12
        at = r["max_abs_at"]
        got = abs(fastbrdf.Model("flog", n=r["n"]).eval(at, precision="f64") - fastbrdf.Model("pow", n=r["n"]).eval(at, precision="f64"))
        assert got == pytest.approx(r["max_abs"], rel=1e-9)
    rc, out, _ = cli("errors", "--model", "flog", "--reference", "pow", "--n", "10,100", "--json")
    assert rc == 0
    assert rows == json.loads(out)["rows"]
    assert fastbrdf.errors("flog", "pow", n="10..30:10") == fastbrdf.errors("flog", "pow", n=[10, 20, 30])


def test_errors_validation():
    with pytest.raises(ValueError, match="give n=... .lobes. or alpha=..."):
        fastbrdf.errors("flog", "pow")
    with pytest.raises(ValueError, match="unknown model id 'nope'"):
        fastbrdf.errors("nope", "pow", n=10)
    with pytest.raises(ValueError, match="model 'flog': parameter n = 0 is invalid"):
        fastbrdf.errors("flog", "pow", n=[0, 10])
    with pytest.raises(ValueError, match="model 'ggx' is a distribution, but a lobe is needed"):
        fastbrdf.errors("flog", "ggx", n=10)
    with pytest.raises(ValueError, match="zone 'middle'"):
        fastbrdf.errors("flog", "pow", n=10, zone="middle")


def test_albedo(cli):
    r = fastbrdf.albedo("lambert", angles=[0, 60])
    assert r["claims_energy"] and r["conserves"]
    assert [row["theta_deg"] for row in r["rows"]] == [0, 60]
    for row in r["rows"]:
        assert abs(row["albedo"] - 1) <= max(1e-6, row["error"])
    rc, out, _ = cli("albedo", "--model", "pow", "--param", "n=50", "--angles", "0,30,60", "--json")
    assert rc == 0
    assert fastbrdf.albedo("pow", n=50, angles="0,30,60") == json.loads(out)
    with pytest.raises(ValueError, match=r"angles: 90 is outside \[0, 90\) degrees"):
        fastbrdf.albedo("lambert", angles=[90])
    with pytest.raises(ValueError, match="model 'ggx' is a distribution, but a brdf or lobe is needed"):
        fastbrdf.albedo("ggx")


def test_render():
    img = fastbrdf.render("cook-torrance", d="ggx", alpha=0.3, width=40, height=30, spp=1)
    assert img.shape == (30, 40, 3) and img.dtype == np.float32
    assert np.isfinite(img).all() and (img >= 0).all()
    # The sphere is lit in the middle and the background is not the sphere.
    assert img[15, 20].sum() > 0
    # Shading is linear in the weights (kd, ks); the background does not depend on them.
    def at(weights):
        return fastbrdf.render("cook-torrance", d="ggx", alpha=0.3, width=40, height=30, spp=1, weights=weights)

    dark = at((0, 0))
    assert not np.array_equal(dark, img)
    np.testing.assert_allclose(at((1.2, 0.8)) - dark, 2 * (img - dark), rtol=1e-4, atol=1e-5)
    with pytest.raises(ValueError, match=r"weights \(0.6,\): expected 2 numbers from 0 to 1000"):
        fastbrdf.render("pow", weights=(0.6,))
    with pytest.raises(ValueError, match="size 0x10: both sides must be at least 1"):
        fastbrdf.render("pow", width=0, height=10)
    with pytest.raises(ValueError, match="unknown model id 'nope'"):
        fastbrdf.render("nope")


def test_shader(cli):
    for lang, needle in [("wgsl", "fn fb_cook_torrance("), ("glsl", "fb_cook_torrance("), ("hlsl", "fb_cook_torrance("), ("msl", "fb_cook_torrance(")]:
        text = fastbrdf.shader("cook-torrance", lang=lang, alpha=0.2, f="schlick")
        assert needle in text
    rc, out, _ = cli("shader", "--model", "flog", "--param", "n=20", "--lang", "glsl")
    assert rc == 0 and fastbrdf.shader("flog", lang="glsl", n=20) == out
    assert "p_n" in fastbrdf.shader("cubic", runtime_params=True)
    with pytest.raises(ValueError, match="lang 'c\\+\\+': expected one of wgsl, glsl, hlsl, msl, brdf-explorer"):
        fastbrdf.shader("flog", lang="c++")


def test_example_script_runs():
    p = subprocess.run([sys.executable, str(EXAMPLES / "quickstart.py")], capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stderr
    assert "flog" in p.stdout


def test_docstring_examples():
    import doctest

    attempted = 0
    for module in [fastbrdf, *fastbrdf._MODULES]:
        r = doctest.testmod(module, extraglobs={"np": np, "fastbrdf": fastbrdf}, optionflags=doctest.ELLIPSIS)
        assert r.failed == 0, module.__name__
        attempted += r.attempted
    assert attempted >= 10


def _public_callables():
    """Every public function and class of the package, and every public method and property
    of its classes, as (name, object)."""
    import inspect

    found = []
    for name in fastbrdf.__all__:
        obj = getattr(fastbrdf, name)
        if inspect.isfunction(obj):
            found.append((name, obj))
        elif inspect.isclass(obj):
            found.append((name, obj))
            for attr, member in vars(obj).items():
                if attr.startswith("_") and attr not in ("__init__", "__eq__", "__repr__", "__reduce__"):
                    continue
                if isinstance(member, property):
                    found.append((f"{name}.{attr}", member.fget))
                elif inspect.isfunction(member) and not attr.startswith("_"):
                    found.append((f"{name}.{attr}", member))
    return found


def test_every_public_function_has_a_runnable_example():
    """Issue 29: every function has a docstring with a ``>>>`` example (run by
    test_docstring_examples); a class's example may sit in the class docstring for its
    dunder methods."""
    missing = [
        name
        for name, obj in _public_callables()
        if not (obj.__doc__ and ">>>" in obj.__doc__) and not name.endswith(("__init__", "__eq__"))
    ]
    assert missing == [], missing

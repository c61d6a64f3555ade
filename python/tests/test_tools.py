"""The CLI's analyses from Python (issue 29): check, reproduce, fit, normalize, lut, pareto and
chi2 return what the `fastbrdf` command prints with --json (the same numbers: one Rust function
builds both), lut the table its --out file holds; bad input is a ValueError/TypeError naming
the argument. The slow commands run at their smallest options (check one model at a time, the
CLI beside Python); reproduce and the lobes' pareto, seconds of CPU each, are compared with the
book's sections that crates/cli/tests/docs.rs keeps equal to the binary's output."""

import csv
import io
import json
import pathlib
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

import fastbrdf

ROOT = pathlib.Path(__file__).resolve().parents[2]
BENCH = ROOT / "docs" / "bench" / "bench.json"
PARETO_BRDF = ROOT / "docs" / "bench" / "pareto-brdf.json"


def cli_json(cli, *args, code=0):
    rc, out, err = cli(*args)
    assert rc == code, err
    return json.loads(out)


def beside(cli, args, call):
    """Runs the CLI (on a thread) while Python computes: (CLI's JSON, Python's result)."""
    with ThreadPoolExecutor(1) as pool:
        job = pool.submit(cli, *args)
        mine = call()
        rc, out, err = job.result()
    assert rc == 0, err
    return json.loads(out), mine


# --- check -------------------------------------------------------------------------------


@pytest.mark.parametrize("model", ["power4-tuned", "phong"])
def test_check_equals_the_cli(cli, model):
    theirs, mine = beside(cli, ["check", "--json", "--model", model], lambda: fastbrdf.check(model))
    assert mine == theirs
    assert set(mine) == {"ok", "bounds", "f32", "kernels"}
    assert [r["model"] for r in mine["f32"]] == [model]
    assert {r["model"] for r in mine["bounds"]} <= {model}
    # The batch kernels on every instruction set of this CPU, held to the model's f32 bound.
    [k] = mine["kernels"]
    assert k["model"] == model and k["isas"] and k["isas"][-1] == "sse2"
    assert k["ok"] and k["finite"] and 0 <= k["measured"] <= k["documented"]
    # ok is every row's verdict (the CLI's exit code says the same).
    assert mine["ok"] == all(r["ok"] for r in mine["bounds"] + mine["f32"] + mine["kernels"])


def test_check_keyword_names_and_errors():
    assert fastbrdf.check(model="pow", full=False)["f32"][0]["model"] == "pow"
    with pytest.raises(ValueError, match="nope"):
        fastbrdf.check("nope")
    with pytest.raises(TypeError, match="full"):
        fastbrdf.check("pow", full="yes")
    with pytest.raises(TypeError, match="model"):
        fastbrdf.check(3)


# --- reproduce ---------------------------------------------------------------------------


def section(page, marker):
    """The generated section `marker` of a book page (what crates/cli/tests/docs.rs keeps
    equal to the binary's output)."""
    text = (ROOT / "docs" / "book" / "src" / page).read_text(encoding="utf-8")
    return text.split(f"<!-- {marker}:begin -->\n")[1].split(f"<!-- {marker}:end -->")[0]


def test_reproduce_equals_the_cli_report():
    # A run takes about five seconds of CPU, so it is not run twice: the book's section
    # (docs/book/src/reproduction.md) is `fastbrdf reproduce --markdown --speedups
    # docs/bench/bench.json`, which crates/cli/tests/docs.rs keeps equal to the binary's
    # output; Python's claims, printed the CLI's way (reproduce::markdown), must be it.
    mine = fastbrdf.reproduce(speedups=BENCH)
    claims = mine["claims"]
    md = "| claim | seed | claimed | measured | verdict |\n|---|---|---|---|---|\n"
    for c in claims:
        md += f"| `{c['id']}` | {c['seed']} | {c['claimed_text'] or '-'} | {c['measured_text'] or '-'} | {c['verdict']} |\n"
    md += "\nDomains (how each number was measured):\n\n"
    md += "".join(f"- `{c['id']}`: {c['domain']}\n" for c in claims)
    assert md == section("reproduction.md", "reproduce")
    assert set(mine) == {"claims"}
    # The speed rows come from the file (not measured without it).
    speed = [c for c in claims if c["id"].endswith(".speedup")]
    assert speed and all(c["measured"] is not None for c in speed)


def test_reproduce_errors_as_the_cli(cli):
    rc, _, err = cli("reproduce", "--json", "--speedups", "missing.json")
    assert rc == 2
    with pytest.raises(ValueError) as e:
        fastbrdf.reproduce(speedups="missing.json")
    assert str(e.value) in err
    with pytest.raises(TypeError, match="speedups"):
        fastbrdf.reproduce(speedups=3)


# --- fit ---------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "flags, kwargs",
    [
        (["--family", "power16", "--reference", "pow", "--n", "8,16,100"], dict(n=[8, 16, 100])),
        (["--family", "exp2", "--reference", "pow", "--n", "8..64:8", "--metric", "rms"], dict(n="8..64:8", metric="rms")),
        (["--family", "power8", "--reference", "pow", "--n", "8,50", "--normalized"], dict(n=[8, 50], normalized=True)),
        (
            ["--family", "beckmann-power16", "--reference", "beckmann-ct", "--m", "0.1,0.3", "--metric", "max-rel-epicentre"],
            dict(m=(0.1, 0.3), metric="max-rel-epicentre"),
        ),
    ],
)
def test_fit_equals_the_cli(cli, flags, kwargs):
    theirs = cli_json(cli, "fit", *flags, "--json")
    mine = fastbrdf.fit(flags[1], flags[3], **kwargs)
    assert mine == theirs
    # Five rows and more of a lobe family carry the closed form.
    assert (mine["closed_form"] is not None) == (len(mine["rows"]) >= 5 and flags[1] != "beckmann-power16")


def test_fit_errors_name_the_argument():
    with pytest.raises(ValueError, match="family 'power3'"):
        fastbrdf.fit("power3", "pow", n=10)
    with pytest.raises(ValueError, match="family 'power3'"):
        fastbrdf.fit("power3", "pow")
    # Every listed family is one the library fits (its name comes back).
    for f in fastbrdf.FIT_FAMILIES:
        ref, kw = ("beckmann-ct", {"m": 0.3}) if f == "beckmann-power16" else ("pow", {"n": 20})
        assert fastbrdf.fit(f, ref, **kw)["family"] == f
    with pytest.raises(ValueError, match="reference beckmann-ct: the power16 family approximates pow"):
        fastbrdf.fit("power16", "beckmann-ct", n=10)
    with pytest.raises(ValueError, match=r"n: n = 0\.5 is outside"):
        fastbrdf.fit("power16", "pow", n=[0.5, 10])
    with pytest.raises(ValueError, match="the lobe families take n="):
        fastbrdf.fit("power16", "pow")
    with pytest.raises(ValueError, match="the beckmann-power16 family takes m="):
        fastbrdf.fit("beckmann-power16", "beckmann-ct", n=10)
    with pytest.raises(ValueError, match="not both"):
        fastbrdf.fit("power16", "pow", n=10, m=0.2)
    with pytest.raises(ValueError, match="metric 'l2'"):
        fastbrdf.fit("power16", "pow", n=10, metric="l2")
    with pytest.raises(ValueError, match="normalized applies to the lobe families"):
        fastbrdf.fit("beckmann-power16", "beckmann-ct", m=0.2, normalized=True)
    with pytest.raises(ValueError, match="^n: "):
        fastbrdf.fit("power16", "pow", n="10..")
    with pytest.raises(TypeError, match="normalized"):
        fastbrdf.fit("power16", "pow", n=10, normalized=1)


# --- normalize ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    "flags, kwargs",
    [
        (["--model", "flog", "--n", "1..7"], dict(n="1..7")),
        (["--model", "cubic-rational", "--n", "1..40", "--fit", "linear"], dict(n=range(1, 41), fit="linear")),
        (["--model", "flog", "--n", "1..60", "--fit", "seed"], dict(n="1..60", fit="seed")),
    ],
)
def test_normalize_equals_the_cli(cli, flags, kwargs):
    theirs = cli_json(cli, "normalize", *flags, "--json")
    assert fastbrdf.normalize(flags[1], **kwargs) == theirs


def test_normalize_errors_name_the_argument():
    with pytest.raises(ValueError, match="normalize needs a lobe; 'lambert' is a brdf"):
        fastbrdf.normalize("lambert", [1])
    with pytest.raises(ValueError, match="fit 'cubic'"):
        fastbrdf.normalize("flog", [1, 2, 3, 4], fit="cubic")
    with pytest.raises(ValueError, match="n"):
        fastbrdf.normalize("flog", [1e9])
    with pytest.raises(ValueError, match="n: no values"):
        fastbrdf.normalize("flog", [])


# --- lut ---------------------------------------------------------------------------------


def read_csv_table(text, size):
    rows = list(csv.DictReader(io.StringIO(text)))
    assert len(rows) == size * size
    col = lambda k: np.array([float(r[k]) for r in rows], dtype=np.float32).reshape(size, size)  # noqa: E731
    return col


@pytest.mark.parametrize("size, axis, model", [(8, "roughness", "env-brdf"), (5, "alpha", "env-brdf-approx-tuned")])
def test_lut_equals_the_cli_file(cli, tmp_path, size, axis, model):
    theirs = tmp_path / "cli.csv"
    rc, _, err = cli("lut", "--out", str(theirs), "--size", str(size), "--axis", axis, "--model", model)
    assert rc == 0, err
    mine = tmp_path / "py.csv"
    t = fastbrdf.lut(model, size=size, axis=axis, out=mine)
    assert mine.read_bytes() == theirs.read_bytes()
    col = read_csv_table(theirs.read_text(), size)
    table = t["table"]
    assert table.shape == (size, size, 2) and table.dtype == np.float32
    np.testing.assert_array_equal(table[..., 0], col("scale"))
    np.testing.assert_array_equal(table[..., 1], col("bias"))
    np.testing.assert_array_equal(np.broadcast_to(t["cos_v"], (size, size)), col("cos_v"))
    np.testing.assert_array_equal(np.broadcast_to(t["roughness"][:, None], (size, size)), col("roughness"))
    np.testing.assert_array_equal(np.broadcast_to(t["alpha"][:, None], (size, size)), col("alpha"))
    assert (t["model"], t["size"], t["axis"]) == (model, size, axis)
    # The rows whose nominal alpha is below the domain hold its smallest value.
    k, a = t["clamped_rows"], t["alpha"]
    assert np.all(a[:k] == a[0]) and np.all(np.diff(a[max(k - 1, 0) :]) > 0)
    assert k == (1 if axis == "roughness" else 0)  # (0.5 / 8)^2 < 0.005 < 0.5 / 5


@pytest.mark.parametrize("ext", ["png", "exr"])
def test_lut_writes_the_cli_images(cli, tmp_path, ext):
    theirs = tmp_path / f"cli.{ext}"
    assert cli("lut", "--out", str(theirs), "--size", "6")[0] == 0
    mine = tmp_path / f"py.{ext}"
    fastbrdf.lut(size=6, out=str(mine))
    assert mine.read_bytes() == theirs.read_bytes()
    other = tmp_path / "table.bin"
    fastbrdf.lut(size=6, out=other, format=ext)
    assert other.read_bytes() == theirs.read_bytes()


def test_lut_errors_name_the_argument(tmp_path):
    with pytest.raises(ValueError, match="size 0: expected 1 to 4096"):
        fastbrdf.lut(size=0)
    with pytest.raises(ValueError, match="size"):
        fastbrdf.lut(size=-1)
    with pytest.raises(TypeError, match="size"):
        fastbrdf.lut(size=2.5)
    with pytest.raises(ValueError, match="axis 'r'"):
        fastbrdf.lut(size=2, axis="r")
    with pytest.raises(ValueError, match="flog"):
        fastbrdf.lut("flog", size=2)
    with pytest.raises(ValueError, match=r"out .*x\.txt: the file must end in"):
        fastbrdf.lut(size=2, out=tmp_path / "x.txt")
    with pytest.raises(ValueError, match="format 'jpg'"):
        fastbrdf.lut(size=2, out=tmp_path / "x.png", format="jpg")
    (tmp_path / "file").write_text("")
    with pytest.raises(OSError, match="cannot write"):
        fastbrdf.lut(size=2, out=tmp_path / "file" / "x.csv")
    assert [p.name for p in tmp_path.iterdir()] == ["file"]


# --- pareto ------------------------------------------------------------------------------


def test_pareto_lobes_equal_the_cli_table():
    # The lobes' run takes about ten seconds of CPU, so it is not run twice: the book's table
    # (docs/book/src/tuned.md, between the pareto markers) is `fastbrdf pareto --bench
    # docs/bench/bench.json --markdown`, which crates/cli/tests/docs.rs keeps equal to the
    # binary's output; Python's rows, printed the CLI's way, must be its lines. With the saved
    # bench run the throughput is the file's, so every column is comparable.
    mine = fastbrdf.pareto(bench=BENCH)
    table = section("tuned.md", "pareto").splitlines()
    lines = [
        f"| `{r['model']}` | {r['ops']} | {r['simd_evals_per_s'] / 1e9:.2f} G | {r['max_abs_1_1e5']:.4f} | "
        f"{r['max_abs_8_1e5']:.5f} | {r['max_rel_epicentre_8_1e5']:.5f} | {'yes' if r['pareto'] else ''} |"
        for r in mine["models"]
    ]
    assert lines == table[2:]
    assert set(mine) == {"models"}


def test_pareto_bench_errors_as_the_cli(cli):
    rc, _, err = cli("pareto", "--json", "--bench", "missing.json")
    assert rc == 2
    with pytest.raises(ValueError) as e:
        fastbrdf.pareto(bench="missing.json")
    assert str(e.value) in err


@pytest.mark.parametrize(
    "flags, kwargs",
    [
        ([], {}),
        (
            ["--alpha", "0.1,0.5", "--front-on", "max", "--grid", "8x16"],
            dict(alpha=[0.1, 0.5], front_on="max", grid="8x16"),
        ),
        (
            ["--reference", "d=beckmann,g=smith,f=dielectric,eta=1.5", "--alpha", "0.2..0.3:0.1"],
            dict(reference="d=beckmann,g=smith,f=dielectric,eta=1.5", alpha="0.2..0.3:0.1"),
        ),
    ],
)
def test_pareto_brdf_equals_the_cli(cli, flags, kwargs):
    # Saved costs (docs/bench/pareto-brdf.json) instead of timings; no renders.
    common = ["--brdf", "--quick", "--size", "0", "--costs", str(PARETO_BRDF)]
    theirs = cli_json(cli, "pareto", *common, *flags, "--json")
    mine = fastbrdf.pareto(brdf=True, quick=True, size=0, costs=PARETO_BRDF, **kwargs)
    assert mine == theirs


def test_pareto_brdf_with_renders_has_flip():
    r = fastbrdf.pareto(brdf=True, quick=True, size=8, costs=PARETO_BRDF)
    assert r["size"] == 8
    assert all(row["flip_sphere"] is not None for row in r["rows"])
    assert [row["flip_sphere"] for row in r["rows"] if row["reference"]] == [0.0]


def test_pareto_errors_name_the_argument():
    with pytest.raises(ValueError, match="alpha: at most 16 values"):
        fastbrdf.pareto(brdf=True, alpha="0.05..1:0.05", quick=True, size=0)
    with pytest.raises(ValueError, match="alpha: 2 is outside"):
        fastbrdf.pareto(brdf=True, alpha=2, quick=True, size=0)
    with pytest.raises(ValueError, match="grid 8x15: expected THETAxPHI"):
        fastbrdf.pareto(brdf=True, grid="8x15", quick=True, size=0)
    with pytest.raises(ValueError, match="costs .*pareto-brdf.json: the saved costs lack"):
        fastbrdf.pareto(brdf=True, all=True, quick=True, size=0, costs=PARETO_BRDF)
    with pytest.raises(ValueError, match="front_on 'l2'"):
        fastbrdf.pareto(brdf=True, front_on="l2", quick=True, size=0)
    with pytest.raises(ValueError, match="reference"):
        fastbrdf.pareto(brdf=True, reference="d=nope", quick=True, size=0)
    with pytest.raises(ValueError, match="size: at most 1024"):
        fastbrdf.pareto(brdf=True, size=2048)
    with pytest.raises(ValueError, match="mesh needs renders"):
        fastbrdf.pareto(brdf=True, size=0, mesh="face.obj")
    with pytest.raises(ValueError, match="bench applies to the lobes"):
        fastbrdf.pareto(brdf=True, bench=BENCH)
    with pytest.raises(TypeError, match="quick"):
        fastbrdf.pareto(brdf=True, quick="yes")


# --- chi2 --------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "flags, model, kwargs",
    [
        (["--param", "n=100", "--samples", "20000"], "phong", dict(n=100, samples=20000)),
        (
            ["--param", "d=ggx", "--param", "alpha=0.2", "--theta-i", "60", "--strategy", "vndf", "--precision", "f32", "--samples", "30000", "--res", "8", "--seed", "3"],
            "cook-torrance",
            dict(d="ggx", alpha=0.2, theta_i=60, strategy="vndf", precision="f32", samples=30000, res=8, seed=3),
        ),
        (["--param", "alpha_x=0.1", "--param", "alpha_y=0.4", "--samples", "20000"], "ward", dict(alpha_x=0.1, alpha_y=0.4, samples=20000)),
    ],
)
def test_chi2_equals_the_cli(cli, tmp_path, flags, model, kwargs):
    png = tmp_path / "cli.png"
    rc, out, err = cli("chi2", "--model", model, *flags, "--json", "--out", str(png))
    mine = fastbrdf.chi2(model, out=tmp_path / "py.png", **kwargs)
    assert mine == json.loads(out)
    assert (tmp_path / "py.png").read_bytes() == png.read_bytes()
    # A failed test is a result (passed False), the CLI's exit code 1.
    assert (rc == 0) == mine["passed"], err
    assert mine["passed"] == (mine["p_value"] > mine["threshold"])


def test_chi2_errors_name_the_argument():
    with pytest.raises(ValueError, match=r"theta_i 90: expected degrees in \[0, 90\)"):
        fastbrdf.chi2("lambert", theta_i=90)
    with pytest.raises(ValueError, match="samples 0: expected 1 to 100000000"):
        fastbrdf.chi2("lambert", samples=0)
    with pytest.raises(ValueError, match="res 1001: expected 1 to 1000"):
        fastbrdf.chi2("lambert", res=1001)
    with pytest.raises(ValueError, match="strategy 'best'"):
        fastbrdf.chi2("lambert", strategy="best")
    with pytest.raises(ValueError, match="lambert"):
        fastbrdf.chi2("lambert", strategy="vndf")
    with pytest.raises(ValueError, match="only full BRDFs sample"):
        fastbrdf.chi2("flog", n=10)
    with pytest.raises(ValueError, match="precision 'f16'"):
        fastbrdf.chi2("lambert", precision="f16")
    with pytest.raises(ValueError, match="alpha"):
        fastbrdf.chi2("cook-torrance", alpha=5)
    with pytest.raises(ValueError, match="seed"):
        fastbrdf.chi2("lambert", seed=-1)
    with pytest.raises(TypeError, match="samples"):
        fastbrdf.chi2("lambert", samples=1.5)
    with pytest.raises(TypeError, match="theta_i"):
        fastbrdf.chi2("lambert", theta_i="45")

"""fastbrdf.render / compare / materials / metals against the CLI's `render --out FILE.exr`,
`compare --json`, `materials --json` and `metals --json`: the same options give the same
films (bit for bit: the CPU renderer is deterministic) and the same numbers."""

import json
import os
import struct
import subprocess
import sys
import zlib

import numpy as np
import pytest

import fastbrdf
from test_measured import read_exr  # the EXR reader (standard library + numpy)

LVP = "/usr/share/vulkan/icd.d/lvp_icd.x86_64.json"


def write_obj(path):
    """A small closed mesh (an octahedron) with texture coordinates."""
    v = [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)]
    f = [(0, 2, 4), (2, 1, 4), (1, 3, 4), (3, 0, 4), (2, 0, 5), (1, 2, 5), (3, 1, 5), (0, 3, 5)]
    with open(path, "w") as out:
        for x, y, z in v:
            out.write(f"v {x} {y} {z}\n")
        for x, y, z in v:
            out.write(f"vt {0.5 + 0.4 * x} {0.5 + 0.4 * y}\n")
        for a, b, c in f:
            out.write(f"f {a + 1}/{a + 1} {b + 1}/{b + 1} {c + 1}/{c + 1}\n")


def write_png(path, rgb):
    """An 8-bit RGB PNG of an (H, W, 3) uint8 array, with zlib and struct."""
    h, w, _ = rgb.shape
    raw = b"".join(b"\0" + rgb[y].tobytes() for y in range(h))

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b"")
    open(path, "wb").write(png)


def write_hdr(path, rgb):
    """A Radiance .hdr (flat RGBE scanlines) of an (H, W, 3) float array."""
    h, w, _ = rgb.shape
    m = rgb.max(axis=-1)
    e = np.where(m > 0, np.floor(np.log2(np.maximum(m, 1e-30))) + 1, 0)
    scale = np.where(m > 0, 256.0 / np.exp2(e), 0)
    rgbe = np.concatenate([np.clip(rgb * scale[..., None], 0, 255), np.where(m > 0, e + 128, 0)[..., None]], -1)
    body = rgbe.astype(np.uint8).tobytes()
    open(path, "wb").write(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n" + f"-Y {h} +X {w}\n".encode() + body)


@pytest.fixture(scope="module")
def assets(tmp_path_factory):
    d = tmp_path_factory.mktemp("assets")
    write_obj(d / "octa.obj")
    y, x = np.mgrid[0:16, 0:16]
    write_png(d / "checker.png", np.where(((x // 4 + y // 4) % 2)[..., None] == 1, [200, 60, 40], [40, 120, 220]).astype(np.uint8))
    yy = np.linspace(0, 1, 8)[:, None, None]
    env = np.broadcast_to(np.concatenate([1.5 - yy, 0.8 + 0 * yy, 0.3 + yy], -1), (8, 16, 3)).copy()
    env[2, 5] = [40.0, 35.0, 30.0]  # a sun
    write_hdr(d / "sky.hdr", env)
    return d


def cli_film(cli, tmp_path, flags):
    out = tmp_path / "cli.exr"
    rc, _, err = cli("render", "--out", str(out), *flags)
    assert rc == 0, err
    return read_exr(out)


# (Python keyword arguments, the CLI's flags): each case renders 32x32 or smaller.
CASES = [
    ("a distribution shaded, its BRDF's g",
     dict(model="ggx", alpha=0.3, g="smith"),
     ["--model", "ggx", "--param", "alpha=0.3", "--param", "g=smith"]),
    ("a material's fit and colour",
     dict(model="ward", material="gold-paint"),
     ["--model", "ward", "--material", "gold-paint"]),
    ("a metal, a floor, lights",
     dict(model="cook-torrance", d="ggx", alpha=0.2, metal="gold", floor=True, lights=["point:2,3,3:1,1,1:20", "dir:0,1,1"]),
     ["--model", "cook-torrance", "--param", "d=ggx", "--param", "alpha=0.2", "--metal", "gold", "--floor",
      "--light", "point:2,3,3:1,1,1:20", "--light", "dir:0,1,1"]),
    ("R,G,B values as a tuple",
     dict(model="cook-torrance", f="schlick", f0=(0.95, 0.64, 0.54), alpha=0.25, weights=(0.2, 1), albedo="0.1,0.2,0.3"),
     ["--model", "cook-torrance", "--param", "f=schlick", "--param", "f0=0.95,0.64,0.54", "--param", "alpha=0.25",
      "--weights", "0.2,1", "--albedo", "0.1,0.2,0.3"]),
    ("the built-in face and skin, bump, no shadows",
     dict(model="flog", n=40, mesh="face", texture="skin", bump=(40, 0.6), shadows="off", size=(24, 32)),
     ["--model", "flog", "--param", "n=40", "--mesh", "face", "--texture", "skin", "--bump", "40,0.6",
      "--shadows", "off"]),
    ("the sky, a metal's weights given",
     dict(model="beckmann", alpha=0.3, metal="copper", weights=(0.3, 0.7), env="sky", env_samples=2),
     ["--model", "beckmann", "--param", "alpha=0.3", "--metal", "copper", "--weights", "0.3,0.7",
      "--env", "sky", "--env-samples", "2"]),
    ("adaptive antialiasing on the face, 3x3 at edges",
     dict(model="ggx", alpha=0.3, mesh="face", spp=3, size=(24, 32)),
     ["--model", "ggx", "--param", "alpha=0.3", "--mesh", "face"]),
    ("the sky, independent numbers, grid antialiasing",
     dict(model="ggx", alpha=0.3, env="sky", env_samples=2, spp=2, sampler="independent", aa="grid"),
     ["--model", "ggx", "--param", "alpha=0.3", "--env", "sky", "--env-samples", "2",
      "--sampler", "independent", "--aa", "grid"]),
    ("the sky, Sobol numbers, adaptive antialiasing",
     dict(model="ggx", alpha=0.3, env="sky", env_samples=2, spp=2, sampler="sobol", aa="adaptive"),
     ["--model", "ggx", "--param", "alpha=0.3", "--env", "sky", "--env-samples", "2"]),
    ("the sky, every light direction from the whole map",
     dict(model="ggx", alpha=0.3, env="sky", env_samples=2, env_sun="with-map"),
     ["--model", "ggx", "--param", "alpha=0.3", "--env", "sky", "--env-samples", "2",
      "--env-sun", "with-map"]),
    ("the furnace",
     dict(model="pow", env="white", env_samples=1, weights=(1, 0), albedo=(1, 1, 1)),
     ["--model", "pow", "--env", "white", "--env-samples", "1", "--weights", "1,0", "--albedo", "1,1,1"]),
]


@pytest.mark.parametrize("what, kw, flags", CASES, ids=[c[0] for c in CASES])
def test_render_equals_the_cli_exr(cli, tmp_path, what, kw, flags):
    kw = dict(kw)
    model = kw.pop("model")
    kw.setdefault("spp", 1)
    if "size" not in kw:
        kw["size"] = "32x24"
    w, h = (int(s) for s in kw["size"].split("x")) if isinstance(kw["size"], str) else kw["size"]
    want = cli_film(cli, tmp_path, flags + ["--size", f"{w}x{h}", "--spp", str(kw["spp"])])
    got = fastbrdf.render(model, **kw)
    assert got.dtype == np.float32 and got.shape == (h, w, 3)
    assert got.max() > 0 and np.all(np.isfinite(got))
    np.testing.assert_array_equal(got, want)


def test_files_equal_the_cli(cli, tmp_path, assets):
    """An OBJ mesh, a PNG texture and an .hdr environment map, read from files."""
    for kw, flags in [
        (dict(mesh=assets / "octa.obj", texture=str(assets / "checker.png"), lights=["dir:0.3,0.6,1"]),
         ["--mesh", str(assets / "octa.obj"), "--texture", str(assets / "checker.png"), "--light", "dir:0.3,0.6,1"]),
        (dict(env=str(assets / "sky.hdr"), env_samples=2, floor=True),
         ["--env", str(assets / "sky.hdr"), "--env-samples", "2", "--floor"]),
    ]:
        want = cli_film(cli, tmp_path, ["--model", "ward", "--param", "alpha=0.3", "--size", "24x16", "--spp", "1", *flags])
        got = fastbrdf.render("ward", alpha=0.3, width=24, height=16, spp=1, **kw)
        assert got.max() > 0
        np.testing.assert_array_equal(got, want)


def test_colour_changes_the_picture():
    grey = fastbrdf.render("ggx", alpha=0.3, size="16x16", spp=1, weights=(0, 1))
    gold = fastbrdf.render("ggx", alpha=0.3, size="16x16", spp=1, metal="gold")
    assert np.array_equal(grey[..., 0], grey[..., 2])  # grey: equal channels
    centre = gold[4:12, 4:12].sum(axis=(0, 1))
    assert centre[0] > 1.2 * centre[2]  # gold reflects red more than blue
    # A metal sets the weights (0, 1) unless given; the same metal by its values is the same.
    metal = next(m for m in fastbrdf.metals()["metals"] if m["id"] == "gold")
    by_values = fastbrdf.render("ggx", alpha=0.3, size="16x16", spp=1, weights=(0, 1), f="conductor",
                                eta=tuple(metal["eta"]), k=tuple(metal["k"]))
    np.testing.assert_array_equal(gold, by_values)


def test_bad_options_name_the_argument():
    cases = [
        (ValueError, "material: unknown material 'gold'", dict(material="gold")),
        (ValueError, "metal: unknown metal", dict(metal="unobtainium")),
        (ValueError, "metal 'gold': model 'flog' has no conductor Fresnel term", dict(model="flog", metal="gold")),
        (ValueError, "material 'gold-metallic-paint': model 'lambert' takes none", dict(model="lambert", material="gold-metallic-paint")),
        (ValueError, "gpu=True: coloured specular", dict(metal="gold", gpu=True)),
        (ValueError, "size: give size or width and height", dict(size="8x8", width=8)),
        (ValueError, "size 'big'", dict(size="big")),
        (ValueError, r"bump \(0.0, 1.0\): expected \(SCALE, DEPTH\)", dict(bump=(0, 1))),
        (ValueError, "weights '1,x': not numbers", dict(weights="1,x")),
        (ValueError, "model 'cook-torrance' has no parameter 'nope'", dict(nope=1)),
        (ValueError, "spp 17: must be 1 to 16", dict(spp=17)),
        (ValueError, "env_samples 0", dict(env_samples=0)),
        (TypeError, "mesh: expected a path", dict(mesh=3)),
        (TypeError, "shadows: expected a bool or 'on'/'off', got str", dict(shadows="no")),
        (TypeError, "floor: expected a bool, got int", dict(floor=1)),
        (TypeError, "metal: expected a string", dict(metal=3)),
        (ValueError, "sampler 'halton': expected sobol or independent", dict(sampler="halton")),
        (ValueError, "aa 'msaa': expected adaptive or grid", dict(aa="msaa")),
        (TypeError, "aa: expected a string", dict(aa=2)),
        (ValueError, "env_sun 'whole': expected apart or with-map", dict(env_sun="whole")),
    ]
    for kind, msg, kw in cases:
        kw = {"model": "cook-torrance", "size": "8x8", "spp": 1, **kw}
        with pytest.raises(kind, match=msg):
            fastbrdf.render(kw.pop("model"), **kw)
    # shadows as a bool or as the CLI's on/off: the same picture.
    lit = dict(size="16x16", spp=1, floor=True, lights=["point:2,3,3:1,1,1:20"])
    np.testing.assert_array_equal(fastbrdf.render("ward", shadows=False, **lit), fastbrdf.render("ward", shadows="off", **lit))
    assert not np.array_equal(fastbrdf.render("ward", shadows="on", **lit), fastbrdf.render("ward", shadows="off", **lit))
    with pytest.raises(ValueError, match="nosuch.obj"):
        fastbrdf.render("pow", size="8x8", mesh="nosuch.obj")


def gpu_env(monkeypatch):
    if os.path.exists(LVP) and not os.environ.get("VK_ICD_FILENAMES") and not os.environ.get("VK_DRIVER_FILES"):
        monkeypatch.setenv("VK_ICD_FILENAMES", LVP)
    monkeypatch.setenv("WGPU_BACKEND", os.environ.get("WGPU_BACKEND", "vulkan"))


def test_gpu_equals_the_cli_gpu(cli, tmp_path, monkeypatch):
    gpu_env(monkeypatch)
    flags = ["--model", "flog", "--param", "n=50", "--floor", "--light", "point:2,3,3:1,1,1:20", "--size", "32x24", "--spp", "1"]
    want = cli_film(cli, tmp_path, flags + ["--gpu"])
    got = fastbrdf.render("flog", n=50, floor=True, lights=["point:2,3,3:1,1,1:20"], size="32x24", spp=1, gpu=True)
    assert got.shape == (24, 32, 3) and got.max() > 0
    np.testing.assert_array_equal(got, want)
    # The GPU's picture is the CPU's within 2/255 in sRGB (fastbrdf-gpu's tests/render.rs); here
    # on the linear film, a loose check that it is the same scene.
    cpu = fastbrdf.render("flog", n=50, floor=True, lights=["point:2,3,3:1,1,1:20"], size="32x24", spp=1)
    assert np.abs(got - cpu).mean() < 0.02 * cpu.mean()


def test_gpu_environment_light_equals_the_cli_gpu(cli, tmp_path, monkeypatch):
    # Environment light on the GPU (as `render --gpu --env`, issue 32): the CLI's film to the bit.
    gpu_env(monkeypatch)
    flags = ["--model", "cook-torrance", "--param", "alpha=0.3", "--env", "sky", "--env-samples", "2", "--size", "16x12", "--spp", "1"]
    want = cli_film(cli, tmp_path, flags + ["--gpu"])
    got = fastbrdf.render("cook-torrance", alpha=0.3, env="sky", env_samples=2, size="16x12", spp=1, gpu=True)
    assert got.shape == (12, 16, 3) and got.max() > 0
    np.testing.assert_array_equal(got, want)


def test_gpu_without_an_adapter_is_a_runtime_error(tmp_path):
    """No Vulkan driver at all: a RuntimeError saying so, never a crash (in a fresh process,
    so that this one's Vulkan loader is not involved)."""
    code = (
        "import fastbrdf\n"
        "try:\n"
        "    fastbrdf.render('flog', size='8x8', spp=1, gpu=True)\n"
        "except RuntimeError as e:\n"
        "    print('RuntimeError', e)\n"
    )
    env = {**os.environ, "VK_ICD_FILENAMES": str(tmp_path / "none.json"), "WGPU_BACKEND": "vulkan"}
    env.pop("VK_DRIVER_FILES", None)
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=120)
    assert p.returncode == 0, p.stderr
    assert p.stdout.startswith("RuntimeError no GPU adapter found"), p.stdout + p.stderr


def test_compare_equals_the_cli_json(cli, tmp_path):
    for args, kw in [
        (["--models", "flog,schlick", "--reference", "pow", "--param", "n=100"],
         dict(models="flog,schlick", reference="pow", n=100)),
        (["--models", "ggx,beckmann-power16", "--reference", "cook-torrance", "--param", "alpha=0.2", "--metal", "gold",
          "--exposure", "2", "--floor"],
         dict(models=["ggx", "beckmann-power16"], reference="cook-torrance", alpha=0.2, metal="gold", exposure=2, floor=True)),
        (["--models", "ward", "--reference", "cook-torrance", "--material", "gold-paint", "--env", "sky", "--env-samples", "2"],
         dict(models=["ward"], reference="cook-torrance", material="gold-paint", env="sky", env_samples=2)),
    ]:
        rc, out, err = cli("compare", *args, "--size", "16x16", "--spp", "1", "--json", "--out", str(tmp_path / "c.png"))
        assert rc == 0, err
        got = fastbrdf.compare(**kw, size="16x16", spp=1)
        assert got == json.loads(out)


def test_compare_with_measured_data_and_films(cli, tmp_path):
    path = str(tmp_path / "lambert.binary")
    fastbrdf.write_merl(path, np.array([0.5, 0.4, 0.3]) / np.pi)
    rc, out, err = cli("compare", "--models", "lambert,pow", "--measured", path, "--weights", "1,0", "--albedo", "0.5,0.4,0.3",
                       "--size", "16x12", "--spp", "1", "--json", "--out", str(tmp_path / "c.png"))
    assert rc == 0, err
    got = fastbrdf.compare(["lambert", "pow"], measured=path, weights=(1, 0), albedo=(0.5, 0.4, 0.3), size="16x12", spp=1, films=True)
    films = got.pop("films")
    assert got == json.loads(out)
    assert films.shape == (3, 12, 16, 3) and films.dtype == np.float32
    # The reference film is the measured render, as Measured.render draws it.
    np.testing.assert_array_equal(films[0], fastbrdf.Measured(path).render(width=16, height=12, spp=1))
    # With weights (1, 0) the models' specular terms weigh nothing: both films are the
    # diffuse term alone, so they are equal, and so are their scores.
    np.testing.assert_array_equal(films[1], films[2])
    assert got["metrics"][0]["rmse"] == got["metrics"][1]["rmse"] > 0
    with pytest.raises(ValueError, match="reference, measured: give exactly one"):
        fastbrdf.compare(["flog"], "pow", measured=path)
    with pytest.raises(ValueError, match="parameter alpha: none of the models takes it"):
        fastbrdf.compare(["flog"], "pow", alpha=0.3)


def test_materials_and_metals_equal_the_cli(cli):
    rc, out, err = cli("materials", "--json")
    assert rc == 0, err
    assert fastbrdf.materials() == json.loads(out)
    rc, out, err = cli("metals", "--json")
    assert rc == 0, err
    assert fastbrdf.metals() == json.loads(out)

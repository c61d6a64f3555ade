"""fastbrdf.Measured, fastbrdf.write_merl and fastbrdf.fit_measured against the CLI's
`fastbrdf measured info|eval|render` and `fastbrdf fit-measured` on synthetic MERL files.

The files are written in each test session's tmp folder by `fastbrdf.write_merl` (numpy: the
int32 header 90, 90, 180, then the R, G and B channels of float64 divided by their scales, a
negative value written as -1), never read from ../shared: no real MERL file is needed. The CLI
reads them with the library's reader, so a file this module writes wrongly fails here.
"""

import json
import math
import os
import pickle
import struct
import zlib

import numpy as np
import pytest

import fastbrdf

SCALE = np.array([1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0])
DIMS = (90, 90, 180)


def angles():
    """The bins' centre angles, computed here (not by the module under test)."""
    th = ((np.arange(90) + 0.5) / 90) ** 2 * (np.pi / 2)
    td = (np.arange(90) + 0.5) / 90 * (np.pi / 2)
    pd = (np.arange(180) + 0.5) / 180 * np.pi
    return np.meshgrid(th, td, pd, indexing="ij")


def varied(th, td, pd):
    """A BRDF that differs from bin to bin in every channel, missing where theta_d > 60
    degrees in green only (so the channels' statistics differ)."""
    r = 0.05 + 2.0 * np.cos(th) ** 30
    g = np.where(td > np.radians(60), -1.0, 0.1 + 0.2 * np.cos(td))
    b = 0.01 + 0.003 * pd + 0.5 * np.cos(th) ** 5
    return np.stack([r, g, b], axis=-1)


def shiny(th, td, pd):
    """kd / pi + ks cos(theta_h)^25 per channel: blinn-phong with norm=none, exactly."""
    kd, ks = np.array([0.3, 0.2, 0.1]), np.array([0.6, 0.5, 0.4])
    return kd / np.pi + ks * (np.cos(th) ** 25)[..., None]


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    d = tmp_path_factory.mktemp("merl")
    out = {}
    for name, f in (("varied", varied), ("shiny", shiny)):
        p = d / f"{name}.binary"
        fastbrdf.write_merl(p, f)
        out[name] = str(p)
    yield out
    for p in out.values():
        os.remove(p)


def test_write_merl_bytes_follow_the_format(files):
    raw = open(files["varied"], "rb").read()
    assert len(raw) == 34_992_012
    assert struct.unpack("<3i", raw[:12]) == DIMS
    body = np.frombuffer(raw, dtype="<f8", offset=12).reshape(3, *DIMS)
    want = varied(*angles())
    for c in range(3):
        v = want[..., c]
        np.testing.assert_array_equal(body[c], np.where(v < 0, -1.0, v / SCALE[c]))


def test_info_equals_the_cli_and_the_data(cli, files):
    for name, path in files.items():
        m = fastbrdf.Measured(path)
        rc, out, err = cli("measured", "info", path, "--json")
        assert rc == 0, err
        assert m.info() == json.loads(out), name
    # The statistics, from the values written (computed here with numpy).
    info = fastbrdf.Measured(files["varied"]).info()
    want = varied(*angles())
    for c, ch in enumerate(info["channels"]):
        stored = np.where(want[..., c] < 0, -1.0, want[..., c] / SCALE[c]) * SCALE[c]
        valid = stored[stored >= 0]
        assert ch["valid"] == valid.size and ch["missing"] == stored.size - valid.size
        # A sequential sum (the library) against numpy's pairwise one: n eps apart at most.
        assert math.isclose(ch["mean"], valid.mean(), rel_tol=1e-9)
        assert ch["min"] == valid.min() and ch["max"] == valid.max()
    assert info["channels"][1]["missing"] == 90 * 180 * np.count_nonzero(
        (np.arange(90) + 0.5) / 90 * 90 > 60
    )


def random_dirs(rng, n):
    wi = rng.normal(size=(n, 3))
    wo = rng.normal(size=(n, 3))
    wi[:, 2] = np.abs(wi[:, 2])
    wo[:, 2] = np.abs(wo[:, 2])
    wi[:5, 2] *= -1  # below the horizon: 0
    wo[5] = 0.0  # a zero vector: 0
    wi[6] = wo[6] = (0.0, 0.0, 2.0)  # normal incidence, any length
    return wi, wo


@pytest.mark.parametrize("precision", ["f32", "f64"])
def test_eval_equals_the_cli(cli, files, tmp_path, precision):
    rng = np.random.default_rng(7)
    wi, wo = random_dirs(rng, 400)
    lines = ["wi_x,wi_y,wi_z,wo_x,wo_y,wo_z"]
    lines += [",".join(repr(float(x)) for x in (*a, *b)) for a, b in zip(wi, wo)]
    csv = tmp_path / "in.csv"
    csv.write_text("\n".join(lines) + "\n")
    path = files["varied"]
    rc, out, err = cli("measured", "eval", path, "--input", str(csv), "--precision", precision)
    assert rc == 0, err
    dtype = np.float32 if precision == "f32" else np.float64
    want = np.array([[float(x) for x in row.split(",")[6:]] for row in out.splitlines()[1:]], dtype=dtype)
    got = fastbrdf.Measured(path).eval(wi, wo, precision=precision)
    assert got.dtype == dtype and got.shape == (400, 3)
    np.testing.assert_array_equal(got, want)
    assert np.all(got[:6] == 0) and np.all(got[7] > 0)
    # Not a constant: the rows differ (the lookup reads many bins).
    assert len(np.unique(got[:, 0])) > 50


def test_eval_broadcasts_and_follows_the_array_rules(files):
    m = fastbrdf.Measured(files["varied"])
    rng = np.random.default_rng(3)
    wo = np.abs(rng.normal(size=(4, 5, 3)))
    wi = np.array([0.2, 0.1, 0.9])
    got = m.eval(wi, wo)
    assert got.shape == (4, 5, 3) and got.dtype == np.float32
    full = m.eval(np.broadcast_to(wi, wo.shape).copy(), wo)
    np.testing.assert_array_equal(got, full)
    # A strided (non-contiguous) input reads the same as its copy.
    big = np.abs(rng.normal(size=(10, 6)))
    np.testing.assert_array_equal(m.eval(big[:, :3], big[:, 3:]), m.eval(big[:, :3].copy(), big[:, 3:].copy()))
    one = m.eval([0, 0, 1], [0, 0, 1], precision="f64")
    assert one.shape == (3,) and one.dtype == np.float64
    assert one[0] == pytest.approx(0.05 + 2.0 * math.cos(((0.5 / 90) ** 2) * math.pi / 2) ** 30)
    with pytest.raises(ValueError, match=r"wi: expected shape \(\.\.\., 3\)"):
        m.eval([0, 1], [0, 0, 1])
    with pytest.raises(ValueError, match="shapes do not broadcast"):
        m.eval(np.ones((2, 3)), np.ones((3, 3)))
    with pytest.raises(TypeError, match="wo: dtype"):
        m.eval([0, 0, 1], ["a", "b", "c"])
    with pytest.raises(ValueError, match="precision 'f16'"):
        m.eval([0, 0, 1], [0, 0, 1], precision="f16")


def read_exr(path):
    """The RGB float32 pixels of a scanline OpenEXR file without or with ZIP compression (what
    the render crate writes), read with the standard library and numpy (OpenEXR 2 layout:
    header attributes, the chunk offset table, chunks of lines, channels in name order)."""
    raw = open(path, "rb").read()
    assert raw[:4] == b"\x76\x2f\x31\x01", "not an OpenEXR file"
    pos, attrs = 8, {}
    while raw[pos] != 0:
        end = raw.index(b"\0", pos)
        name = raw[pos:end].decode()
        tend = raw.index(b"\0", end + 1)
        size = struct.unpack_from("<i", raw, tend + 1)[0]
        attrs[name] = raw[tend + 5 : tend + 5 + size]
        pos = tend + 5 + size
    pos += 1
    chans, c = [], attrs["channels"]
    i = 0
    while c[i] != 0:
        e = c.index(b"\0", i)
        ptype = struct.unpack_from("<i", c, e + 1)[0]
        assert ptype == 2, "FLOAT channels expected"
        chans.append(c[i:e].decode())
        i = e + 17
    compression = attrs["compression"][0]
    lines_per = {0: 1, 2: 1, 3: 16}[compression]
    x0, y0, x1, y1 = struct.unpack("<4i", attrs["dataWindow"])
    w, h = x1 - x0 + 1, y1 - y0 + 1
    n_chunks = -(-h // lines_per)
    offsets = struct.unpack_from(f"<{n_chunks}Q", raw, pos)
    img = {ch: np.zeros((h, w), np.float32) for ch in chans}
    for off in offsets:
        y, size = struct.unpack_from("<ii", raw, off)
        data = raw[off + 8 : off + 8 + size]
        lines = min(lines_per, y1 + 1 - y)
        full = lines * len(chans) * w * 4
        if size < full:
            t = np.frombuffer(zlib.decompress(data), np.uint8).astype(np.int64)
            t[1:] -= 128
            t = (np.cumsum(t) % 256).astype(np.uint8)
            half = (t.size + 1) // 2
            u = np.empty_like(t)
            u[0::2], u[1::2] = t[:half], t[half:]
            data = u.tobytes()
        vals = np.frombuffer(data, "<f4").reshape(lines, len(chans), w)
        for k, ch in enumerate(chans):
            img[ch][y - y0 : y - y0 + lines] = vals[:, k]
    return np.stack([img["R"], img["G"], img["B"]], axis=-1)


@pytest.mark.parametrize(
    "kw, flags",
    [
        (dict(width=40, height=24, spp=1, lights=["dir:0.3,0.5,1", "point:2,2,3:1,0.5,0.2:4"], floor=True),
         ["--size", "40x24", "--spp", "1", "--light", "dir:0.3,0.5,1", "--light", "point:2,2,3:1,0.5,0.2:4", "--floor"]),
        (dict(width=24, height=20, spp=2, mesh="face", env="sky", env_samples=2, shadows=False),
         ["--size", "24x20", "--spp", "2", "--mesh", "face", "--env", "sky", "--env-samples", "2", "--shadows", "off"]),
    ],
)
def test_render_equals_the_cli_exr(cli, files, tmp_path, kw, flags):
    path = files["shiny"]
    out = tmp_path / "m.exr"
    rc, _, err = cli("measured", "render", path, "--out", str(out), *flags)
    assert rc == 0, err
    want = read_exr(out)
    m = fastbrdf.Measured(path)
    got = m.render(**kw)
    assert got.dtype == np.float32 and got.shape == (kw["height"], kw["width"], 3)
    assert got.max() > 0 and np.all(np.isfinite(got))
    np.testing.assert_array_equal(got, want)


def test_render_refuses_bad_options(files):
    m = fastbrdf.Measured(files["shiny"])
    with pytest.raises(ValueError, match="spp 0: must be 1 to 16"):
        m.render(width=8, height=8, spp=0)
    with pytest.raises(TypeError, match="width: expected an int"):
        m.render(width=8.0)
    with pytest.raises(ValueError, match="env_samples 0"):
        m.render(width=8, height=8, env="sky", env_samples=0)
    with pytest.raises(ValueError, match="nosuch.obj"):
        m.render(width=8, height=8, mesh="nosuch.obj")
    with pytest.raises(ValueError, match="light"):
        m.render(width=8, height=8, lights=["sun:1,2"])
    # Switches are strict: "off" is the CLI's word, any other text is refused (bool("no") is
    # True, which rendered shadows and a floor the caller had turned off).
    with pytest.raises(TypeError, match="shadows: expected a bool or 'on'/'off', got str"):
        m.render(width=8, height=8, shadows="no")
    with pytest.raises(TypeError, match="floor: expected a bool, got str"):
        m.render(width=8, height=8, floor="no")


def test_render_size_and_switches_as_the_cli_spells_them(files):
    m = fastbrdf.Measured(files["shiny"])
    lit = dict(spp=1, floor=True, lights=["point:2,3,3:1,1,1:20"])
    off = m.render(size="24x16", shadows="off", **lit)
    np.testing.assert_array_equal(off, m.render(width=24, height=16, shadows=False, **lit))
    np.testing.assert_array_equal(off, m.render(size=(24, 16), shadows=False, **lit))
    assert not np.array_equal(off, m.render(size="24x16", shadows="on", **lit))


def fit_cli(cli, tmp_path, path, model, *flags):
    pic = tmp_path / "fit.png"
    rc, out, err = cli("fit-measured", "--data", path, "--model", model, "--json", "--out", str(pic),
                       "--size", "8x8", "--spp", "1", *flags)
    assert rc == 0, err
    return json.loads(out)


@pytest.mark.parametrize(
    "model, kw, flags",
    [
        ("blinn-phong", dict(norm="none", samples=600, restarts=2),
         ["--param", "norm=none", "--samples", "600", "--restarts", "2"]),
        ("cook-torrance", dict(f="schlick", metric="low-log", samples=300, restarts=1),
         ["--param", "f=schlick", "--metric", "low-log", "--samples", "300", "--restarts", "1"]),
    ],
)
def test_fit_equals_the_cli(cli, files, tmp_path, model, kw, flags):
    path = files["shiny"]
    want = fit_cli(cli, tmp_path, path, model, *flags)
    # From a path and from a Measured: the same document.
    for data in (path, fastbrdf.Measured(path)):
        got = fastbrdf.fit_measured(data, model, **kw)
        assert got["picture"] is None and got["fit_seconds"] > 0
        assert want["picture"].endswith("fit.png")
        for k in ("picture", "fit_seconds"):
            del got[k]
        # Everything else is equal, numbers exactly: the fit is deterministic (a fixed-seed
        # subsample, a sequential Nelder-Mead), and both print the same function's document.
        assert got == {k: v for k, v in want.items() if k not in ("picture", "fit_seconds")}
    if model == "blinn-phong":
        # The data are exact at the bin centres the fit samples: it recovers them.
        assert got["params"]["n"] == pytest.approx(25, rel=1e-4)
        assert got["rho_d"] == pytest.approx([0.3, 0.2, 0.1], rel=1e-4)
        assert got["rho_s"] == pytest.approx([0.6, 0.5, 0.4], rel=1e-4)
        assert got["residuals"]["ngan-l2"] < 1e-6
    else:
        assert got["held"] == {"f90": 1.0} and got["metric"] == "low-log"


def test_fit_free_and_undetermined_warn_like_the_cli(cli, files, tmp_path):
    path = files["varied"]
    # Lambert against lambert data: rho_d and rho_s trade exactly, named on stderr by the CLI.
    want = fit_cli(cli, tmp_path, path, "lambert", "--samples", "200", "--restarts", "1")
    with pytest.warns(UserWarning, match="do not determine"):
        got = fastbrdf.fit_measured(path, "lambert", samples=200, restarts=1)
    assert got["undetermined"] == want["undetermined"] and got["undetermined"]


def test_fit_refuses_bad_arguments(files):
    m = fastbrdf.Measured(files["shiny"])
    with pytest.raises(ValueError, match="restarts 0: must be 1 to 64"):
        fastbrdf.fit_measured(m, "ward", restarts=0)
    with pytest.raises(ValueError, match="restarts 65"):
        fastbrdf.fit_measured(m, "ward", restarts=65)
    with pytest.raises(TypeError, match="samples: expected an int"):
        fastbrdf.fit_measured(m, "ward", samples=1.5)
    with pytest.raises(ValueError, match="metric 'l1'"):
        fastbrdf.fit_measured(m, "ward", metric="l1")
    with pytest.raises(ValueError, match="model nosuch: "):
        fastbrdf.fit_measured(m, "nosuch")
    with pytest.raises(ValueError, match="model ward: "):
        fastbrdf.fit_measured(m, "ward", alpha=-1)
    with pytest.raises(ValueError, match="^free alpha: alpha is fitted already; free only adds"):
        fastbrdf.fit_measured(m, "cook-torrance", free=["alpha"])
    with pytest.raises(ValueError, match="^free f90: "):
        fastbrdf.fit_measured(m, "cook-torrance", f="none", free="f90")
    with pytest.raises(TypeError, match="data: expected a path"):
        fastbrdf.fit_measured(3, "ward")


def test_bad_files_name_the_file(tmp_path, files):
    missing = tmp_path / "missing.binary"
    with pytest.raises(ValueError, match="missing.binary"):
        fastbrdf.Measured(missing)
    short = tmp_path / "short.binary"
    short.write_bytes(open(files["shiny"], "rb").read(1000))
    with pytest.raises(ValueError, match="short.binary.*34992012 bytes expected"):
        fastbrdf.Measured(short)
    header = tmp_path / "header.binary"
    header.write_bytes(struct.pack("<3i", 90, 90, 90) + b"\0" * 64)
    with pytest.raises(ValueError, match="header.binary.*dimensions 90 x 90 x 90"):
        fastbrdf.Measured(header)
    nan = tmp_path / "nan.binary"
    raw = bytearray(open(files["shiny"], "rb").read())
    raw[12 + 8 * 5 : 12 + 8 * 6] = struct.pack("<d", float("nan"))
    nan.write_bytes(bytes(raw))
    with pytest.raises(ValueError, match="nan.binary.*red channel, sample 5"):
        fastbrdf.Measured(nan)
    with pytest.raises(ValueError, match="nan.binary"):
        fastbrdf.fit_measured(str(nan), "ward")
    with pytest.raises(TypeError, match="path: expected a path"):
        fastbrdf.Measured(5)
    with pytest.raises(ValueError, match="values: shape"):
        fastbrdf.write_merl(tmp_path / "x.binary", [1.0, 2.0])
    with pytest.raises(ValueError, match="finite"):
        fastbrdf.write_merl(tmp_path / "x.binary", [1.0, np.nan, 2.0])
    assert not (tmp_path / "x.binary").exists()


def test_pickle_and_repr(files):
    m = fastbrdf.Measured(files["shiny"])
    assert repr(m) == f"fastbrdf.Measured({files['shiny']!r})"
    back = pickle.loads(pickle.dumps(m))
    assert back.path == m.path and back.info() == m.info()
    d = [[0.1, 0.2, 0.9]]
    np.testing.assert_array_equal(back.eval(d, d), m.eval(d, d))
    assert eval(repr(m), {"fastbrdf": fastbrdf}).path == m.path
    assert fastbrdf.Measured(pathlib_path(files["shiny"])).path == files["shiny"]


def pathlib_path(p):
    import pathlib

    return pathlib.Path(p)


INTERRUPT = """
import os, signal, sys, threading, time
import numpy as np
import fastbrdf

m = fastbrdf.Measured(sys.argv[1])
t0 = time.perf_counter()
threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT)).start()
try:
    {CALL}
except KeyboardInterrupt:
    print("interrupted", time.perf_counter() - t0)
else:
    print("finished", time.perf_counter() - t0)
"""


@pytest.mark.parametrize(
    "call",
    [
        # 64 joint searches of 20000 samples: about a minute; one run is well under a second.
        "fastbrdf.fit_measured(m, 'cook-torrance', f='schlick', metric='max', samples=20000, restarts=64)",
        "m.render(width=2048, height=2048, spp=16)",
    ],
)
def test_ctrl_c_stops_a_fit_and_a_render(files, call):
    import subprocess
    import sys

    code = INTERRUPT.replace("{CALL}", call)
    try:
        p = subprocess.run([sys.executable, "-c", code, files["shiny"]], capture_output=True, text=True, timeout=120)
    except subprocess.TimeoutExpired as e:
        pytest.fail(f"did not finish in 120 s (stdout {e.stdout!r})")
    assert p.returncode == 0, p.stderr[-2000:]
    word, seconds = p.stdout.split()
    assert word == "interrupted" and float(seconds) < 4.0, p.stdout

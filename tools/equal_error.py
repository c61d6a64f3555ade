#!/usr/bin/env python3
"""Time to equal error: fastbrdf against Mitsuba 3 on matched scenes (issue 30).

Renders four scenes (the sphere and the built-in face, under the default key light and under
the built-in sky) with `fastbrdf render` and, where it is installed, with Mitsuba 3.9.1
(llvm_ad_rgb, its `independent` and `multijitter` samplers) at a ladder of sample counts. Each
renderer's error is measured against its OWN converged reference; the target error of a scene is
fastbrdf's error at its defaults (--spp 2, --env-samples 16); the time each renderer needs to
reach it is interpolated along its ladder (log error against log time). Prints the README table
(markdown) with the CPU named and writes everything to a JSON file.

Run (docs/book/src/equal-error.md):
  cargo build --release -p fastbrdf-cli
  DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM-19.so \\
    target/python-wheel-venv/bin/python tools/equal_error.py --full --out-json equal-error.json
Mitsuba is optional (`pip install mitsuba==3.9.1`; its llvm variants need Debian's libllvm19
and DRJIT_LIBLLVM_PATH); without it only fastbrdf's columns are filled. --quick is a smoke run
(64x64, short ladders) of well under a minute.

Error metric: relative MSE, mean over pixels and channels of (x - ref)^2 / (ref^2 + 1e-2)
(Rousselle et al. 2011's relMSE with the epsilon of Mitsuba's and Bitterli's tools), so dark
and bright regions count alike and the error is comparable across renderers whose references
differ slightly. Time: the render alone (fastbrdf's printed "render X s", which leaves out the
model's set-up as Mitsuba's time leaves out load_dict; Mitsuba's mi.render after a warm-up
render of the same scene, sampler and sample count, so JIT compilation is excluded; fastbrdf
--gpu's printed "draws X s", after the device and pipelines are set up, which is mostly the
driver compiling shaders; both fastbrdf's at the second render of one process, `render
--repeat 2`, as Mitsuba's after its warm-up, the first kept as the cold time), the median of
--repeats runs, renderers interleaved.
"""

from __future__ import annotations

import argparse
import functools
import json
import math
import os
import pathlib
import platform
import re
import struct
import subprocess
import sys
import tempfile
import time
import zlib
from typing import Any, Callable, Dict, List, Optional, Tuple

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]
FACE_OBJ = ROOT / "crates" / "render" / "data" / "canonical_face_model.obj"
LLVM = "/usr/lib/x86_64-linux-gnu/libLLVM-19.so"
LAVAPIPE = "/usr/share/vulkan/icd.d/lvp_icd.x86_64.json"
EPS = 1e-2
# A ladder is climbed until its error falls below STOP x the target error.
STOP = 0.5

# The scene fastbrdf draws by default (crates/render/src/setup.rs): kd 0.6 x albedo 0.8
# Lambert + ks 0.4 x the specular BRDF, the key light towards (-0.45, 0.55, 0.7) of irradiance
# 3, an ambient term 0.04 x kd x albedo on every hit and a background of 0.015 (both only
# without an environment); the sphere of radius 1 seen from (0, 0, 4.6), fov_y 30 degrees.
KD, KS, ALBEDO = 0.6, 0.4, 0.8
KEY_DIR = np.array([-0.45, 0.55, 0.7])
KEY_DIR = KEY_DIR / np.linalg.norm(KEY_DIR)
KEY_IRRADIANCE = 3.0
AMBIENT, BACKGROUND = 0.04, 0.015
FOV_Y = 30.0
MODEL = ["--model", "cook-torrance", "--param", "d=ggx", "--param", "alpha=0.3"]
ALPHA = 0.3

SCENES: Dict[str, Dict[str, Any]] = {
    "sphere-directional": {"label": "sphere, directional light", "mesh": False, "env": False},
    "face-directional": {"label": "face, directional light", "mesh": True, "env": False},
    "sphere-sky": {"label": "sphere, built-in sky", "mesh": False, "env": True},
    "face-sky": {"label": "face, built-in sky", "mesh": True, "env": True},
}


def log(msg: str) -> None:
    print(f"[equal_error {time.strftime('%H:%M:%S')}] {msg}", file=sys.stderr, flush=True)


def cpu_name() -> str:
    try:
        for line in pathlib.Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


# ---------------------------------------------------------------------------------------------
# OpenEXR (scanline, uncompressed / ZIPS / ZIP, HALF or FLOAT): what `fastbrdf render --out
# x.exr` writes, read without any image library so that fastbrdf's columns need numpy alone.


def read_exr(path: pathlib.Path) -> np.ndarray:
    """The R, G, B channels of a scanline OpenEXR file as a float32 (height, width, 3) array."""
    data = pathlib.Path(path).read_bytes()
    if data[:4] != b"\x76\x2f\x31\x01":
        raise ValueError(f"{path}: not an OpenEXR file")
    if data[5] & 0x02:
        raise ValueError(f"{path}: tiled OpenEXR files are not read here")
    pos, attrs = 8, {}
    while data[pos] != 0:
        end = data.index(b"\0", pos)
        name = data[pos:end].decode()
        end2 = data.index(b"\0", end + 1)
        size = struct.unpack_from("<i", data, end2 + 1)[0]
        attrs[name] = data[end2 + 5 : end2 + 5 + size]
        pos = end2 + 5 + size
    pos += 1
    channels: List[Tuple[str, int]] = []
    c = attrs["channels"]
    i = 0
    while c[i] != 0:
        end = c.index(b"\0", i)
        channels.append((c[i:end].decode(), struct.unpack_from("<i", c, end + 1)[0]))
        i = end + 1 + 16
    comp = attrs["compression"][0]
    x0, y0, x1, y1 = struct.unpack("<4i", attrs["dataWindow"])
    w, h = x1 - x0 + 1, y1 - y0 + 1
    lines = {0: 1, 2: 1, 3: 16}.get(comp)
    if lines is None:
        raise ValueError(f"{path}: compression {comp} is not read here (none, ZIPS, ZIP only)")
    nchunks = (h + lines - 1) // lines
    offsets = struct.unpack_from(f"<{nchunks}Q", data, pos)
    dtypes = {1: np.float16, 2: np.float32}
    sizes = [np.dtype(dtypes[t]).itemsize for _, t in channels]
    out = {n: np.zeros((h, w), np.float32) for n, _ in channels}
    for off in offsets:
        y, size = struct.unpack_from("<ii", data, off)
        raw = data[off + 8 : off + 8 + size]
        n = min(lines, y1 + 1 - y)
        expect = n * w * sum(sizes)
        if comp != 0 and size < expect:
            t = np.frombuffer(zlib.decompress(raw), np.uint8).astype(np.int32)
            t = np.cumsum(np.concatenate([t[:1], t[1:] - 128])) % 256  # undo the predictor
            t = t.astype(np.uint8)
            half = (len(t) + 1) // 2
            raw_arr = np.empty_like(t)
            raw_arr[0::2], raw_arr[1::2] = t[:half], t[half:]
            raw = raw_arr.tobytes()
        p = 0
        for row in range(n):
            for (name, typ), sz in zip(channels, sizes):
                out[name][y - y0 + row] = np.frombuffer(raw, dtypes[typ], w, p)
                p += w * sz
    return np.stack([out["R"], out["G"], out["B"]], axis=-1)


# ---------------------------------------------------------------------------------------------
# Error and interpolation


def rel_mse(x: np.ndarray, ref: np.ndarray) -> float:
    """Mean over pixels and channels of (x - ref)^2 / (ref^2 + 1e-2)."""
    x, ref = x[..., :3].astype(np.float64), ref[..., :3].astype(np.float64)
    return float(np.mean((x - ref) ** 2 / (ref * ref + EPS)))


def time_to_error(ladder: List[Dict[str, Any]], target: float) -> Tuple[Optional[float], str]:
    """The time at which the ladder's error reaches `target`: log-log interpolation between the
    two points that bracket it (along the ladder, in order of samples), else extrapolation from
    the two nearest ends ("extrapolated"). None when the ladder has fewer than two usable
    points."""
    pts = [(p["time_s"], p["error"]) for p in ladder if p["time_s"] > 0 and p["error"] > 0]
    if not pts:
        return None, "no points"
    for (t0, e0), (t1, e1) in zip(pts, pts[1:]):
        if (e0 - target) * (e1 - target) <= 0 and e0 != e1:
            f = (math.log(target) - math.log(e0)) / (math.log(e1) - math.log(e0))
            return math.exp(math.log(t0) + f * (math.log(t1) - math.log(t0))), "interpolated"
    if len(pts) < 2:
        return None, "one point"
    # Not bracketed: extend the end nearest the target.
    (t0, e0), (t1, e1) = (pts[0], pts[1]) if target > pts[0][1] else (pts[-2], pts[-1])
    if e0 == e1 or t0 == t1:
        return None, "flat"
    slope = (math.log(e1) - math.log(e0)) / (math.log(t1) - math.log(t0))
    if slope >= 0:
        return None, "error does not fall"
    return math.exp(math.log(t0) + (math.log(target) - math.log(e0)) / slope), "extrapolated"


def point_at_error(ladder: List[Dict[str, Any]], target: float) -> Optional[Dict[str, Any]]:
    """The cheapest point the ladder measured at or below `target` (a sample count the
    renderer was run at, no interpolation): {samples, time_s, error}, or None when no point
    reaches it. Interpolation between two points assumes a renderer could run between them,
    which Mitsuba can (any sample count) and fastbrdf cannot (N x N samples, adaptive from
    N = 2): this figure rounds each renderer up to a configuration it ran."""
    pts = [p for p in ladder if p["error"] <= target and p["time_s"] > 0]
    if not pts:
        return None
    p = min(pts, key=lambda p: p["time_s"])
    return {"samples": p["samples"], "time_s": p["time_s"], "error": p["error"]}


def cold_ladder(ladder: List[Dict[str, Any]]) -> List[Dict[str, Any]]:
    """The ladder's points timed at the first render of each process (`cold_time_s`, where
    the ladder was timed warm), as points of a ladder of their own."""
    return [dict(p, time_s=p["cold_time_s"]) for p in ladder if "cold_time_s" in p]


# ---------------------------------------------------------------------------------------------
# fastbrdf


class Fastbrdf:
    def __init__(self, binary: pathlib.Path, size: int, tmp: pathlib.Path, cold: bool = False):
        self.bin, self.size, self.tmp = binary, size, tmp
        helptext = subprocess.run(
            [str(binary), "render", "--help"], capture_output=True, text=True, check=True
        ).stdout
        self.has_sampler = "--sampler" in helptext
        self.has_aa = "--aa" in helptext
        self.has_env_sun = "--env-sun" in helptext
        # `render --repeat 2`: the ladders time the second render of the process, a warm one
        # as Mitsuba's after its warm-up render (`warm`, off with --cold-fastbrdf); the first
        # render's time is kept apart (`last_cold`).
        self.has_repeat = "--repeat" in helptext
        self.warm = self.has_repeat and not cold
        # Since `--repeat` takes `--gpu` too, the GPU's ladders time the second render's draws
        # on the same device (its first draws may compile the driver's shader variants).
        self.gpu_warm = self.warm and "With --gpu on one device" in " ".join(helptext.split())
        self.last_cold: Optional[float] = None
        v = subprocess.run([str(binary), "--version"], capture_output=True, text=True)
        self.version = v.stdout.strip()

    def args(self, scene: Dict[str, Any]) -> List[str]:
        a = MODEL + ["--size", f"{self.size}x{self.size}"]
        if scene["mesh"]:
            a += ["--mesh", "face"]
        if scene["env"]:
            a += ["--env", "sky"]
        return a

    def render_seeded(self, scene: Dict[str, Any], extra: List[str], gpu: bool, seed: int) -> Tuple[np.ndarray, float]:
        """`render` for the ladders, which pass a seed: fastbrdf's renders are deterministic."""
        return self.render(scene, extra, gpu, warm=self.gpu_warm if gpu else self.warm)

    def render(self, scene: Dict[str, Any], extra: List[str], gpu: bool = False,
               warm: bool = False) -> Tuple[np.ndarray, float]:
        """The picture and its render time: with `warm`, the second render of the process
        (`--repeat 2`), the first's time in `last_cold` (on the GPU, the draws')."""
        out = self.tmp / "fastbrdf.exr"
        cmd = [str(self.bin), "render", *self.args(scene), *extra, "--out", str(out)]
        if warm:
            cmd += ["--repeat", "2"]
        env = dict(os.environ)
        if gpu:
            cmd.append("--gpu")
            env.setdefault("VK_ICD_FILENAMES", LAVAPIPE)
            env.setdefault("WGPU_BACKEND", "vulkan")
        p = subprocess.run(cmd, capture_output=True, text=True, env=env)
        if p.returncode != 0:
            raise RuntimeError(f"{' '.join(cmd)}: {p.stderr.strip()}")
        t, self.last_cold = render_times(p.stderr, gpu, warm)
        return read_exr(out), t


def render_times(stderr: str, gpu: bool, warm: bool) -> Tuple[float, float]:
    """From `fastbrdf render`'s report: (the time timed, the first render's). On the CPU
    "render X s"; on the GPU the draws alone where the binary reports them ("draws X s": the
    set-up before them, device and pipelines, mostly the driver compiling the shaders, is left
    out as Mitsuba's JIT compilation is), else "render X s". With `warm` (`--repeat 2`) the time
    timed is the second render's, "(then Y s", the first's the other."""
    m = re.search(r"render ([0-9.]+) s", stderr)
    if not m:
        raise RuntimeError(f"no 'render X s' in fastbrdf's output: {stderr.strip()}")
    d = re.search(r"draws ([0-9.]+) s", stderr) if gpu else None
    what = "draws" if d else "render"
    first = float((d or m).group(1))
    if not warm:
        return first, first
    then = re.search(what + r" [0-9.]+ s \(then ([0-9.]+) s", stderr)
    if not then:
        raise RuntimeError(f"no '{what} X s (then Y s' in fastbrdf's output: {stderr.strip()}")
    return float(then.group(1)), first


# ---------------------------------------------------------------------------------------------
# Mitsuba


def import_mitsuba(variant: str) -> Tuple[Any, Any, str]:
    """(mitsuba, drjit, why not); the modules are None with the reason when unusable."""
    if variant.startswith("llvm") and "DRJIT_LIBLLVM_PATH" not in os.environ and os.path.exists(LLVM):
        os.environ["DRJIT_LIBLLVM_PATH"] = LLVM
    try:
        import drjit as dr
        import mitsuba as mi
    except ImportError as e:
        return None, None, f"Mitsuba is not importable ({e}): pip install mitsuba==3.9.1"
    try:
        mi.set_variant(variant)
    except Exception as e:  # noqa: BLE001 (Mitsuba raises plain exceptions here)
        return None, None, (
            f"Mitsuba's {variant} variant is unusable ({e}); llvm variants need Debian's "
            f"libllvm19 and DRJIT_LIBLLVM_PATH={LLVM}"
        )
    # Multijitter's "sample count rounded up" warnings would land in the table on stdout.
    mi.set_log_level(mi.LogLevel.Error)
    return mi, dr, ""


def sky_texels() -> np.ndarray:
    """The built-in sky of crates/render/src/env.rs (EnvMap::sky), 1024 x 512, in float32 as
    the renderer computes it, in fastbrdf's latitude-longitude layout."""
    w, h = 1024, 512
    f = np.float32
    u = (np.arange(w, dtype=f) + f(0.5)) / f(w)
    v = (np.arange(h, dtype=f) + f(0.5)) / f(h)
    phi = ((u - f(0.5)) * f(2 * math.pi))[None, :]
    theta = (v * f(math.pi))[:, None]
    st, ct = np.sin(theta), np.cos(theta)
    d = np.stack(np.broadcast_arrays(st * np.sin(phi), ct, -st * np.cos(phi)), axis=-1)
    horizon, zenith = np.array([0.85, 0.9, 1.0], f), np.array([0.2, 0.35, 0.75], f)
    ground = np.array([0.2, 0.18, 0.16], f)
    y = d[..., 1:2]
    sky = horizon + (zenith - horizon) * np.sqrt(np.maximum(y, 0))
    tex = np.where(y >= 0, sky, ground).astype(f)
    sun = KEY_DIR.astype(f)
    cos_r = f(math.cos(math.radians(2.0)))
    sun_l = np.array([1.0, 0.95, 0.85], f) * f(KEY_IRRADIANCE / (2 * math.pi * (1 - float(cos_r))))
    tex = tex + np.where((d @ sun)[..., None] >= cos_r, sun_l, f(0))
    return tex.astype(f)


def face_mesh() -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The built-in face: positions, triangles and fastbrdf's smooth normals (crates/render/src/
    mesh.rs smooth_normals: each triangle's normal weighted by its area and its angle at the
    vertex, vertices at one position sharing the normal)."""
    pos, tris = [], []
    for line in FACE_OBJ.read_text().splitlines():
        t = line.split()
        if not t:
            continue
        if t[0] == "v":
            pos.append([float(x) for x in t[1:4]])
        elif t[0] == "f":
            idx = [int(c.split("/")[0]) - 1 for c in t[1:]]
            for k in range(1, len(idx) - 1):
                tris.append([idx[0], idx[k], idx[k + 1]])
    p = np.array(pos, np.float64)
    f = np.array(tris, np.int64)
    _, group = np.unique(p, axis=0, return_inverse=True)
    group = group.reshape(-1)
    acc = np.zeros((group.max() + 1, 3))
    tp = p[f]
    cross = np.cross(tp[:, 1] - tp[:, 0], tp[:, 2] - tp[:, 0])
    for k in range(3):
        e1 = tp[:, (k + 1) % 3] - tp[:, k]
        e2 = tp[:, (k + 2) % 3] - tp[:, k]
        e1 /= np.maximum(np.linalg.norm(e1, axis=1, keepdims=True), 1e-30)
        e2 /= np.maximum(np.linalg.norm(e2, axis=1, keepdims=True), 1e-30)
        ang = np.arccos(np.clip(np.sum(e1 * e2, axis=1), -1, 1))
        np.add.at(acc, group[f[:, k]], cross * ang[:, None])
    n = acc[group]
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-30)
    return p, f, n


def camera(mesh: bool) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """eye, target, up as setup.rs builds them (Camera::framing along -z for a mesh)."""
    if not mesh:
        return np.array([0, 0, 4.6]), np.zeros(3), np.array([0.0, 1, 0])
    p, _, _ = face_mesh()
    lo, hi = p.min(axis=0), p.max(axis=0)
    c = 0.5 * (lo + hi)
    radius = 0.5 * np.linalg.norm(hi - lo)
    dist = radius / math.sin(math.radians(FOV_Y) * 0.5) * 1.05
    return c + np.array([0, 0, 1.0]) * dist, c, np.array([0.0, 1, 0])


def write_ply(path: pathlib.Path, p: np.ndarray, f: np.ndarray, n: np.ndarray) -> None:
    head = (
        "ply\nformat binary_little_endian 1.0\n"
        f"element vertex {len(p)}\nproperty float x\nproperty float y\nproperty float z\n"
        "property float nx\nproperty float ny\nproperty float nz\n"
        f"element face {len(f)}\nproperty list uchar int vertex_indices\nend_header\n"
    )
    verts = np.concatenate([p, n], axis=1).astype("<f4").tobytes()
    faces = b"".join(struct.pack("<B3i", 3, *t) for t in f.tolist())
    path.write_bytes(head.encode() + verts + faces)


class Mitsuba:
    """Matched Mitsuba scenes. Direct-light scenes render RGBA: fastbrdf's ambient term
    (0.04 kd albedo on every hit, no visibility, a constant with no noise) and background
    (0.015) are added from Mitsuba's own alpha (its sampled coverage), since no Mitsuba emitter
    is a per-hit constant."""

    def __init__(self, mi: Any, dr: Any, variant: str, size: int, tmp: pathlib.Path, env_roll: int):
        self.mi, self.dr, self.variant, self.size, self.tmp = mi, dr, variant, size, tmp
        self.env_roll = env_roll
        self.cache: Dict[Tuple[str, str], Any] = {}
        self.version = mi.__version__

    def scene(self, name: str, sampler: str) -> Any:
        key = (name, sampler)
        if key in self.cache:
            return self.cache[key]
        mi = self.mi
        sc = SCENES[name]
        eye, target, up = camera(sc["mesh"])
        bsdf = {
            "type": "twosided",
            "inner": {
                "type": "blendbsdf",
                "weight": KS,
                "a": {"type": "diffuse", "reflectance": {"type": "rgb", "value": ALBEDO}},
                # F = 1 (fastbrdf's default f = none): Mitsuba's material "none", a perfect
                # reflector (eta 0, k 1).
                "b": {
                    "type": "roughconductor",
                    "distribution": "ggx",
                    "alpha": ALPHA,
                    "sample_visible": True,
                    "material": "none",
                },
            },
        }
        if sc["mesh"]:
            ply = self.tmp / "face.ply"
            if not ply.exists():
                write_ply(ply, *face_mesh())
            shape = {"type": "ply", "filename": str(ply), "face_normals": False, "bsdf": bsdf}
        else:
            shape = {"type": "sphere", "center": [0, 0, 0], "radius": 1.0, "bsdf": bsdf}
        d: Dict[str, Any] = {
            "type": "scene",
            "integrator": {"type": "direct"},
            "sensor": {
                "type": "perspective",
                "fov": FOV_Y,
                "fov_axis": "y",
                "to_world": mi.ScalarTransform4f().look_at(
                    origin=eye.tolist(), target=target.tolist(), up=up.tolist()
                ),
                "film": {
                    "type": "hdrfilm",
                    "width": self.size,
                    "height": self.size,
                    "rfilter": {"type": "box"},
                    "pixel_format": "rgb" if sc["env"] else "rgba",
                },
                "sampler": {"type": sampler, "sample_count": 4},
            },
            "object": shape,
        }
        if sc["env"]:
            tex = np.roll(sky_texels(), self.env_roll, axis=1)
            d["sky"] = {"type": "envmap", "bitmap": mi.Bitmap(np.ascontiguousarray(tex))}
        else:
            d["key"] = {
                "type": "directional",
                "direction": (-KEY_DIR).tolist(),
                "irradiance": {"type": "rgb", "value": KEY_IRRADIANCE},
            }
        s = mi.load_dict(d)
        self.cache[key] = s
        return s

    def render(self, name: str, sampler: str, spp: int, seed: int) -> Tuple[np.ndarray, float]:
        mi, dr = self.mi, self.dr
        s = self.scene(name, sampler)
        t = time.perf_counter()
        img = mi.render(s, spp=spp, seed=seed)
        dr.eval(img)
        dr.sync_thread()
        dt = time.perf_counter() - t
        a = np.array(img, dtype=np.float32)
        if a.shape[-1] == 4:
            alpha = a[..., 3:4]
            a = a[..., :3] + alpha * (AMBIENT * KD * ALBEDO) + (1 - alpha) * BACKGROUND
        return a, dt


# ---------------------------------------------------------------------------------------------
# The benchmark


def ladders(quick: bool, full: bool) -> Dict[str, Any]:
    if quick:
        return {
            "size": 64,
            "repeats": 1,
            "fb_spp": [1, 2, 3],
            "fb_ref_spp": 8,
            "fb_env": [4, 16, 64],
            "fb_env_ref": (4, 64),
            "mi_spp": [4, 16, 64, 256],
            "mi_ref_spp": 1024,
        }
    return {
        "size": 512,
        "repeats": 5 if full else 3,
        "fb_spp": [1, 2, 3, 4],
        "fb_ref_spp": 16,
        "fb_env": [1, 2, 4, 8, 16, 32, 64, 128],
        "fb_env_ref": (4, 256) if full else (4, 128),
        "mi_spp": [1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024],
        "mi_ref_spp": 4096 if full else 2048,
    }


def median(xs: List[float]) -> float:
    s = sorted(xs)
    n = len(s)
    return s[n // 2] if n % 2 else 0.5 * (s[n // 2 - 1] + s[n // 2])


def spread(xs: List[float]) -> float:
    """(max - min) / median: how noisy the repeats were."""
    m = median(xs)
    return (max(xs) - min(xs)) / m if m > 0 else 0.0


def run(opts: argparse.Namespace, tmp: pathlib.Path) -> Dict[str, Any]:
    """The benchmark; the renderers' files go in `tmp` (the caller removes it)."""
    L = ladders(opts.quick, opts.full)
    size = opts.size or L["size"]
    repeats = opts.repeats or L["repeats"]
    fb = Fastbrdf(pathlib.Path(opts.fastbrdf), size, tmp, cold=opts.cold_fastbrdf)
    samplers = ["sobol", "independent"] if fb.has_sampler else [None]
    mi_obj: Optional[Mitsuba] = None
    mi_note = "not requested (--no-mitsuba)"
    if not opts.no_mitsuba:
        mi, dr, why = import_mitsuba(opts.mitsuba_variant)
        if mi is None:
            mi_note = why
            log(f"Mitsuba skipped: {why}")
        else:
            mi_obj = Mitsuba(mi, dr, opts.mitsuba_variant, size, tmp, opts.env_roll)
            mi_note = f"mitsuba {mi.__version__} {opts.mitsuba_variant}"
    # The GPU renderer on lavapipe spends seconds per process starting up: not in --quick.
    gpu_ok: Optional[bool] = not (opts.no_gpu or opts.quick)
    result: Dict[str, Any] = {
        "cpu": cpu_name(),
        "cores": os.cpu_count(),
        "date": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
        "fastbrdf": {"binary": str(opts.fastbrdf), "version": fb.version, "sampler_flag": fb.has_sampler},
        "mitsuba": mi_note,
        "size": [size, size],
        "repeats": repeats,
        "metric": "relMSE: mean over pixels and channels of (x - ref)^2 / (ref^2 + 1e-2)",
        "timing": "render only (fastbrdf's printed 'render X s', the model's set-up apart as load_dict is "
        "Mitsuba's; "
        + ("on the CPU its second render in one process (`render --repeat 2`'s 'then Y s'), as Mitsuba's after "
           "a warm-up render, the first in cold_time_s; " if fb.warm else "")
        + "on the GPU its 'draws X s' after the device and pipeline set-up"
        + (" (of the second render on one device, `--repeat 2`'s 'then Y s': a process's first draws may "
           "compile the driver's shader variants; the first in cold_time_s)" if fb.gpu_warm else "")
        + "; mi.render + dr.eval after a warm-up render of the same scene and "
        "sample count), median of the repeats, renderers interleaved"
        + (", each timed call (but the GPU's) right after an untimed call of its own" if opts.warm_call else ""),
        "scenes": {},
    }
    for name in opts.scenes:
        sc = SCENES[name]
        log(f"{name}: references")
        entry: Dict[str, Any] = {"label": sc["label"], "renderers": {}}
        # fastbrdf: the configurations of the ladder; direct light uses no random numbers (a
        # fixed N x N grid per pixel), so the sampler only matters under the sky.
        configs: List[Tuple[str, List[List[str]], List[int]]] = []
        # With issue 30's flags, the ladders run the defaults and, as "fastbrdf-before", the
        # renderer's settings before it (independent numbers, every pixel on the N x N grid):
        # the target error is the latter's at its defaults, the issue's target; the reference
        # is a grid render (the pixel's area, as Mitsuba's box filter integrates it).
        # Every light direction from the whole map too (`--env-sun with-map`): before it, the
        # "before" settings run on a later binary drew the sun apart and the target fell 4-5x.
        before = ["--sampler", "independent"] if fb.has_sampler else []
        before += ["--aa", "grid"] if fb.has_aa else []
        before += ["--env-sun", "with-map"] if fb.has_env_sun and sc["env"] else []
        grid = ["--aa", "grid"] if fb.has_aa else []
        if sc["env"]:
            r_spp, r_env = L["fb_env_ref"]
            ref_args = ["--spp", str(r_spp), "--env-samples", str(r_env), *grid]
            if fb.has_sampler:
                ref_args += ["--sampler", "sobol"]
            for cname, extra in [("fastbrdf-cpu", []), ("fastbrdf-before", before)] if before else [("fastbrdf-cpu", [])]:
                pts = [["--env-samples", str(n), *extra] for n in L["fb_env"]]
                configs.append((cname, pts, [4 * n for n in L["fb_env"]]))
            default_args = ["--env-samples", "16"]
        else:
            ref_args = ["--spp", str(L["fb_ref_spp"]), *grid]
            for cname, extra in [("fastbrdf-cpu", []), ("fastbrdf-before", before)] if before else [("fastbrdf-cpu", [])]:
                pts = [["--spp", str(n), *extra] for n in L["fb_spp"]]
                configs.append((cname, pts, [n * n for n in L["fb_spp"]]))
            default_args = []
        fb_ref, t_ref = fb.render(sc, ref_args)
        log(f"{name}: fastbrdf reference {' '.join(ref_args)} in {t_ref:.2f} s")
        mi_ref = None
        mi_samplers = ["independent", "multijitter"] if mi_obj else []
        if mi_obj:
            ref_spp = L["mi_ref_spp"]
            # The reference in passes of at most 1024 spp (memory), averaged.
            acc, passes, t_mref = None, max(1, ref_spp // 1024), 0.0
            for k in range(passes):
                img, dt = mi_obj.render(name, "independent", min(ref_spp, 1024), seed=10_000 + k)
                acc = img if acc is None else acc + img
                t_mref += dt
            mi_ref = acc / passes
            log(f"{name}: Mitsuba reference {ref_spp} spp in {t_mref:.2f} s")
            diff = np.abs(mi_ref - fb_ref) / np.maximum(np.abs(fb_ref), 1e-3)
            entry["validation"] = {
                "mean_rel_diff": float(np.mean(diff)),
                "median_rel_diff": float(np.median(diff)),
                "rel_diff_of_means": float(abs(mi_ref.mean() - fb_ref.mean()) / fb_ref.mean()),
                "rel_mse_between_references": rel_mse(mi_ref, fb_ref),
                "mitsuba_ref_spp": ref_spp,
                "fastbrdf_ref": " ".join(ref_args),
            }
            log(f"{name}: validation {entry['validation']}")
            if opts.refs_dir:
                refs = pathlib.Path(opts.refs_dir)
                refs.mkdir(parents=True, exist_ok=True)
                np.save(refs / f"{name}-fastbrdf-ref.npy", fb_ref)
                np.save(refs / f"{name}-mitsuba-ref.npy", mi_ref)
        # The ladders: per renderer, its points in rising sample counts.
        jobs: Dict[str, List[Tuple[int, Callable[[int], Tuple[np.ndarray, float]]]]] = {}
        for cname, pts, samples in configs:
            jobs[cname] = [(n, functools.partial(fb.render_seeded, sc, a, False)) for a, n in zip(pts, samples)]
        if not sc["env"] and gpu_ok:
            jobs["fastbrdf-gpu"] = [
                (n * n, functools.partial(fb.render_seeded, sc, ["--spp", str(n)], True)) for n in L["fb_spp"]
            ]
        elif gpu_ok:
            # The GPU renders the 2 x 2 grid in every pixel (no adaptive antialiasing), with
            # the CPU's Sobol numbers: 4 x n samples per pixel, as the CPU's ladder counts them.
            jobs["fastbrdf-gpu"] = [
                (4 * n, functools.partial(fb.render_seeded, sc, ["--env-samples", str(n)], True))
                for n in L["fb_env"]
            ]
        for smp in mi_samplers:
            assert mi_obj is not None
            jobs[f"mitsuba-{smp}"] = [(n, functools.partial(mi_obj.render, name, smp, n)) for n in L["mi_spp"]]

        def ref_of(cname: str) -> np.ndarray:
            r = mi_ref if cname.startswith("mitsuba") else fb_ref
            assert r is not None
            return r

        # The target: fastbrdf's error at its defaults (spp 2, env-samples 16), with the
        # renderer's settings before issue 30 where the binary has them (the issue's target).
        default_name = "fastbrdf-cpu"
        target_name = "fastbrdf-before" if "fastbrdf-before" in jobs else default_name
        default_samples = 64 if sc["env"] else 4
        fn = dict(jobs[target_name])[default_samples]
        img, _ = fn(0)
        target = rel_mse(img, fb_ref)
        log(f"{name}: target error {target:.4g} ({target_name} at its defaults, {default_samples} spp)")
        # Exploration, which is also the warm-up (Mitsuba's JIT compiles each kernel here):
        # each ladder is climbed until its error is below STOP x the target, so that the target
        # is bracketed without rendering the long tail; the points kept are then timed.
        meas: Dict[Tuple[str, int], Dict[str, Any]] = {}
        order: List[Tuple[str, int, Callable[[int], Tuple[np.ndarray, float]]]] = []
        for cname, lad in jobs.items():
            for n, fn in lad:
                try:
                    img, _ = fn(0)
                except RuntimeError as e:
                    if cname == "fastbrdf-gpu":
                        gpu_ok = False
                        result["gpu_note"] = f"fastbrdf --gpu failed: {e}"
                        log(result["gpu_note"])
                        break
                    raise
                err = rel_mse(img, ref_of(cname))
                meas[(cname, n)] = {"times": [], "cold_times": [],
                                    "errors": [err] if cname.startswith("mitsuba") else []}
                order.append((cname, n, fn))
                log(f"{name}: {cname} {n} spp: error {err:.4g}")
                if err < STOP * target and not (cname in (default_name, target_name) and n < default_samples):
                    break
        log(f"{name}: timing {len(order)} ladder points x {repeats} repeats, interleaved"
            + (", each after an untimed call of its own" if opts.warm_call else ""))
        prev = ""
        for r in range(repeats):
            for cname, n, fn in order:
                if prev.startswith("mitsuba") and not cname.startswith("mitsuba"):
                    # Mitsuba's threads keep spinning after its renders: in the fifteenth
                    # pass's runs the first fastbrdf point of each repeat, right after
                    # Mitsuba's longest render, took up to twice the time of the same render
                    # in the "before" ladder (face, --spp 1: 8.1-16.6 ms against 8.2-10.0).
                    time.sleep(opts.settle)
                prev = cname
                if opts.warm_call and cname != "fastbrdf-gpu":
                    # Mitsuba runs in this process and its threads keep spinning a while after
                    # a render: a fastbrdf render timed right after one took 12.3 ms (median of
                    # 12) against 9.4 after a 0.3 s pause and 10.3 after another fastbrdf render
                    # (the face, --spp 1). Each timed call so follows one of its own, which also
                    # has Mitsuba's threads awake for its own timed call. The GPU's processes
                    # time their draws after seconds of set-up, long after any spinning ended.
                    fn(r + 1)
                img, dt = fn(r + 1)
                meas[(cname, n)]["times"].append(dt)
                if (fb.warm and cname in ("fastbrdf-cpu", "fastbrdf-before")
                        or fb.gpu_warm and cname == "fastbrdf-gpu"):
                    assert fb.last_cold is not None
                    meas[(cname, n)]["cold_times"].append(fb.last_cold)
                meas[(cname, n)]["errors"].append(rel_mse(img, ref_of(cname)))
        renderers: Dict[str, Any] = {}
        for (cname, n), m in meas.items():
            lad = renderers.setdefault(cname, {"ladder": []})["ladder"]
            lad.append({
                "samples": n,
                "time_s": median(m["times"]),
                "times_s": m["times"],
                "time_spread": spread(m["times"]),
                # With the warm timing, the first render of each process (a cold one) too.
                **({"cold_time_s": median(m["cold_times"]), "cold_times_s": m["cold_times"]}
                   if m["cold_times"] else {}),
                # fastbrdf is deterministic (the same error each time); Mitsuba: the mean over
                # its seeds.
                "error": float(np.mean(m["errors"])),
            })
        base = next(p for p in renderers[target_name]["ladder"] if p["samples"] == default_samples)
        entry["target_error"] = target
        entry["target_from"] = f"{target_name} at {default_samples} spp"
        # fastbrdf's time: at its defaults where they set the target, else interpolated along
        # its ladder to the target.
        if target_name == default_name:
            t_base, how_base = base["time_s"], "measured at the defaults"
        else:
            t_fb, how_base = time_to_error(renderers[default_name]["ladder"], target)
            t_base = t_fb if t_fb else base["time_s"]
        entry["fastbrdf_default"] = {"renderer": default_name, "samples": default_samples, "time_s": t_base,
                                     "how": how_base, "args": " ".join(default_args) or "(defaults)",
                                     "target_time_s": base["time_s"]}
        # The same from the first render of each process (cold), where timed warm.
        cold = cold_ladder(renderers[default_name]["ladder"])
        if cold:
            t_cold, _ = time_to_error(cold, target) if target_name != default_name else (None, "")
            entry["fastbrdf_default"]["cold_time_s"] = t_cold or next(
                p["time_s"] for p in cold if p["samples"] == default_samples)
        for cname, rr in renderers.items():
            t, how = time_to_error(rr["ladder"], target)
            if cname == target_name:
                t, how = base["time_s"], "measured at the defaults"
            elif cname == default_name:
                t, how = t_base, how_base
            rr["time_to_target_s"] = t
            rr["how"] = how
            rr["ratio_vs_fastbrdf"] = (t / t_base) if t else None
            log(f"{name}: {cname}: time to target {t if t is None else round(t, 4)} s ({how})")
            # The GPU's from its first renders' draws, where timed warm (the CPU's default:
            # `fastbrdf_default.cold_time_s` above).
            if cname == "fastbrdf-gpu" and (cold := cold_ladder(rr["ladder"])):
                rr["cold_time_to_target_s"] = time_to_error(cold, target)[0]
        # The same at the ladders' own points (`point_at_error`), against fastbrdf's.
        own = point_at_error(renderers[default_name]["ladder"], target)
        for cname, rr in renderers.items():
            pt = point_at_error(rr["ladder"], target)
            rr["at_point"] = pt and dict(pt, ratio_vs_fastbrdf=pt["time_s"] / own["time_s"] if own else None)
        entry["renderers"] = renderers
        result["scenes"][name] = entry
        if opts.out_json:  # after every scene, so that an interrupted run keeps what it measured
            result["table_markdown"] = table(result)
            pathlib.Path(opts.out_json).write_text(json.dumps(result, indent=1) + "\n")
    result["table_markdown"] = table(result)
    return result


def ms(t: float) -> str:
    return f"{t * 1e3:.3g} ms" if t < 1 else f"{t:.3g} s"


def ratio_text(r: Optional[float], how: str) -> str:
    if r is None:
        return f"n/a ({how})"
    pre = "~" if how == "extrapolated" else ""
    return f"{pre}{r:.2g}x slower" if r >= 1 else f"{pre}{1 / r:.2g}x faster"


def table(res: Dict[str, Any]) -> str:
    mitsuba = "Mitsuba " + res["mitsuba"][len("mitsuba "):] if res["mitsuba"].startswith("mitsuba ") else "Mitsuba"
    lines = [
        f"Time to fastbrdf's default error (before issue 30: --spp 2, --env-samples 16, independent numbers, "
        f"every pixel on the grid, every light direction from the whole map), {res['size'][0]}x{res['size'][1]}, on {res['cpu']} "
        f"({res['cores']} threads); each renderer against its own converged reference; "
        "\"Nx slower\" = N times fastbrdf CPU's time.",
        "",
        f"| scene | fastbrdf CPU | {mitsuba}, independent (default) | multijitter | fastbrdf GPU |",
        "|---|---|---|---|---|",
    ]
    for name, e in res["scenes"].items():
        d = e["fastbrdf_default"]
        rr = e["renderers"]
        if d.get("how", "measured at the defaults") == "measured at the defaults":
            cells = [e["label"], f"{d['samples']} spp, {ms(d['time_s'])}"]
        else:
            pre = "~" if d["how"] == "extrapolated" else ""
            cells = [e["label"], f"{pre}{ms(d['time_s'])}"]
        if "fastbrdf-before" in rr:
            x = rr["fastbrdf-before"]
            cells[1] += f" (before issue 30: {d['samples']} spp, {ms(d['target_time_s'])}, {ratio_text(x['ratio_vs_fastbrdf'], x['how'])})"
        for k in ["mitsuba-independent", "mitsuba-multijitter", "fastbrdf-gpu"]:
            if k in rr:
                x = rr[k]
                t = x["time_to_target_s"]
                cells.append(ratio_text(x["ratio_vs_fastbrdf"], x["how"]) + (f" ({ms(t)})" if t else ""))
            else:
                cells.append("-")
        lines.append("| " + " | ".join(cells) + " |")
    notes = []
    agree = [f"{name} {100 * v['mean_rel_diff']:.2g}% (median {100 * v['median_rel_diff']:.2g}%, "
             f"image means {100 * v['rel_diff_of_means']:.2g}%)"
             for name, e in res["scenes"].items() if (v := e.get("validation"))]
    if agree:
        notes.append("the two renderers' references differ per pixel on average by: " + "; ".join(agree))
    spreads = [p["time_spread"] for e in res["scenes"].values() for r in e["renderers"].values() for p in r["ladder"]]
    if spreads:
        notes.append(
            f"timing noise, (max - min) / median of {res['repeats']} repeats: median {100 * median(spreads):.0f}%, "
            f"worst {100 * max(spreads):.0f}%"
        )
    colds = {n: e["fastbrdf_default"]["cold_time_s"] for n, e in res["scenes"].items()
             if "cold_time_s" in e["fastbrdf_default"]}
    if colds:
        mj = {n: res["scenes"][n]["renderers"].get("mitsuba-multijitter", {}).get("time_to_target_s") for n in colds}
        each = ", ".join(f"{n} {ms(t)}" + (f" ({mj[n] / t:.2g}x ahead of multijitter)" if mj[n] else "")
                         for n, t in colds.items())
        notes.append(
            "fastbrdf CPU is timed at its second render in one process (`render --repeat 2`), as Mitsuba "
            f"after its warm-up render; its first render in a fresh process (cold): {each}"
        )
    gpu_cold = []
    for n, e in res["scenes"].items():
        t = e["renderers"].get("fastbrdf-gpu", {}).get("cold_time_to_target_s")
        mj = e["renderers"].get("mitsuba-multijitter", {}).get("time_to_target_s")
        if t:
            gpu_cold.append(f"{n} {ms(t)}" + (f" ({t / mj:.2g}x multijitter's time)" if mj else ""))
    if gpu_cold:
        notes.append(
            "fastbrdf GPU is timed at the draws of its second render on one device (`render --gpu --repeat 2`); "
            "from its first render's draws (which may compile the driver's shader variants): " + ", ".join(gpu_cold)
        )
    at = []
    for n, e in res["scenes"].items():
        fb = e["renderers"][e["fastbrdf_default"]["renderer"]].get("at_point")
        mj = e["renderers"].get("mitsuba-multijitter", {}).get("at_point")
        if fb and mj:
            at.append(f"{n} {fb['samples']} against {mj['samples']} spp, {ms(fb['time_s'])} against "
                      f"{ms(mj['time_s'])} ({mj['ratio_vs_fastbrdf']:.2g}x)")
    if at:
        notes.append(
            "at the ladders' own points (each renderer's cheapest measured sample count at or below "
            "the target error, no interpolation), fastbrdf CPU against multijitter: " + "; ".join(at)
        )
    if not res["mitsuba"].startswith("mitsuba "):
        notes.append(f"Mitsuba: {res['mitsuba']}")
    if res.get("gpu_note"):
        notes.append(res["gpu_note"])
    if notes:
        lines += [""] + [f"- {n}" for n in notes]
    return "\n".join(lines)


def main(argv: Optional[List[str]] = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--fastbrdf", default=str(ROOT / "target" / "release" / "fastbrdf"), help="the fastbrdf binary")
    ap.add_argument("--scenes", nargs="+", choices=list(SCENES), default=list(SCENES))
    ap.add_argument("--out-json", help="write the results here")
    ap.add_argument("--refs-dir", metavar="DIR",
                    help="keep each scene's two converged references there when Mitsuba runs "
                    "(SCENE-fastbrdf-ref.npy, SCENE-mitsuba-ref.npy); by default they are not kept")
    mode = ap.add_mutually_exclusive_group()
    mode.add_argument("--quick", action="store_true", help="64x64, short ladders, 1 repeat: a smoke run")
    mode.add_argument("--full", action="store_true", help="5 repeats, references of 4096 samples per pixel")
    ap.add_argument("--size", type=int, help="image side (default 512; 64 with --quick)")
    ap.add_argument("--repeats", type=int, help="timed repeats per ladder point (median)")
    ap.add_argument("--no-mitsuba", action="store_true", help="fastbrdf's columns only")
    ap.add_argument("--no-gpu", action="store_true", help="skip fastbrdf --gpu (always skipped with --quick)")
    ap.add_argument("--no-warm-call", dest="warm_call", action="store_false",
                    help="time each ladder point right after the previous renderer's (before the tenth "
                    "pass: a fastbrdf render after Mitsuba's ran with Mitsuba's threads still spinning)")
    ap.add_argument("--settle", type=float, default=0.5, metavar="S",
                    help="seconds to wait before a fastbrdf render that follows Mitsuba's, whose "
                    "threads keep spinning after a render (default 0.5)")
    ap.add_argument("--cold-fastbrdf", action="store_true",
                    help="time fastbrdf's first render in its process (before the sixteenth pass), not "
                    "its second (`render --repeat 2`, a warm process as Mitsuba's after its warm-up)")
    ap.add_argument("--mitsuba-variant", default="llvm_ad_rgb")
    ap.add_argument("--env-roll", type=int, default=512,
                    help="columns the sky is rolled by for Mitsuba's envmap (its u = fastbrdf's u - 1/2)")
    opts = ap.parse_args(argv)
    if not pathlib.Path(opts.fastbrdf).exists():
        print(f"equal_error: no fastbrdf binary at {opts.fastbrdf} (cargo build --release -p fastbrdf-cli)", file=sys.stderr)
        return 2
    # The renders' files go in a temporary folder that goes with the run, however it ends.
    with tempfile.TemporaryDirectory(prefix="equal-error-") as tmp:
        res = run(opts, pathlib.Path(tmp))
    print(res["table_markdown"])
    if opts.out_json:
        pathlib.Path(opts.out_json).write_text(json.dumps(res, indent=1) + "\n")
        log(f"wrote {opts.out_json}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

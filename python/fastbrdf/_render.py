"""The renderer (``render``, ``compare``) and the catalogues of colours (``materials``,
``metals``), as the CLI's ``render``, ``compare --json``, ``materials --json`` and
``metals --json``."""

from __future__ import annotations

import json
import os
from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np

from . import _fastbrdf as _native
from ._arrays import _opt_str, _params, _str, _triple
from ._model import Model

__all__ = ["compare", "materials", "metals", "render"]

PathLike = Union[str, "os.PathLike[str]"]
Numbers = Union[str, Sequence[float]]


def _int(name: str, v: Any) -> int:
    if isinstance(v, bool) or not isinstance(v, (int, np.integer)):
        raise TypeError(f"{name}: expected an int, got {type(v).__name__}")
    if v < 0:
        raise ValueError(f"{name} {v}: must be positive")
    return int(v)


def _numbers(name: str, x: Any, count: int) -> Optional[Tuple[float, ...]]:
    """None, or ``count`` numbers from 0 to 1e3: a sequence or the CLI's ``"A,B,..."`` text."""
    if x is None:
        return None
    if isinstance(x, str):
        try:
            x = [float(p) for p in x.split(",")]
        except ValueError:
            raise ValueError(f"{name} '{x}': not numbers") from None
    return _triple(name, x, count)


def _opt_path(name: str, p: Any) -> Optional[str]:
    if p is None:
        return None
    if not isinstance(p, (str, os.PathLike)):
        raise TypeError(f"{name}: expected a path (str or os.PathLike), got {type(p).__name__}")
    s = os.fspath(p)
    return os.fsdecode(s) if isinstance(s, bytes) else s


def _flag(name: str, v: Any, on_off: bool = False) -> bool:
    """A switch: a bool (numpy's too), or with ``on_off`` the CLI's ``"on"``/``"off"``."""
    if isinstance(v, (bool, np.bool_)):
        return bool(v)
    if on_off and v in ("on", "off"):
        return bool(v == "on")
    allowed = "a bool or 'on'/'off'" if on_off else "a bool"
    raise TypeError(f"{name}: expected {allowed}, got {type(v).__name__}")


def _size(size: Any, width: Optional[int], height: Optional[int]) -> Tuple[int, int]:
    """The image size: ``size`` ("WxH" as the CLI's ``--size``, or (W, H)) or ``width`` and
    ``height`` (default 256 each)."""
    if size is None:
        return (
            _int("width", 256 if width is None else width),
            _int("height", 256 if height is None else height),
        )
    if width is not None or height is not None:
        raise ValueError("size: give size or width and height, not both")
    if isinstance(size, str):
        parts = size.lower().split("x")
        if len(parts) != 2 or not all(p.strip().isdigit() for p in parts):
            raise ValueError(f"size '{size}': expected WIDTHxHEIGHT, e.g. 64x48")
        return int(parts[0]), int(parts[1])
    if isinstance(size, (tuple, list)) and len(size) == 2:
        return _int("size[0]", size[0]), _int("size[1]", size[1])
    raise TypeError(f"size: expected 'WxH' or (width, height), got {type(size).__name__}")


def _scene(
    size: Any,
    width: Optional[int],
    height: Optional[int],
    spp: int,
    weights: Any,
    albedo: Any,
    lights: Any,
    floor: bool,
    shadows: Union[bool, str],
    env: Any,
    env_samples: int,
    mesh: Any,
    texture: Any,
    bump: Any,
    sampler: str = "sobol",
    aa: str = "adaptive",
    env_sun: str = "apart",
) -> Dict[str, Any]:
    """The scene options as the native ``render`` and ``compare_json`` take them."""
    w, h = _size(size, width, height)
    if isinstance(lights, str):
        lights = [lights]
    return {
        "width": w,
        "height": h,
        "spp": _int("spp", spp),
        "weights": _numbers("weights", weights, 2),
        "albedo": _numbers("albedo", albedo, 3),
        "lights": list(lights),
        "floor": _flag("floor", floor),
        "shadows": _flag("shadows", shadows, on_off=True),
        "env": _opt_str(env, "env"),
        "env_samples": _int("env_samples", env_samples),
        "mesh": _opt_path("mesh", mesh),
        "texture": _opt_path("texture", texture),
        "bump": None if bump is None else _bump(bump),
        "sampler": _str(sampler, "sampler"),
        "aa": _str(aa, "aa"),
        "env_sun": _str(env_sun, "env_sun"),
    }


def _bump(bump: Any) -> Tuple[float, float]:
    if isinstance(bump, str):
        try:
            bump = [float(p) for p in bump.split(",")]
        except ValueError:
            raise ValueError(f"bump '{bump}': not numbers") from None
    v = np.asarray(bump, dtype=np.float64).reshape(-1)
    if v.shape != (2,):
        raise ValueError(f"bump {bump}: expected (SCALE, DEPTH)")
    return float(v[0]), float(v[1])


def render(
    model: Union[str, Model],
    *,
    size: Union[str, Tuple[int, int], None] = None,
    width: Optional[int] = None,
    height: Optional[int] = None,
    spp: int = 2,
    mesh: Optional[PathLike] = None,
    texture: Optional[PathLike] = None,
    lights: Sequence[str] = (),
    bump: Optional[Numbers] = None,
    weights: Optional[Numbers] = None,
    albedo: Optional[Numbers] = None,
    shadows: Union[bool, str] = True,
    floor: bool = False,
    env: Optional[str] = None,
    env_samples: int = 16,
    sampler: str = "sobol",
    aa: str = "adaptive",
    env_sun: str = "apart",
    material: Optional[str] = None,
    metal: Optional[str] = None,
    gpu: bool = False,
    **params: Any,
) -> np.ndarray:
    """Renders ``model`` as ``fastbrdf render --out FILE.exr`` does, with the same options
    (the flags' dashes as underscores): the linear radiance film, float32 of shape (height,
    width, 3), top row first (no exposure, no sRGB: ``--exposure`` only scales PNG files).

    The scene: the built-in sphere, or ``mesh`` (an OBJ file, or ``"face"``, the built-in
    face) with ``texture`` (a PNG or JPEG albedo map, or ``"skin"``); ``lights``: the CLI's
    ``--light`` specs (``dir:X,Y,Z[:R,G,B[:I]]``, ``point:...``; default one key light);
    ``env``: ``"sky"``, ``"white"`` or a latitude-longitude ``.hdr``/``.exr`` map, sampled
    ``env_samples`` times per primary ray; ``floor``; ``shadows`` (a bool, or the CLI's
    ``"on"``/``"off"``); ``bump`` (SCALE, DEPTH);
    ``weights`` (KD, KS), default (0.6, 0.4); ``albedo`` (R, G, B), default 0.8 grey.
    ``size`` is ``"WxH"`` or (W, H), or give ``width`` and ``height`` (default 256 each; the
    CLI's default is 512x512); ``spp`` N gives up to N x N samples per pixel: ``aa``
    ``"adaptive"`` (the default: N x N samples only at edges, 2N x 2N at outlines) or
    ``"grid"`` (N x N in every pixel), as ``--aa``; ``sampler`` ``"sobol"`` (default) or ``"independent"``, as ``--sampler``;
    ``env_sun`` ``"apart"`` (default: a map's sun drawn apart from the rest) or ``"with-map"``
    (every light direction from the whole map), as ``--env-sun``.

    Colour: ``material`` (a MERL material's published fit, see ``materials()``: its n, alpha,
    f0, and its diffuse colour with weight 1 unless ``albedo``/``weights`` are given),
    ``metal`` (see ``metals()``: f = conductor, eta and k per channel; weights 0, 1 unless
    given), or any parameter given as (R, G, B) or ``"r,g,b"``. Parameters a lobe or a
    distribution does not take go to the BRDF it is shaded as (Blinn-Phong, Cook-Torrance).

    ``gpu=True`` renders on the GPU (wgpu; Mesa's lavapipe without one), as ``render --gpu``:
    grey models only (else ``ValueError``), with or without ``env``; no adapter is a
    ``RuntimeError``.
    The CPU film equals the CLI's exactly (deterministic). Ctrl-C stops it.

    >>> img = fastbrdf.render("ggx", alpha=0.3, size="32x24", metal="gold", env="sky", env_samples=2)
    >>> ct = fastbrdf.Model("cook-torrance", d="ggx", alpha=0.3, metal="gold")
    >>> same = fastbrdf.render(ct, size="32x24", env="sky", env_samples=2)
    >>> bool((same == img).all())                      # a Model renders as its id and values
    True
    >>> img.shape, img.dtype
    ((24, 32, 3), dtype('float32'))
    >>> bool(img[12, 16, 0] > img[12, 16, 2])          # gold: more red than blue
    True
    """
    if isinstance(model, Model):
        # A Model: its id, parameters, material and metal (keywords given here win).
        if model._arrays:
            raise ValueError(
                f"model: per-element parameters ({', '.join(model._arrays)}) cannot be rendered; "
                "give one value per parameter"
            )
        params = {**model.params, **params}
        material = material if material is not None else model.material
        metal = metal if metal is not None else model.metal
        model = model.id
    scene = _scene(
        size, width, height, spp, weights, albedo, lights, floor, shadows, env, env_samples,
        mesh, texture, bump, sampler, aa, env_sun,
    )
    flat = _native.render(
        model,
        _params(model, params),
        _opt_str(material, "material"),
        _opt_str(metal, "metal"),
        scene,
        _flag("gpu", gpu),
    )
    return flat.reshape(scene["height"], scene["width"], 3)


def compare(
    models: Union[str, Sequence[str]],
    reference: Optional[str] = None,
    *,
    measured: Optional[PathLike] = None,
    size: Union[str, Tuple[int, int], None] = None,
    width: Optional[int] = None,
    height: Optional[int] = None,
    spp: int = 2,
    mesh: Optional[PathLike] = None,
    texture: Optional[PathLike] = None,
    lights: Sequence[str] = (),
    bump: Optional[Numbers] = None,
    weights: Optional[Numbers] = None,
    albedo: Optional[Numbers] = None,
    exposure: float = 1.0,
    shadows: Union[bool, str] = True,
    floor: bool = False,
    env: Optional[str] = None,
    env_samples: int = 16,
    sampler: str = "sobol",
    aa: str = "adaptive",
    env_sun: str = "apart",
    material: Optional[str] = None,
    metal: Optional[str] = None,
    films: bool = False,
    **params: Any,
) -> Dict[str, Any]:
    """Renders ``models`` and a reference (model ``reference``, or the MERL file
    ``measured``, rendered as the whole BRDF) in one scene and scores each model against it,
    as ``fastbrdf compare --json``: returns ``{"reference": NAME, "metrics": [{"model",
    "rmse", "psnr", "flip", "rmse_linear", "psnr_linear", "psnr_linear_peak",
    "flip_reinhard"}, ...]}`` with the CLI's numbers (sRGB scores on the 8-bit pictures after
    ``exposure``; PSNR None when infinite). ``models``: ids as a list or the CLI's
    comma-separated text; ``params`` go to every model that takes them (a value no model
    takes is an error); the scene options as ``render``'s. With ``films=True`` the dict also
    holds ``"films"``: float32 of shape (models + 1, height, width, 3), the reference first.

    >>> r = fastbrdf.compare(["flog", "schlick"], "pow", n=100, size="16x16", spp=1)
    >>> r["reference"], [m["model"] for m in r["metrics"]]
    ('pow', ['flog n=100', 'schlick n=100'])
    """
    if isinstance(models, str):
        models = models.split(",")
    if not isinstance(models, (list, tuple)) or not all(isinstance(m, str) for m in models):
        raise TypeError("models: expected model ids (a list of strings or 'a,b,...')")
    scene = _scene(
        size, width, height, spp, weights, albedo, lights, floor, shadows, env, env_samples,
        mesh, texture, bump, sampler, aa, env_sun,
    )
    if isinstance(exposure, bool) or not isinstance(exposure, (int, float, np.integer, np.floating)):
        raise TypeError(f"exposure: expected a number, got {type(exposure).__name__}")
    if measured is not None:
        from ._measured import _path

        measured = _path(measured, "measured")
    doc, flat = _native.compare_json(
        [m.strip() for m in models],
        _opt_str(reference, "reference"),
        measured,
        _params(reference or (models[0] if models else ""), params),
        _opt_str(material, "material"),
        _opt_str(metal, "metal"),
        scene,
        float(exposure),
        _flag("films", films),
    )
    out: Dict[str, Any] = json.loads(doc)
    if flat is not None:
        out["films"] = flat.reshape(-1, scene["height"], scene["width"], 3)
    return out


def materials() -> List[Dict[str, Any]]:
    """The 86 MERL materials' published fits (Ngan, Matusik and Durand, EGSR 2005), as
    ``fastbrdf materials --json``: dicts {"name", "blinn_phong": {"n", "kd", "ks"},
    "cook_torrance": {"m", "f0", "kd", "ks"}, "ward": {"alpha", "kd", "ks"}, "inside":
    [family, ...]}. A name is ``render``'s and ``Model``'s ``material=``.

    >>> gold = next(m for m in fastbrdf.materials() if m["name"] == "gold-paint")
    >>> sorted(gold)
    ['blinn_phong', 'cook_torrance', 'inside', 'name', 'ward']
    """
    rows: List[Dict[str, Any]] = json.loads(_native.materials_json())
    return rows


def metals() -> Dict[str, Any]:
    """The named metals, as ``fastbrdf metals --json``: {"wavelengths_nm": [650, 550, 450],
    "metals": [{"id", "symbol", "eta": [r, g, b], "k": [r, g, b], "f0": [r, g, b],
    "source"}, ...]}. An id is ``render``'s and ``Model``'s ``metal=``.

    >>> [m["id"] for m in fastbrdf.metals()["metals"]][:3]
    ['gold', 'silver', 'copper']
    """
    doc: Dict[str, Any] = json.loads(_native.metals_json())
    return doc

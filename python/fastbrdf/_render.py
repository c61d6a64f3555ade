"""The CPU renderer (``render``), as the CLI's ``render`` command."""

from __future__ import annotations

from typing import Any, Optional, Sequence

import numpy as np

from . import _fastbrdf as _native
from ._arrays import _params, _triple

__all__ = ["render"]


def render(
    model: str,
    *,
    width: int = 256,
    height: int = 256,
    spp: int = 2,
    weights: Sequence[float] = (0.6, 0.4),
    albedo: Sequence[float] = (0.8, 0.8, 0.8),
    lights: Sequence[str] = (),
    floor: bool = False,
    shadows: bool = True,
    env: Optional[str] = None,
    env_samples: int = 16,
    **params: Any,
) -> np.ndarray:
    """Renders the built-in sphere shaded by ``model`` on the CPU, as ``fastbrdf render``:
    returns the linear radiance film, float32 of shape (height, width, 3), top row first (no
    exposure, no sRGB). ``weights`` are (kd, ks), ``lights`` the CLI's ``--light`` specs
    (``dir:X,Y,Z[:R,G,B[:I]]``, ``point:...``), ``env`` ``sky``, ``white`` or a map file.
    Ctrl-C stops it.

    >>> img = fastbrdf.render("ggx", alpha=0.3, width=64, height=48)
    >>> img.shape, img.dtype
    ((48, 64, 3), dtype('float32'))
    """
    kd, ks = _triple("weights", weights, 2)
    rgb = _triple("albedo", albedo, 3)
    for name, v in (("width", width), ("height", height), ("spp", spp), ("env_samples", env_samples)):
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)):
            raise TypeError(f"{name}: expected an int, got {type(v).__name__}")
        if v < 0:
            raise ValueError(f"{name} {v}: must be positive")
    if isinstance(lights, str):
        lights = [lights]
    flat = _native.render(
        model,
        _params(model, params),
        int(width),
        int(height),
        int(spp),
        kd,
        ks,
        (rgb[0], rgb[1], rgb[2]),
        list(lights),
        bool(floor),
        bool(shadows),
        env,
        int(env_samples),
    )
    return flat.reshape(int(height), int(width), 3)



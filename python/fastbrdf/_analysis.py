"""The registry (``models``), error sweeps (``errors``), albedo curves (``albedo``) and shader
export (``shader``), as the CLI's ``models``, ``errors``, ``albedo`` and ``shader`` commands."""

from __future__ import annotations

import json
from typing import Any, Dict, List, Optional

from . import _fastbrdf as _native
from ._arrays import _opt_str, _params, _str, _values

__all__ = ["KINDS", "LANGS", "albedo", "errors", "models", "shader"]

#: The model kinds, as ``fastbrdf models --kind`` names them.
KINDS = ("lobe", "distribution", "shadowing", "fresnel", "brdf", "env")
#: The languages of :func:`shader`, as ``fastbrdf shader --lang`` names them.
LANGS = ("wgsl", "glsl", "hlsl", "msl", "brdf-explorer")


def models(kind: Optional[str] = None) -> List[Dict[str, Any]]:
    """Every registered model, as the list ``fastbrdf models --json`` prints under ``models``.

    >>> [m["id"] for m in fastbrdf.models("lobe")][:3]
    ['pow', 'schlick', 'schlick-modified']
    """
    all_models: List[Dict[str, Any]] = json.loads(_native.models_json())["models"]
    if kind is None:
        return all_models
    if kind not in KINDS:
        raise ValueError(f"kind '{kind}': expected one of {', '.join(KINDS)}")
    return [m for m in all_models if m["kind"] == kind]


def errors(
    model: str,
    reference: str,
    *,
    n: Any = None,
    alpha: Any = None,
    zone: str = "all",
) -> List[Dict[str, Any]]:
    """The errors of ``model`` against ``reference`` per parameter value, as the rows of
    ``fastbrdf errors --json``: ``{n or alpha, max_abs, max_abs_at, max_rel, max_rel_at, rms,
    samples}`` (an infinite relative error is ``None``). Give ``n`` (lobes) or ``alpha``
    (microfacet terms, Ward) as a number, a sequence (1 to ``MAX_VALUES`` values) or the
    CLI's range text (``"1..1000:log10"``); ``zone`` is ``all``, ``epicentre`` or
    ``band:LO,HI``. Ctrl-C stops it.

    >>> round(fastbrdf.errors("flog", "pow", n=[10, 100])[0]["max_abs"], 6)
    0.125
    """
    if (n is None) == (alpha is None):
        raise ValueError("give n=... (lobes) or alpha=... (microfacet terms, Ward), not both")
    param, x, step = ("n", n, 1.0) if n is not None else ("alpha", alpha, 0.01)
    rows = json.loads(_native.errors_json(model, reference, param, _values(x, param, step), zone))
    return [{param: r.pop("param"), **r} for r in rows]


def albedo(
    model: str,
    *,
    angles: Any = "0..85:5",
    as_brdf: str = "phong",
    norm: str = "energy",
    material: Optional[str] = None,
    **params: Any,
) -> Dict[str, Any]:
    """Directional albedo against the incidence angle (degrees, in [0, 90)) and the
    white-furnace verdict, as ``fastbrdf albedo --json``: ``{model, brdf, params,
    claims_energy, conserves, rows: [{theta_deg, albedo, error}]}``. A lobe is evaluated as
    ``as_brdf`` (``phong`` or ``blinn-phong``) normalised by ``norm`` (``energy`` or ``none``).
    ``material``: a MERL material's published fit supplies the parameters (the CLI's
    ``--material``). ``angles``: a number, a sequence (1 to ``MAX_VALUES`` values) or a range text. Ctrl-C stops
    it.

    >>> r = fastbrdf.albedo("lambert", angles=[0, 60])
    >>> [round(row["albedo"], 6) for row in r["rows"]]
    [1.0, 1.0]
    """
    _opt_str(material, "material")
    _str(as_brdf, "as_brdf")
    _str(norm, "norm")
    return dict(
        json.loads(
            _native.albedo_json(
                model, _params(model, params), _values(angles, "angles", 5.0), as_brdf, norm, material
            )
        )
    )


def shader(
    model: str,
    *,
    lang: str = "wgsl",
    runtime_params: bool = False,
    material: Optional[str] = None,
    metal: Optional[str] = None,
    **params: Any,
) -> str:
    """The model as a self-contained shader function ``fb_<id>`` (dashes as underscores), as
    ``fastbrdf shader``: ``lang`` is ``wgsl``, ``glsl``, ``hlsl``, ``msl`` or
    ``brdf-explorer``; ``runtime_params`` takes the numeric parameters as trailing arguments
    ``p_<name>``. ``material`` and ``metal`` as for :class:`Model` (a coloured model exports
    three channel functions and ``fb_<id>_rgb``). Needs no GPU.

    >>> "fn fb_flog(" in fastbrdf.shader("flog", n=20)
    True
    >>> "fb_cook_torrance_rgb" in fastbrdf.shader("cook-torrance", d="ggx", metal="gold")
    True
    """
    _opt_str(material, "material")
    _opt_str(metal, "metal")
    return str(_native.shader(model, _params(model, params), lang, bool(runtime_params), material, metal))

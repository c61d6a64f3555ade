"""The CLI's analyses: ``check``, ``reproduce``, ``fit``, ``normalize``, ``lut``, ``pareto`` and
``chi2``, each returning what its command prints with ``--json`` (built by the same Rust
function, so the numbers are the command's), ``lut`` the table itself as a numpy array."""

from __future__ import annotations

import json
import os
from typing import Any, Dict, List, Optional, Union

import numpy as np

from . import _fastbrdf as _native
from ._arrays import _opt_str, _params, _str, _values

__all__ = ["FIT_FAMILIES", "check", "chi2", "fit", "lut", "normalize", "pareto", "reproduce"]

#: A file path: text or ``os.PathLike``.
PathArg = Union[str, "os.PathLike[str]"]

#: The families of :func:`fit`, as ``fastbrdf fit --family`` names them.
FIT_FAMILIES = ("power4", "power8", "power16", "exp2", "cubic-rational", "beckmann-power16")


def _bool(x: Any, name: str) -> bool:
    if not isinstance(x, (bool, np.bool_)):
        raise TypeError(f"{name}: expected a bool, got {type(x).__name__}")
    return bool(x)


def _path(x: Any, name: str) -> Optional[str]:
    if x is None:
        return None
    if not isinstance(x, (str, os.PathLike)):
        raise TypeError(f"{name}: expected a path (str or os.PathLike), got {type(x).__name__}")
    return os.fspath(x)


def _int(x: Any, name: str) -> int:
    if isinstance(x, (bool, np.bool_)) or not isinstance(x, (int, np.integer)):
        raise TypeError(f"{name}: expected an integer, got {type(x).__name__}")
    return int(x)


def _range(x: Any, name: str, step: float) -> List[float]:
    """A number, a sequence or the CLI's range text; a bad text's message names ``name``."""
    try:
        return _values(x, name, step)
    except ValueError as e:
        if isinstance(x, str) and not str(e).startswith(f"{name}:"):
            raise ValueError(f"{name}: {e}") from None
        raise


def check(model: Optional[str] = None, full: bool = False) -> Dict[str, Any]:
    """Every documented bound of the registry (or of ``model``) re-measured on this machine, as
    ``fastbrdf check --json [--model M] [--full]``: ``{ok, bounds: [{model, reference, metric,
    zone, param, documented, measured, at_param, at_x, samples, ok}], f32: [{model, documented,
    measured, configurations, evaluations, corners, at, finite, invalid, ok}], kernels: [{model,
    documented, measured, isas, configurations, evaluations, at, finite, invalid, ok}]}`` (the
    batch kernels that ``eval`` runs, on every instruction set of this CPU, against f64). A
    bound that does not hold is ``ok: False`` (nothing is raised). ``full`` searches 32 times longer.
    Ctrl-C stops it.

    >>> r = fastbrdf.check("pow")
    >>> r["ok"], [b["model"] for b in r["f32"]]
    (True, ['pow'])
    """
    return dict(json.loads(_native.check_json(_opt_str(model, "model"), _bool(full, "full"))))


def reproduce(speedups: Optional[PathArg] = None) -> Dict[str, Any]:
    """Every numeric claim of the seed papers, measured, as ``fastbrdf reproduce --json``:
    ``{claims: [{id, seed, claimed, claimed_text, measured, measured_text, unit,
    claimed_values, measured_values, domain, verdict}]}``. ``speedups``: a saved ``fastbrdf
    bench --json`` file that fills the speed rows (as ``--speedups``). Takes a few seconds;
    Ctrl-C stops it.

    >>> claims = fastbrdf.reproduce()["claims"]  # doctest: +SKIP
    >>> sorted({c["verdict"] for c in claims})  # doctest: +SKIP
    ['agrees', 'no claim', 'not measured']
    """
    return dict(json.loads(_native.reproduce_json(_path(speedups, "speedups"))))


def fit(
    family: str,
    reference: str,
    *,
    n: Any = None,
    m: Any = None,
    metric: str = "max-abs",
    normalized: bool = False,
) -> Dict[str, Any]:
    """Minimax-tuned coefficients of a one-coefficient ``family`` (``FIT_FAMILIES``) against
    ``reference`` (``pow`` for the lobe families, ``beckmann-ct`` for ``beckmann-power16``),
    one per exponent ``n`` (lobe families) or slope ``m`` (``beckmann-power16``), as
    ``fastbrdf fit --json``: ``{family, metric, normalized, param, rows: [{n or alpha,
    coefficient, error, untuned_coefficient, untuned_error}], closed_form}`` (``closed_form``:
    a fit of the optima over 5 or more lobe rows, else ``None``). ``metric``: ``max-abs``,
    ``max-rel-epicentre`` or ``rms``; ``normalized`` fits the energy-normalised forms (lobe
    families). ``n``/``m``: a number, a sequence or the CLI's range text. Ctrl-C stops it.

    >>> r = fastbrdf.fit("power16", "pow", n=[100])
    >>> row = r["rows"][0]
    >>> row["n"], row["error"] < row["untuned_error"]
    (100.0, True)
    """
    family, reference, metric = (
        _str(family, "family"),
        _str(reference, "reference"),
        _str(metric, "metric"),
    )
    if family not in FIT_FAMILIES:
        raise ValueError(f"family '{family[:40]}': expected one of {', '.join(FIT_FAMILIES)}")
    if n is not None and m is not None:
        raise ValueError("give n=... (lobe families) or m=... (beckmann-power16), not both")
    arg, x, step = ("m", m, 0.01) if m is not None else ("n", n, 1.0)
    if x is None:
        raise ValueError(
            "the beckmann-power16 family takes m=..." if family == "beckmann-power16" else "the lobe families take n=..."
        )
    values = _range(x, arg, step)
    return dict(json.loads(_native.fit_json(family, reference, arg, values, metric, _bool(normalized, "normalized"))))


def normalize(model: str, n: Any, *, fit: Optional[str] = None) -> Dict[str, Any]:
    """``Int(n) = integral_0^1 lobe(c) c dc`` and ``coef(n) = 1 / (2 pi Int(n))`` of lobe
    ``model`` by quadrature, and with ``fit`` (``seed``, ``linear`` or ``seed-published``) a
    closed form of ``coef(n)``, as ``fastbrdf normalize --json``: ``{model, rows: [{n, int,
    coef, int_err}], fit}``. ``n``: a number, a sequence or the CLI's range text.

    >>> r = fastbrdf.normalize("pow", [1, 2])
    >>> [round(row["coef"] * 2 * np.pi, 9) for row in r["rows"]]
    [3.0, 4.0]
    """
    return dict(json.loads(_native.normalize_json(_str(model, "model"), _range(n, "n", 1.0), _opt_str(fit, "fit"))))


def lut(
    model: str = "env-brdf",
    *,
    size: int = 128,
    axis: str = "roughness",
    out: Optional[PathArg] = None,
    format: Optional[str] = None,
) -> Dict[str, Any]:
    """The split-sum "DFG" look-up table of env ``model``, as ``fastbrdf lut``: ``{"table":
    float32 array (size, size, 2) of (scale, bias), "model", "size", "axis", "clamped_rows",
    "cos_v", "roughness", "alpha"}``. ``table[j, i]`` is row ``j`` (``roughness[j]``, the
    ``alpha[j]`` evaluated, clamped to the domain in the first ``clamped_rows`` rows) and
    column ``i`` (``cos_v[i] = (i + 0.5) / size``); ``axis``: ``roughness`` (alpha = r^2)
    or ``alpha``. ``out``: also write the file ``fastbrdf lut --out`` writes (``.exr``,
    ``.png`` or ``.csv``, or as ``format`` says). Ctrl-C stops it.

    >>> t = fastbrdf.lut(size=4)
    >>> t["table"].shape, t["table"].dtype, float(t["cos_v"][0])
    ((4, 4, 2), dtype('float32'), 0.125)
    """
    meta_text, scale, bias = _native.lut_table(
        _str(model, "model"),
        _int(size, "size"),
        _str(axis, "axis"),
        _path(out, "out"),
        _opt_str(format, "format"),
    )
    meta: Dict[str, Any] = json.loads(meta_text)
    n = int(meta["size"])
    for k in ("cos_v", "roughness", "alpha"):
        meta[k] = np.asarray(meta[k], dtype=np.float32)
    return {"table": np.stack([scale, bias], axis=-1).reshape(n, n, 2), **meta}


def pareto(
    *,
    bench: Optional[PathArg] = None,
    brdf: bool = False,
    alpha: Any = 0.3,
    reference: str = "d=ggx,g=smith-ggx-correlated,f=dielectric,eta=1.5",
    size: int = 128,
    mesh: Optional[PathArg] = None,
    all: bool = False,
    quick: bool = False,
    front_on: str = "rms",
    grid: Optional[str] = None,
    costs: Optional[PathArg] = None,
) -> Dict[str, Any]:
    """Error against cost and the Pareto front, as ``fastbrdf pareto --json``.

    Lobes (the default): ``{models: [{model, ops, simd_evals_per_s, max_abs_1_1e5,
    max_abs_8_1e5, max_rel_epicentre_8_1e5, pareto}]}``, the throughput measured now or taken
    from ``bench`` (a saved ``fastbrdf bench --json``). About ten seconds.

    ``brdf=True`` (``pareto --brdf``): Cook-Torrance configurations (``all``: every D x G x F)
    against ``reference`` at each ``alpha`` (a number, up to 16 values or a range text):
    ``{reference, reference_label, alphas, grid, size, spp, mesh, front_on, rows: [{label, d,
    g, f, denominator, params, alpha, reference, simd, ns_per_eval, cost_ratio, max_rel_peak,
    max_at_deg, rms_rel, rms_abs, flip_sphere, flip_mesh, pareto}]}``; ``size`` is the render
    side of the FLIP columns (0: no renders; ``mesh`` an OBJ rendered too), ``quick`` a coarse
    grid and renders of at most 32 pixels, ``front_on`` ``rms``, ``max`` or ``flip``, ``grid``
    ``"THETAxPHI"``, ``costs`` a saved ``pareto --brdf --json`` whose costs are used instead
    of measuring. Ctrl-C stops it.

    >>> r = fastbrdf.pareto(brdf=True, quick=True, size=0)
    >>> r["reference_label"], r["grid"]
    ('ggx / smith-ggx-correlated / dielectric eta=1.5', {'phi': 32, 'theta': 16})
    """
    if not _bool(brdf, "brdf"):
        return dict(json.loads(_native.pareto_json(_path(bench, "bench"))))
    if bench is not None:
        raise ValueError("bench applies to the lobes (brdf=False); brdf=True takes costs=...")
    return dict(
        json.loads(
            _native.pareto_brdf_json(
                _range(alpha, "alpha", 0.05),
                _str(reference, "reference"),
                _int(size, "size"),
                _path(mesh, "mesh"),
                _bool(all, "all"),
                _bool(quick, "quick"),
                _str(front_on, "front_on"),
                _opt_str(grid, "grid"),
                _path(costs, "costs"),
            )
        )
    )


def chi2(
    model: str,
    *,
    theta_i: float = 45.0,
    strategy: str = "auto",
    samples: Optional[int] = None,
    res: Optional[int] = None,
    seed: int = 7,
    full: bool = False,
    precision: str = "f64",
    out: Optional[PathArg] = None,
    **params: Any,
) -> Dict[str, Any]:
    """The chi-square goodness-of-fit test of BRDF ``model``'s importance sampling, as
    ``fastbrdf chi2 --json``: ``samples`` directions (default 1e5, 1e6 with ``full``) drawn
    for ``wo`` at ``theta_i`` degrees with ``strategy`` (``auto``, ``cosine``, ``lobe``,
    ``d-cos``, ``vndf``, ``twin``) in ``precision``, histogrammed on ``res`` x 2 ``res`` bins
    (default 10, 101 with ``full``) against the pdf's integral over each bin. Returns
    ``{samples, res_theta, res_phi, chi2, dof, p_value, threshold, passed, pooled,
    pdf_integral, missing_observed, missing_expected, impossible, observed, expected, model,
    strategy, theta_i, params}``; a failed test is ``passed: False`` (nothing is raised).
    ``out``: also write the picture (PNG) of the histograms. Ctrl-C stops it (within 4096 draws).

    >>> r = fastbrdf.chi2("phong", n=100, samples=20000)
    >>> r["passed"], r["strategy"]
    (True, 'lobe')
    """
    model = _str(model, "model")
    for k, v in (("theta_i", theta_i),):
        if isinstance(v, (bool, np.bool_)):
            raise TypeError(f"{k}: expected a number, got bool")
    return dict(
        json.loads(
            _native.chi2_json(
                model,
                _params(model, params),
                theta_i,
                _str(strategy, "strategy"),
                None if samples is None else _int(samples, "samples"),
                None if res is None else _int(res, "res"),
                _int(seed, "seed"),
                _bool(full, "full"),
                _str(precision, "precision"),
                _path(out, "out"),
            )
        )
    )

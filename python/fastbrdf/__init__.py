"""fastbrdf: fast BRDF and lobe approximations, from Python.

The same vocabulary as the ``fastbrdf`` command line: model ids and parameters as in
``fastbrdf models``, the same validation and the same error messages (raised as
``ValueError``), computed by the same Rust library.

>>> import numpy as np, fastbrdf
>>> m = fastbrdf.Model("flog", n=20)
>>> m.eval(np.array([1.0, 0.95], dtype=np.float32))      # f32, SIMD kernel
array([1.        , 0.3448...], dtype=float32)
>>> ct = fastbrdf.Model("cook-torrance", alpha=0.2, f="schlick")
>>> float(ct.eval([0.0, 0.0, 1.0], [0.3, 0.0, 0.95], precision="f64"))
0.0482...

Array rules (every function taking arrays):

- dtypes: float32 and float64 arrays (and anything ``numpy.asarray`` turns into a real or
  integer array: lists, scalars, integer arrays) are accepted; bool, complex, object and
  string arrays are a ``TypeError`` naming the dtype.
- precision ``"f32"`` (default) evaluates in float32 through the SIMD batch kernels and returns
  float32; ``"f64"`` evaluates the scalar f64 model and returns float64. Input of another dtype
  is converted (one copy).
- a C-contiguous input of the precision's dtype is read in place (no copy); a non-contiguous
  one (a slice with steps, a transposed view) is copied once into a contiguous array.
- inputs broadcast against each other like numpy (BRDF directions over their leading
  dimensions, the last one being the 3 components); broadcasting to a larger shape copies.
- NaN and out-of-domain inputs follow the library's shading rules, per kind: lobes,
  distributions, shadowing terms and BRDFs give 0 for NaN (a lobe clamps its cosine to
  [0, 1] first; a BRDF gives 0 below the horizon or for a zero vector); a Fresnel term gives its
  value at 0 for NaN; a split-sum (env) term reads a NaN ``cos_v`` as 0 and a NaN ``alpha`` as
  its smallest value. No evaluation raises for NaN input (``sample`` refuses a NaN ``u``).
- unaligned arrays (``np.frombuffer`` at an odd offset) and byte-swapped ones are copied once.

Limits (as the CLI's): a sequence of parameter values (``errors``) or of angles (``albedo``)
holds at most ``MAX_VALUES`` (10^6) values and at least one. An output too large for memory
raises ``MemoryError`` (the output is allocated by numpy, as numpy's own). Long calls
(evaluations, sweeps, albedo curves, renders) stop on Ctrl-C with ``KeyboardInterrupt``: an
evaluation runs in chunks of about a million elements, the others on a worker thread that
stops at its next step. Wrong values raise ``ValueError`` and wrong types ``TypeError``, each
naming the argument; nothing else is raised for bad input (an internal error, a bug, is a
``RuntimeError``).
"""

from __future__ import annotations

import json
from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np

from . import _fastbrdf as _native

__all__ = [
    "KINDS",
    "LANGS",
    "MAX_VALUES",
    "Model",
    "albedo",
    "errors",
    "models",
    "render",
    "shader",
]

#: The model kinds, as ``fastbrdf models --kind`` names them.
KINDS = ("lobe", "distribution", "shadowing", "fresnel", "brdf", "env")
#: The languages of :func:`shader`, as ``fastbrdf shader --lang`` names them.
LANGS = ("wgsl", "glsl", "hlsl", "msl", "brdf-explorer")

#: The most values a sequence of parameter values or angles may hold (the CLI's cap on its
#: ranges and lists).
MAX_VALUES: int = int(_native.MAX_VALUES)

_DTYPES = {"f32": np.float32, "f64": np.float64}
#: The largest float32 below 1: where a float64 ``u`` just below 1 rounds to 1 in float32.
_BELOW_ONE_F32 = np.nextafter(np.float32(1), np.float32(0))

Number = Union[int, float, str]


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


def _param_text(model: str, name: str, value: Any) -> str:
    """A parameter value as the text the CLI's ``--param NAME=VALUE`` would carry."""
    if isinstance(value, (bool, np.bool_)):
        raise TypeError(f"model '{model}': parameter {name}: expected a number or a string, got bool")
    if isinstance(value, (int, np.integer)):
        return str(int(value))
    if isinstance(value, (float, np.floating)):
        return repr(float(value))
    if isinstance(value, str):
        return value
    raise TypeError(
        f"model '{model}': parameter {name}: expected a number or a string, got {type(value).__name__}"
    )


def _params(model: str, params: Dict[str, Any]) -> List[Tuple[str, str]]:
    return [(k, _param_text(model, k, v)) for k, v in params.items()]


def _dtype(precision: str) -> Any:
    try:
        return _DTYPES[precision]
    except (KeyError, TypeError):
        raise ValueError(f"precision '{precision}': expected f32 or f64") from None


def _array(x: Any, name: str) -> np.ndarray:
    """``x`` as an array, checked against the dtype rule (no copy for arrays)."""
    a = np.asarray(x)
    if a.dtype.kind not in "fiu":
        raise TypeError(
            f"{name}: dtype {a.dtype} is not supported: expected float32 or float64 "
            "(integers are converted)"
        )
    return a


def _prepare(a: np.ndarray, shape: Tuple[int, ...], dtype: Any) -> np.ndarray:
    """``a`` broadcast to ``shape``, C-contiguous, aligned and of ``dtype`` (native byte
    order): ``a`` itself (no copy) when it already is all of these."""
    if a.shape != shape:
        a = np.broadcast_to(a, shape)
    a = np.ascontiguousarray(a, dtype=dtype)
    if not a.flags.aligned:
        a = a.copy()
    return a


def _check_unit_interval(u: np.ndarray, name: str) -> None:
    """Every value of ``u`` in [0, 1) (NaN is not): else ``ValueError`` naming the first."""
    if u.size == 0:
        return
    lo, hi = u.min(), u.max()  # NaN propagates: the test below fails for it
    if lo >= 0 and hi < 1:
        return
    flat = u.reshape(-1)
    i = int(np.flatnonzero(~((flat >= 0) & (flat < 1)))[0])
    width = u.shape[-1]
    raise ValueError(f"{name}: {flat[i]} (row {i // width}, column {i % width}) is outside [0, 1)")


def _vectors(x: Any, name: str, width: int) -> np.ndarray:
    a = _array(x, name)
    if a.ndim == 0 or a.shape[-1] != width:
        raise ValueError(f"{name}: expected shape (..., {width}), got {a.shape}")
    return a


def _broadcast(names: Sequence[str], shapes: Sequence[Tuple[int, ...]]) -> Tuple[int, ...]:
    try:
        return tuple(np.broadcast_shapes(*shapes))
    except ValueError:
        listed = ", ".join(f"{n} {s}" for n, s in zip(names, shapes))
        raise ValueError(f"shapes do not broadcast: {listed}") from None


def _result(out: np.ndarray, shape: Tuple[int, ...]) -> Any:
    out = out.reshape(shape)
    return out[()] if shape == () else out


class Model:
    """One model by id, with its parameters as keyword arguments (validated at once).

    >>> m = fastbrdf.Model("ggx", alpha=0.3)
    >>> m.kind, m.inputs
    ('distribution', (['cos_h'], []))
    >>> fastbrdf.Model("flog", n=0)
    Traceback (most recent call last):
    ValueError: model 'flog': parameter n = 0 is invalid: expected ...
    """

    def __init__(self, id: str, **params: Any) -> None:
        if not isinstance(id, str):
            raise TypeError(f"model id: expected a string, got {type(id).__name__}")
        self._params = dict(params)
        self._handle = _native.Handle(id, _params(id, params))
        self._info: Optional[Dict[str, Any]] = None

    def __repr__(self) -> str:
        args = "".join(f", {k}={v!r}" for k, v in self._params.items())
        return f"Model({self.id!r}{args})"

    @property
    def id(self) -> str:
        """The model id."""
        return str(self._handle.id)

    @property
    def kind(self) -> str:
        """``lobe``, ``distribution``, ``shadowing``, ``fresnel``, ``brdf`` or ``env``."""
        return str(self._handle.kind)

    @property
    def params(self) -> Dict[str, Any]:
        """The parameters as given (the rest take their defaults, listed in ``info``)."""
        return dict(self._params)

    @property
    def inputs(self) -> Tuple[List[str], List[str]]:
        """The inputs ``eval`` takes, ``(required, optional)``, named as ``fastbrdf eval``'s
        columns (a BRDF: ``wi_*``, ``wo_*``, given as two (..., 3) arrays)."""
        r, o = self._handle.columns
        return list(r), list(o)

    @property
    def simd(self) -> bool:
        """Whether f32 evaluation runs a vectorised kernel (else the scalar f32 model)."""
        return bool(self._handle.simd)

    @property
    def info(self) -> Dict[str, Any]:
        """The model's entry of ``fastbrdf models --json``: id, kind, params (with ranges and
        defaults), formula, source, ops (cost), bounds, f32_bound, note."""
        if self._info is None:
            self._info = json.loads(_native.info_json(self.id))
        return dict(self._info)

    def eval(self, *inputs: Any, precision: str = "f32") -> Any:
        """Evaluates the model: ``eval(cos)`` for lobes (likewise ``cos_h`` for
        distributions, ``cos_vh`` for Fresnel terms; ``eval(cos_v, alpha)`` for env terms;
        shadowing terms take their inputs in the order of ``inputs``) and ``eval(wi, wo)``
        with arrays of shape (..., 3) for BRDFs (local frame, normal +z, both pointing away
        from the surface, of any length; the value has no cosine factor).

        Returns an array of the broadcast shape (a numpy scalar for scalar inputs), float32
        for ``precision="f32"`` and float64 for ``"f64"``. The GIL is released while it runs.

        >>> fastbrdf.Model("pow", n=2).eval([1.0, 0.5])
        array([1.  , 0.25], dtype=float32)
        """
        dtype = _dtype(precision)
        h = self._handle
        if self.kind == "brdf":
            if len(inputs) != 2:
                raise TypeError(
                    f"model '{self.id}' is a brdf: eval(wi, wo) takes two arrays of shape (..., 3), "
                    f"got {len(inputs)} argument(s)"
                )
            wi, wo = _vectors(inputs[0], "wi", 3), _vectors(inputs[1], "wo", 3)
            shape = _broadcast(["wi", "wo"], [wi.shape[:-1], wo.shape[:-1]])
            wi, wo = _prepare(wi, shape + (3,), dtype), _prepare(wo, shape + (3,), dtype)
            fd = h.eval_dirs_f32 if precision == "f32" else h.eval_dirs_f64
            return _result(fd(wi.reshape(-1, 3), wo.reshape(-1, 3)), shape)
        req, opt = self.inputs
        if not len(req) <= len(inputs) <= len(req) + len(opt):
            want = ", ".join(req) + ("" if not opt else f" (optionally {', '.join(opt)})")
            raise TypeError(
                f"model '{self.id}' is a {self.kind}: eval takes {want}, got {len(inputs)} argument(s)"
            )
        names = (req + opt)[: len(inputs)]
        arrays = [_array(x, n) for x, n in zip(inputs, names)]
        shape = _broadcast(names, [a.shape for a in arrays])
        cols = [_prepare(a, shape, dtype).reshape(-1) for a in arrays]
        fc = h.eval_f32 if precision == "f32" else h.eval_f64
        return _result(fc(cols), shape)

    def strategies(self) -> List[str]:
        """The sampling strategies of a BRDF, its default (``auto``) first."""
        return list(self._handle.strategies())

    def sample(
        self, wo: Any, u: Any, strategy: str = "auto", precision: str = "f32"
    ) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Draws ``wi`` given ``wo`` (..., 3) and ``u`` (..., 2) in [0, 1)^2, as
        ``fastbrdf sample`` (``u`` outside [0, 1) or NaN is a ``ValueError``): returns
        ``(wi (..., 3), weight (...), pdf (...))`` with
        ``weight = f(wi, wo) cos(theta_i) / pdf``. A draw that yields no sample (below the
        horizon, density 0: the strategy's missing mass, or ``wo`` out of the domain) gives
        ``wi = (0, 0, 0)``, weight 0 and pdf 0. BRDFs only.

        >>> wi, w, p = fastbrdf.Model("lambert").sample([0, 0, 1], [0.3, 0.7])
        >>> float(w)
        1.0
        """
        dtype = _dtype(precision)
        wo_a, u_given = _vectors(wo, "wo", 3), _vectors(u, "u", 2)
        _check_unit_interval(u_given, "u")
        shape = _broadcast(["wo", "u"], [wo_a.shape[:-1], u_given.shape[:-1]])
        wo_a, u_a = _prepare(wo_a, shape + (3,), dtype), _prepare(u_given, shape + (2,), dtype)
        if u_a.dtype != u_given.dtype and dtype is np.float32:
            # A fresh copy: keep float64 values just below 1 below 1 in float32.
            np.minimum(u_a, _BELOW_ONE_F32, out=u_a)
        h = self._handle
        f = h.sample_f32 if precision == "f32" else h.sample_f64
        wi, weight, pdf = f(wo_a.reshape(-1, 3), u_a.reshape(-1, 2), strategy)
        return wi.reshape(shape + (3,)), _result(weight, shape), _result(pdf, shape)

    def pdf(self, wo: Any, wi: Any, strategy: str = "auto", precision: str = "f32") -> Any:
        """The solid-angle density with which :meth:`sample` draws ``wi`` given ``wo``
        (both (..., 3)), as ``fastbrdf sample --pdf``. BRDFs only."""
        dtype = _dtype(precision)
        wo_a, wi_a = _vectors(wo, "wo", 3), _vectors(wi, "wi", 3)
        shape = _broadcast(["wo", "wi"], [wo_a.shape[:-1], wi_a.shape[:-1]])
        wo_a, wi_a = _prepare(wo_a, shape + (3,), dtype), _prepare(wi_a, shape + (3,), dtype)
        h = self._handle
        f = h.pdf_f32 if precision == "f32" else h.pdf_f64
        return _result(f(wo_a.reshape(-1, 3), wi_a.reshape(-1, 3), strategy), shape)


def _values(x: Any, name: str, default_step: float) -> List[float]:
    """A range text or a sequence of numbers: at least one, at most ``MAX_VALUES``."""
    if isinstance(x, str):
        return list(_native.parse_range(x, default_step))
    a = _array(x, name).reshape(-1)
    if a.size > MAX_VALUES:
        raise ValueError(f"{name}: {a.size} values; at most {MAX_VALUES} are allowed")
    if a.size == 0:
        raise ValueError(f"{name}: no values")
    return [float(v) for v in a.astype(np.float64)]


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
    **params: Any,
) -> Dict[str, Any]:
    """Directional albedo against the incidence angle (degrees, in [0, 90)) and the
    white-furnace verdict, as ``fastbrdf albedo --json``: ``{model, brdf, params,
    claims_energy, conserves, rows: [{theta_deg, albedo, error}]}``. A lobe is evaluated as
    ``as_brdf`` (``phong`` or ``blinn-phong``) normalised by ``norm`` (``energy`` or ``none``).
    ``angles``: a number, a sequence (1 to ``MAX_VALUES`` values) or a range text. Ctrl-C stops
    it.

    >>> r = fastbrdf.albedo("lambert", angles=[0, 60])
    >>> [round(row["albedo"], 6) for row in r["rows"]]
    [1.0, 1.0]
    """
    for k, v in (("as_brdf", as_brdf), ("norm", norm)):
        if not isinstance(v, str):
            raise TypeError(f"{k}: expected a string, got {type(v).__name__}")
    return dict(
        json.loads(
            _native.albedo_json(model, _params(model, params), _values(angles, "angles", 5.0), as_brdf, norm)
        )
    )


def _triple(name: str, x: Any, count: int, top: float = 1e3) -> Tuple[float, ...]:
    v = _array(x, name).astype(np.float64).reshape(-1)
    if v.shape != (count,) or not np.all((v >= 0) & (v <= top)):
        raise ValueError(f"{name} {tuple(np.asarray(x).reshape(-1).tolist())}: expected {count} numbers from 0 to {top:g}")
    return tuple(float(a) for a in v)


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


def shader(model: str, *, lang: str = "wgsl", runtime_params: bool = False, **params: Any) -> str:
    """The model as a self-contained shader function ``fb_<id>`` (dashes as underscores), as
    ``fastbrdf shader``: ``lang`` is ``wgsl``, ``glsl``, ``hlsl``, ``msl`` or
    ``brdf-explorer``; ``runtime_params`` takes the numeric parameters as trailing arguments
    ``p_<name>``. Needs no GPU.

    >>> "fn fb_flog(" in fastbrdf.shader("flog", n=20)
    True
    """
    return str(_native.shader(model, _params(model, params), lang, bool(runtime_params)))

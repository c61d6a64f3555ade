"""fastbrdf's BRDF models as a Mitsuba 3 BSDF plug-in named ``fastbrdf``.

``import fastbrdf`` never imports this module, and importing it imports neither Mitsuba nor
Dr.Jit: :func:`register` does, and registers the plug-in for the current variant (Mitsuba keeps
plug-ins per variant: register again after switching). Importing registers nothing::

    import mitsuba as mi
    import fastbrdf.mitsuba
    fastbrdf.mitsuba.register("scalar_rgb")          # or mi.set_variant(...); register()
    bsdf = mi.load_dict({"type": "fastbrdf", "model": "cook-torrance", "d": "ggx", "alpha": 0.2})

Properties: ``model`` (a BRDF id of ``fastbrdf.models("brdf")``), every parameter of that model
by its fastbrdf name (numbers, choices, R,G,B strings such as ``"0.9,0.6,0.3"`` or Mitsuba's
``{"type": "rgb", "value": [...]}``, validated by :class:`fastbrdf.Model`, whose ``ValueError`` comes out of ``mi.load_dict`` with fastbrdf's
message), ``metal`` and ``material`` (passed to :class:`fastbrdf.Model` as its keywords),
``strategy`` (a sampling strategy of the model, ``auto`` by default), ``precision`` (``f32``,
the default, or ``f64``) and ``reflectance`` (a texture or a number multiplying the model, 1 by
default). Per-element arrays (a list or numpy array, which Mitsuba stores as a vector) are
refused: the plug-in has one model.

Colour: a coloured model (``fastbrdf.Model.channels == 3``: ``metal="gold"``, an R,G,B value)
gives a ``Color3f`` per call in the RGB variants (eval's f, sample's weight, per channel; one
pdf, that of fastbrdf's draw, which follows the R channel's strategy); the spectral and mono
variants refuse a coloured model (fastbrdf's colours are R, G, B values, not spectra).

Conventions: Mitsuba's local shading frame is fastbrdf's (normal +z, both directions pointing
away from the surface). Mitsuba's ``si.wi`` (the given direction, towards the viewer) is
fastbrdf's ``wo`` and Mitsuba's ``wo`` (the sampled or light direction) is fastbrdf's ``wi``;
``eval`` returns fastbrdf's ``f`` times the cosine of Mitsuba's ``wo``, ``sample`` returns
fastbrdf's draw (``bs.wo``, ``bs.pdf``, ``eta`` 1, glossy reflection) and its weight
``f cos / pdf``. One glossy-reflection component, front side only (as ``roughconductor``).

The vectorized variants (``llvm_*``, ``cuda_*``) evaluate whole wavefronts through numpy, which
needs evaluated arrays: render inside :func:`evaluated_mode` (or turn Dr.Jit's
``SymbolicLoops`` and ``SymbolicCalls`` flags off yourself); called in a symbolic scope the
plug-in raises a ``RuntimeError`` saying so. There, ``mi.traverse`` lists ``reflectance`` and
the numbers given (``alpha``, ...), and changing one rebuilds the model (validated again). The
plug-in is not differentiable (no gradient flows through numpy); polarized variants are
refused; spectral and mono variants get a grey model's value on every channel.
"""

from __future__ import annotations

import contextlib
from typing import Any, Dict, Iterator, List, Optional, Tuple

import numpy as np

from ._model import Model

__all__ = ["PLUGIN", "register", "bsdf_class", "evaluated_mode"]

#: The plug-in's name (``"type"`` in ``mi.load_dict``).
PLUGIN = "fastbrdf"

#: Properties that are the plug-in's own, not the model's.
_OWN = ("type", "id", "model", "strategy", "precision", "reflectance")

_CLASSES: Dict[str, Any] = {}

_SYMBOLIC = (
    "fastbrdf.mitsuba: the plug-in evaluates through numpy and cannot run in a symbolic Dr.Jit "
    "scope; call dr.set_flag(dr.JitFlag.SymbolicLoops, False) and "
    "dr.set_flag(dr.JitFlag.SymbolicCalls, False) before rendering"
)


def _mi() -> Tuple[Any, Any]:
    import drjit as dr
    import mitsuba as mi

    return mi, dr


def register(variant: Optional[str] = None) -> str:
    """Registers the ``fastbrdf`` BSDF plug-in for Mitsuba's current variant (or for
    ``variant``, which is then set) and returns the plug-in name. Call it again after
    switching to another variant; calling it twice for one variant is harmless.

    >>> import mitsuba as mi, fastbrdf.mitsuba
    >>> fastbrdf.mitsuba.register("scalar_rgb")
    'fastbrdf'
    >>> b = mi.load_dict({"type": "fastbrdf", "model": "cook-torrance", "d": "ggx", "alpha": 0.2})
    >>> si = mi.SurfaceInteraction3f(); si.wi = [0, 0, 1]
    >>> float(b.eval(mi.BSDFContext(), si, [0, 0, 1])[0]) > 0
    True
    """
    mi, _ = _mi()
    if variant is not None:
        if not isinstance(variant, str):
            raise TypeError(f"variant: expected a string, got {type(variant).__name__}")
        mi.set_variant(variant)
    name = mi.variant()
    if name is None:
        raise ValueError("variant: no Mitsuba variant is set (call mi.set_variant first)")
    if "polarized" in name:
        raise ValueError(f"variant: '{name}' is polarized; the fastbrdf plug-in is unpolarized only")
    cls = bsdf_class()
    mi.register_bsdf(PLUGIN, lambda props: cls(props))
    return PLUGIN


@contextlib.contextmanager
def evaluated_mode() -> Iterator[None]:
    """Turns Dr.Jit's symbolic loops and calls off inside the ``with`` block (restored after),
    which the vectorized variants need to run the plug-in (see the module's notes). Harmless in
    the scalar variants.

    >>> import mitsuba as mi, drjit as dr, fastbrdf.mitsuba
    >>> with fastbrdf.mitsuba.evaluated_mode():
    ...     bool(dr.flag(dr.JitFlag.SymbolicLoops))
    False
    """
    _, dr = _mi()
    flags = (dr.JitFlag.SymbolicLoops, dr.JitFlag.SymbolicCalls)
    before = [dr.flag(f) for f in flags]
    try:
        for f in flags:
            dr.set_flag(f, False)
        yield
    finally:
        for f, b in zip(flags, before):
            dr.set_flag(f, b)


def bsdf_class() -> Any:
    """The plug-in's class (a subclass of the current variant's ``mi.BSDF``), built once per
    variant."""
    mi, dr = _mi()
    name = mi.variant()
    if name is None:
        raise ValueError("variant: no Mitsuba variant is set (call mi.set_variant first)")
    if name not in _CLASSES:
        _CLASSES[name] = _make_class(mi, dr, name.startswith("scalar"), "rgb" in name)
    return _CLASSES[name]


def _property(props: Any, key: str) -> Any:
    """A model parameter from Mitsuba's properties: numbers as floats, strings as given."""
    value = props[key]
    if isinstance(value, bool):
        return value
    if isinstance(value, (int, float)):
        return float(value)
    if isinstance(value, str):
        return value
    _, dr = _mi()
    if type(value).__name__ in ("Color3f", "Color3d", "ScalarColor3f", "ScalarColor3d"):
        # {"type": "rgb", "value": [r, g, b]} for a number: fastbrdf's R,G,B string (one
        # number when grey, which keeps the model grey).
        rgb = [float(x) for x in value]
        return rgb[0] if rgb[0] == rgb[1] == rgb[2] else ",".join(map(repr, rgb))
    if isinstance(value, (np.ndarray, list, tuple)) or dr.is_array_v(value):
        raise TypeError(
            f"fastbrdf: property '{key}': per-element arrays are not supported (one model per "
            "BSDF); give one number, or a colour as an R,G,B string such as \"0.9,0.6,0.3\""
        )
    try:
        return float(value)
    except (TypeError, ValueError):
        raise TypeError(
            f"fastbrdf: property '{key}': expected a number or a string, got {type(value).__name__}"
        ) from None


def _unit(x: float, below_one: float) -> float:
    """x clamped to [0, 1) (NaN: 0), for fastbrdf's sampling."""
    return min(max(float(x), 0.0), below_one) if x == x else 0.0


def _make_class(mi: Any, dr: Any, scalar: bool, rgb: bool) -> Any:
    glossy = mi.BSDFFlags.GlossyReflection
    flags = glossy | mi.BSDFFlags.FrontSide
    below_one = float(np.float32(1.0 - 2.0**-24))

    def rows(v: Any) -> np.ndarray:
        """A Mitsuba Vector3f wavefront (or Point2f) as an (N, dim) float32 array."""
        a = np.asarray(v, dtype=np.float32)
        return a.reshape(a.shape[0], -1).T

    def widen(*arrays: np.ndarray) -> List[np.ndarray]:
        n = max(len(a) for a in arrays)
        return [np.broadcast_to(a, (n,) + a.shape[1:]) for a in arrays]

    def floats(a: np.ndarray) -> Any:
        return mi.Float(np.ascontiguousarray(a, dtype=np.float32))

    def spectrum(a: np.ndarray) -> Any:
        """(N,) grey values as a Float (it multiplies a Spectrum), (N, 3) as a Color3f."""
        if a.ndim == 1:
            return floats(a)
        return mi.Color3f(*(floats(a[:, c]) for c in range(a.shape[1])))

    def scalar_spectrum(v: np.ndarray) -> Any:
        """A scalar call's value: a float (grey) or (3,) R, G, B as a Color3f."""
        v = np.asarray(v, np.float64)
        if v.ndim == 0:
            return float(v)
        return mi.Color3f(*(float(x) for x in v.reshape(-1)))

    def lanes(mask: np.ndarray, like: np.ndarray) -> np.ndarray:
        """An (N,) mask or factor shaped to broadcast against (N,) or (N, channels)."""
        return mask if like.ndim == 1 else mask[:, None]

    class FastbrdfBSDF(mi.BSDF):  # type: ignore[misc]
        """fastbrdf's BRDF model as a Mitsuba BSDF (see fastbrdf.mitsuba)."""

        def __init__(self, props: Any) -> None:
            mi.BSDF.__init__(self, props)
            if "model" not in props:
                raise ValueError(
                    "fastbrdf: property 'model' is missing (a BRDF id of fastbrdf.models('brdf'))"
                )
            model_id = props["model"]
            if not isinstance(model_id, str):
                raise TypeError(
                    f"fastbrdf: property 'model': expected a string, got {type(model_id).__name__}"
                )
            params = {k: _property(props, k) for k in props.keys() if k not in _OWN}
            self.strategy = str(props["strategy"]) if "strategy" in props else "auto"
            self.precision = str(props["precision"]) if "precision" in props else "f32"
            if self.precision not in ("f32", "f64"):
                raise ValueError(
                    f"fastbrdf: property 'precision': expected 'f32' or 'f64', got {self.precision!r}"
                )
            self.model_id = model_id
            # The properties given (metal and material included), for rebuilding.
            self.params = params
            self.model = self._build(model_id, params)
            self.reflectance = props.get_texture("reflectance", 1.0)
            # The numbers given, as Dr.Jit values that mi.traverse can change (JIT variants).
            self.numbers = {
                k: mi.Float(v) for k, v in params.items() if isinstance(v, float) and not scalar
            }
            self.m_components = [flags]
            self.m_flags = flags

        def _build(self, model_id: str, params: Dict[str, Any]) -> Model:
            model = Model(model_id, **params)
            if model.kind != "brdf":
                raise ValueError(
                    f"fastbrdf: property 'model': '{model_id}' is a {model.kind}, not a brdf "
                    "(see fastbrdf.models('brdf'))"
                )
            if model.channels != 1 and not rgb:
                raise ValueError(
                    f"fastbrdf: the model {model!r} is coloured (R, G, B) and the variant "
                    f"'{mi.variant()}' is not an RGB one: use an *_rgb variant or a grey model"
                )
            if self.strategy != "auto" and self.strategy not in model.strategies():
                raise ValueError(
                    f"fastbrdf: property 'strategy': '{self.strategy}' is not one of "
                    f"{['auto'] + model.strategies()}"
                )
            return model

        # -- numpy side: (N, 3) arrays in Mitsuba's naming (wi: si.wi, wo: the light) ---------

        def _f_cos(self, wi: np.ndarray, wo: np.ndarray) -> np.ndarray:
            """f(fastbrdf wi = Mitsuba wo, fastbrdf wo = Mitsuba wi) cos(Mitsuba wo); 0 below
            either horizon."""
            f = np.asarray(self.model.eval(wo, wi, precision=self.precision), np.float64)
            up = (wi[:, 2] > 0) & (wo[:, 2] > 0)
            return np.where(lanes(up, f), f * lanes(wo[:, 2], f), 0.0)

        def _pdf(self, wi: np.ndarray, wo: np.ndarray) -> np.ndarray:
            p = self.model.pdf(wi, wo, strategy=self.strategy, precision=self.precision)
            return np.where((wi[:, 2] > 0) & (wo[:, 2] > 0), np.asarray(p, np.float64), 0.0)

        def _draw(self, wi: np.ndarray, u: np.ndarray) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
            # Inactive lanes may hold anything: fastbrdf refuses u outside [0, 1) or NaN.
            u = np.clip(np.nan_to_num(u, nan=0.0), 0.0, below_one).astype(np.float32)
            d, w, p = self.model.sample(wi, u, strategy=self.strategy, precision=self.precision)
            d = np.asarray(d, np.float32).reshape(-1, 3)
            p = np.asarray(p, np.float64).reshape(-1)
            w = np.asarray(w, np.float64).reshape(len(p), -1)  # (N, channels)
            ok = (wi[:, 2] > 0) & (p > 0) & (d[:, 2] > 0) & np.all(np.isfinite(w), axis=1)
            w = np.where(ok[:, None], w, 0.0)
            return d, (w[:, 0] if self.model.channels == 1 else w), np.where(ok, p, 0.0)

        def _scalar_pair(self, si: Any, wo: Any) -> Tuple[np.ndarray, np.ndarray]:
            a, b = si.wi, wo
            return (
                np.array([a[0], a[1], a[2]], np.float32),
                np.array([b[0], b[1], b[2]], np.float32),
            )

        def _scalar_f_cos(self, wi: np.ndarray, wo: np.ndarray) -> Any:
            # The callers checked both directions above the horizon.
            f = np.asarray(self.model.eval(wo, wi, precision=self.precision), np.float64)
            return scalar_spectrum(f * float(wo[2]))

        def _scalar_pdf(self, wi: np.ndarray, wo: np.ndarray) -> float:
            return float(self.model.pdf(wi, wo, strategy=self.strategy, precision=self.precision))

        def _wave_pair(self, si: Any, wo: Any) -> Tuple[np.ndarray, np.ndarray]:
            if dr.flag(dr.JitFlag.SymbolicScope):
                raise RuntimeError(_SYMBOLIC)
            wi_a, wo_a = widen(rows(si.wi), rows(wo))
            return wi_a, wo_a

        # -- Mitsuba's interface -------------------------------------------------------------

        def eval(self, ctx: Any, si: Any, wo: Any, active: Any = True) -> Any:
            if not ctx.is_enabled(glossy, 0):
                return dr.zeros(mi.Spectrum)
            if scalar:
                if not active or si.wi[2] <= 0 or wo[2] <= 0:
                    return mi.Spectrum(0.0)
                wi_a, wo_a = self._scalar_pair(si, wo)
                return self.reflectance.eval(si, active) * self._scalar_f_cos(wi_a, wo_a)
            value = spectrum(self._f_cos(*self._wave_pair(si, wo)))
            return dr.select(active, self.reflectance.eval(si, active) * value, 0.0)

        def pdf(self, ctx: Any, si: Any, wo: Any, active: Any = True) -> Any:
            if not ctx.is_enabled(glossy, 0):
                return dr.zeros(mi.Float)
            if scalar:
                if not active or si.wi[2] <= 0 or wo[2] <= 0:
                    return 0.0
                wi_a, wo_a = self._scalar_pair(si, wo)
                return self._scalar_pdf(wi_a, wo_a)
            return dr.select(active, floats(self._pdf(*self._wave_pair(si, wo))), 0.0)

        def eval_pdf(self, ctx: Any, si: Any, wo: Any, active: Any = True) -> Tuple[Any, Any]:
            if not ctx.is_enabled(glossy, 0):
                return dr.zeros(mi.Spectrum), dr.zeros(mi.Float)
            if scalar:
                if not active or si.wi[2] <= 0 or wo[2] <= 0:
                    return mi.Spectrum(0.0), 0.0
                wi_a, wo_a = self._scalar_pair(si, wo)
                value = self._scalar_f_cos(wi_a, wo_a)
                return self.reflectance.eval(si, active) * value, self._scalar_pdf(wi_a, wo_a)
            wi_a, wo_a = self._wave_pair(si, wo)
            value, pdf = spectrum(self._f_cos(wi_a, wo_a)), floats(self._pdf(wi_a, wo_a))
            r = self.reflectance.eval(si, active)
            return dr.select(active, r * value, 0.0), dr.select(active, pdf, 0.0)

        def sample(
            self, ctx: Any, si: Any, sample1: Any, sample2: Any, active: Any = True
        ) -> Tuple[Any, Any]:
            enabled = ctx.is_enabled(glossy, 0)
            if scalar:
                bs = mi.BSDFSample3f()
                if not enabled or not active or si.wi[2] <= 0:
                    return bs, mi.Spectrum(0.0)
                wi_a = np.array([si.wi[0], si.wi[1], si.wi[2]], np.float32)
                # Mitsuba may hand u = 1 (or NaN in a dead lane): fastbrdf refuses both.
                u = np.array([_unit(sample2[0], below_one), _unit(sample2[1], below_one)], np.float32)
                d, w_a, p_a = self.model.sample(
                    wi_a, u, strategy=self.strategy, precision=self.precision
                )
                p, w = float(p_a), np.asarray(w_a, np.float64)
                if not p > 0 or not d[2] > 0 or not np.all(np.isfinite(w)):
                    return bs, mi.Spectrum(0.0)
                bs.wo = mi.Vector3f(float(d[0]), float(d[1]), float(d[2]))
                bs.pdf = p
                bs.eta = 1.0
                bs.sampled_type = +glossy
                bs.sampled_component = 0
                return bs, self.reflectance.eval(si, active) * scalar_spectrum(w)
            if dr.flag(dr.JitFlag.SymbolicScope):
                raise RuntimeError(_SYMBOLIC)
            wi_a, u = widen(rows(si.wi), rows(sample2))
            n = len(wi_a)
            bs = dr.zeros(mi.BSDFSample3f, n)
            if not enabled:
                return bs, dr.zeros(mi.Spectrum, n)
            dirs, weights, pdfs = self._draw(wi_a, u)
            bs.wo = mi.Vector3f(*(floats(dirs[:, i]) for i in range(3)))
            bs.pdf = floats(pdfs)
            bs.eta = 1.0
            bs.sampled_type = mi.UInt32(+glossy)
            bs.sampled_component = mi.UInt32(0)
            active = active & (bs.pdf > 0)
            bs.pdf = dr.select(active, bs.pdf, 0.0)
            weight = self.reflectance.eval(si, active) * spectrum(weights)
            return bs, dr.select(active, weight, 0.0)

        def traverse(self, callback: Any) -> None:
            callback.put("reflectance", self.reflectance, mi.ParamFlags.Differentiable)
            for k, v in self.numbers.items():
                callback.put(k, v, mi.ParamFlags.NonDifferentiable)

        def parameters_changed(self, keys: List[str] = []) -> None:  # noqa: B006
            changed = [k for k in keys if k in self.numbers] if keys else list(self.numbers)
            if changed:
                # From the properties given: Model.params leaves metal and material out.
                params = dict(self.params)
                for k in changed:
                    # Through float32 (the Float it was stored as): 0.1 stays 0.1.
                    params[k] = float(str(np.float32(np.asarray(self.numbers[k]).reshape(-1)[0])))
                self.model = self._build(self.model_id, params)
                self.params = params

        def to_string(self) -> str:
            return (
                f"FastbrdfBSDF[\n  model = {self.model!r},\n  strategy = {self.strategy!r},\n"
                f"  precision = {self.precision!r},\n  reflectance = {self.reflectance}\n]"
            )

    return FastbrdfBSDF

"""``Model``: one model by id with its parameters, evaluated, sampled and its density computed
over numpy arrays."""

from __future__ import annotations

import json
from typing import Any, Dict, List, Literal, Optional, Tuple, overload

import numpy as np
import numpy.typing as npt

F32 = npt.NDArray[np.float32]
F64 = npt.NDArray[np.float64]

from . import _fastbrdf as _native
from ._arrays import (
    _BELOW_ONE_F32,
    _array,
    _broadcast,
    _check_unit_interval,
    _dtype,
    _opt_str,
    _params,
    _prepare,
    _result,
    _vectors,
)

__all__ = ["Model"]


class Model:
    """One model by id, with its parameters as keyword arguments (validated at once).

    >>> m = fastbrdf.Model("ggx", alpha=0.3)
    >>> m.kind, m.inputs
    ('distribution', (['cos_h'], []))
    >>> fastbrdf.Model("flog", n=0)
    Traceback (most recent call last):
    ValueError: model 'flog': parameter n = 0 is invalid: expected ...
    """

    def __init__(
        self, id: str, *, material: Optional[str] = None, metal: Optional[str] = None, **params: Any
    ) -> None:
        if not isinstance(id, str):
            raise TypeError(f"model id: expected a string, got {type(id).__name__}")
        self._material, self._metal = _opt_str(material, "material"), _opt_str(metal, "metal")
        scalars = {k: v for k, v in params.items() if not isinstance(v, np.ndarray) or v.ndim == 0}
        # Per-element values are copied and frozen: a model is a value, so the caller's array
        # changing later (or an ``out=`` aliasing it) must not change the model, its hash or
        # its repr.
        self._arrays: Dict[str, np.ndarray] = {
            k: _frozen(_array(v, k)) for k, v in params.items() if isinstance(v, np.ndarray) and v.ndim > 0
        }
        self._params = {k: self._arrays.get(k, v) for k, v in params.items()}
        self._handles = list(_native.Handle.channels(id, _params(id, scalars), material, metal))
        self._handle = self._handles[0]
        if self._arrays:
            from . import _perelement

            for h in self._handles:
                _perelement.check(h, self._arrays)
        self._info: Optional[Dict[str, Any]] = None

    def __repr__(self) -> str:
        """``fastbrdf.Model(id, name=value, ...)`` with the parameters as given: evaluating it
        (with ``fastbrdf`` imported) builds an equal model.

        >>> m = fastbrdf.Model("ggx", alpha=0.3)
        >>> m
        fastbrdf.Model('ggx', alpha=0.3)
        >>> eval(repr(m)) == m
        True
        """
        given = dict(self._params)
        given.update((k, v) for k, v in (("material", self._material), ("metal", self._metal)) if v is not None)
        args = "".join(f", {k}={_repr_value(v)}" for k, v in given.items())
        return f"fastbrdf.Model({self.id!r}{args})"

    def _key(self) -> Tuple[Any, ...]:
        arrays = tuple(
            (k, a.shape, a.astype(np.float64).tobytes()) for k, a in sorted(self._arrays.items())
        )
        return (self.id, tuple(tuple(h.values) for h in self._handles), arrays)

    def __eq__(self, other: object) -> bool:
        """Equal by value: the same model with the same resolved parameters (a default given
        explicitly equals it left out; ``alpha=0.3`` equals ``alpha=0.30``).

        >>> fastbrdf.Model("flog", n=20) == fastbrdf.Model("flog", n=20.0)
        True
        >>> fastbrdf.Model("ggx") == fastbrdf.Model("ggx", alpha=fastbrdf.Model("ggx").values["alpha"])
        True
        """
        if not isinstance(other, Model):
            return NotImplemented
        return self._key() == other._key()

    def __hash__(self) -> int:
        return hash(self._key())

    def __reduce__(self) -> Tuple[Any, ...]:
        """Pickles by value (id and parameters as given), so ``pickle``, ``copy.deepcopy``,
        ``multiprocessing``, joblib and dask can ship a model; unpickling validates again.

        >>> import pickle
        >>> m = fastbrdf.Model("cook-torrance", alpha=0.2, f="schlick")
        >>> pickle.loads(pickle.dumps(m)) == m
        True
        """
        return (_rebuild, (self.id, dict(self._params), self._material, self._metal))

    @property
    def id(self) -> str:
        """The model id.

        >>> fastbrdf.Model("ggx").id
        'ggx'
        """
        return str(self._handle.id)

    @property
    def values(self) -> Dict[str, Any]:
        """Every parameter resolved: the values given and the defaults of the others
        (numbers as floats, choices as strings).

        >>> fastbrdf.Model("cook-torrance", alpha=0.2).values["d"]
        'beckmann'
        """
        return dict(self._handle.values)

    @property
    def kind(self) -> str:
        """``lobe``, ``distribution``, ``shadowing``, ``fresnel``, ``brdf`` or ``env``.

        >>> fastbrdf.Model("smith-ggx").kind
        'shadowing'
        """
        return str(self._handle.kind)

    @property
    def params(self) -> Dict[str, Any]:
        """The parameters as given (the rest take their defaults: see ``values``).

        >>> fastbrdf.Model("ggx", alpha=0.3).params
        {'alpha': 0.3}
        """
        return dict(self._params)

    @property
    def inputs(self) -> Tuple[List[str], List[str]]:
        """The inputs ``eval`` takes, ``(required, optional)``, named as ``fastbrdf eval``'s
        columns (a BRDF: ``wi_*``, ``wo_*``, given as two (..., 3) arrays).

        >>> fastbrdf.Model("smith-ggx").inputs
        (['cos_v'], ['cos_l'])
        """
        r, o = self._handle.columns
        return list(r), list(o)

    @property
    def simd(self) -> bool:
        """Whether f32 evaluation runs a vectorised kernel (else the scalar f32 model).

        >>> fastbrdf.Model("ggx").simd, fastbrdf.Model("smith-ggx").simd
        (True, False)
        """
        return bool(self._handle.simd)

    @property
    def info(self) -> Dict[str, Any]:
        """The model's entry of ``fastbrdf models --json``: id, kind, params (with ranges and
        defaults), formula, source, ops (cost), bounds, f32_bound, note.

        >>> fastbrdf.Model("flog").info["kind"]
        'lobe'
        """
        if self._info is None:
            self._info = json.loads(_native.info_json(self.id))
        return dict(self._info)

    @overload
    def eval(self, *inputs: F32, precision: None = None, out: Optional[F32] = None) -> F32: ...  # type: ignore[overload-overlap]
    @overload
    def eval(self, *inputs: npt.ArrayLike, precision: Literal["f32"], out: Optional[F32] = None) -> F32: ...
    @overload
    def eval(self, *inputs: npt.ArrayLike, precision: Literal["f64"], out: Optional[F64] = None) -> F64: ...
    @overload
    def eval(self, *inputs: F64, precision: None = None, out: Optional[F64] = None) -> F64: ...
    @overload
    def eval(self, *inputs: float, precision: None = None, out: None = None) -> np.float64: ...
    @overload
    def eval(self, *inputs: npt.ArrayLike, precision: Optional[str] = None, out: Optional[npt.NDArray[Any]] = None) -> Any: ...

    def eval(self, *inputs: Any, precision: Optional[str] = None, out: Optional[npt.NDArray[Any]] = None) -> Any:
        """Evaluates the model: ``eval(cos)`` for lobes (likewise ``cos_h`` for
        distributions, ``cos_vh`` for Fresnel terms; ``eval(cos_v, alpha)`` for env terms;
        shadowing terms take their inputs in the order of ``inputs``) and ``eval(wi, wo)``
        with arrays of shape (..., 3) for BRDFs (local frame, normal +z, both pointing away
        from the surface, of any length; the value has no cosine factor).

        Returns an array of the broadcast shape of the inputs and of the per-element
        parameters (a numpy scalar for scalar inputs), with a last axis of 3 (R, G, B) for a
        coloured model (``channels == 3``). The dtype rule: ``precision=None`` (the default)
        keeps the inputs' float dtype (float32 inputs evaluate in float32 through the SIMD
        kernels; float64, integer and Python numbers in float64 through the scalar f64
        model); ``"f32"`` or ``"f64"`` chooses, converting the inputs. ``out``: an array of
        the result's shape and dtype, C-contiguous and writeable, written and returned (it
        may be an input: the result then goes through a temporary). The GIL is released while
        it runs.

        >>> m = fastbrdf.Model("pow", n=2)
        >>> m.eval(np.array([1.0, 0.5], dtype=np.float32))
        array([1.  , 0.25], dtype=float32)
        >>> m.eval([1.0, 0.5])
        array([1.  , 0.25])
        >>> buf = np.empty(2, dtype=np.float32)
        >>> m.eval([1.0, 0.5], precision="f32", out=buf) is buf
        True
        """
        h = self._handle
        if self.kind == "brdf":
            if len(inputs) != 2:
                raise TypeError(
                    f"model '{self.id}' is a brdf: eval(wi, wo) takes two arrays of shape (..., 3), "
                    f"got {len(inputs)} argument(s)"
                )
            names = ["wi", "wo"]
            given = [_vectors(inputs[0], "wi", 3), _vectors(inputs[1], "wo", 3)]
            lead = [a.shape[:-1] for a in given]
        else:
            req, opt = self.inputs
            if not len(req) <= len(inputs) <= len(req) + len(opt):
                want = ", ".join(req) + ("" if not opt else f" (optionally {', '.join(opt)})")
                raise TypeError(
                    f"model '{self.id}' is a {self.kind}: eval takes {want}, got {len(inputs)} argument(s)"
                )
            names = (req + opt)[: len(inputs)]
            given = [_array(x, n) for x, n in zip(inputs, names)]
            lead = [a.shape for a in given]
        pnames = list(self._arrays)
        parrs = [self._arrays[k] for k in pnames]
        shape = _broadcast(names + pnames, lead + [a.shape for a in parrs])
        precision = _precision(precision, given)
        dtype = _dtype(precision)
        channels = len(self._handles)
        full = shape + ((channels,) if channels > 1 else ())
        result, target = _output(out, full, dtype, given + parrs)
        n = int(np.prod(shape, dtype=np.int64))
        if self.kind == "brdf":
            wi, wo = (_rows(a, shape + (3,), dtype) for a in given)
        else:
            cols = [_prepare(a, shape, dtype).reshape(-1) for a in given]
        # Parameter values stay float64 whatever the precision: each element's model is built
        # from the exact value, as ``Model(id, name=value)`` builds it.
        params = self._flat_params(shape)
        flat = target.reshape(-1) if channels == 1 else np.empty(n, dtype=dtype)
        for c, hc in enumerate(self._handles):
            if params:
                from . import _perelement

                if self.kind == "brdf":
                    _perelement.eval_dirs(hc, params, wi, wo, precision, flat)
                else:
                    _perelement.eval_cols(hc, params, cols, precision, flat)
            elif self.kind == "brdf":
                (hc.eval_dirs_f32 if precision == "f32" else hc.eval_dirs_f64)(wi, wo, flat)
            else:
                (hc.eval_f32 if precision == "f32" else hc.eval_f64)(cols, flat)
            if channels > 1:
                target.reshape(-1, channels)[:, c] = flat
        if target is not result:
            result[...] = target
        if out is not None:
            return out
        return _result(result, full)

    def strategies(self) -> List[str]:
        """The sampling strategies of a BRDF, its default (``auto``) first.

        >>> fastbrdf.Model("lambert").strategies()
        ['cosine']
        """
        return list(self._handle.strategies())

    def sample(
        self, wo: Any, u: Any, strategy: str = "auto", precision: Optional[str] = None,
        out: Optional[Tuple[np.ndarray, np.ndarray, np.ndarray]] = None,
    ) -> Tuple[np.ndarray, Any, Any]:
        """Draws ``wi`` given ``wo`` (..., 3) and ``u`` (..., 2) in [0, 1)^2, as
        ``fastbrdf sample`` (``u`` outside [0, 1) or NaN is a ``ValueError``): returns
        ``(wi (..., 3), weight (...), pdf (...))`` with
        ``weight = f(wi, wo) cos(theta_i) / pdf``. A draw that yields no sample (below the
        horizon, density 0: the strategy's missing mass, or ``wo`` out of the domain) gives
        ``wi = (0, 0, 0)``, weight 0 and pdf 0. BRDFs only. The dtype rule of :meth:`eval`
        (``u`` does not count: float32 ``wo`` samples in float32). A coloured model samples
        its first (R) channel's strategy; its weight has a last axis of 3. ``out``: a tuple
        of three arrays ``(wi, weight, pdf)`` of the results' shapes and dtype, C-contiguous
        and writeable, written and returned (as :meth:`eval`'s ``out``). The GIL is released
        while it runs, and large batches run on every core.

        >>> wi, w, p = fastbrdf.Model("lambert").sample([0, 0, 1], [0.3, 0.7])
        >>> float(w)
        1.0
        >>> bufs = (np.empty((2, 3)), np.empty(2), np.empty(2))
        >>> fastbrdf.Model("lambert").sample([0, 0, 1], [[0.3, 0.7], [0.1, 0.2]], out=bufs) is bufs
        True
        """
        wo_a, u_given = _vectors(wo, "wo", 3), _vectors(u, "u", 2)
        precision = _precision(precision, [wo_a])
        dtype = _dtype(precision)
        pnames = list(self._arrays)
        parrs = [self._arrays[k] for k in pnames]
        shape = _broadcast(["wo", "u"] + pnames, [wo_a.shape[:-1], u_given.shape[:-1]] + [a.shape for a in parrs])
        if not (out is None and u_given.dtype == dtype and not pnames and u_given.shape == shape + (2,)):
            # Else the native call checks these very values, rows numbered alike, in its
            # threaded pass (numpy's min and max here were two more passes over u), and its
            # fresh outputs are dropped with the error (a caller's `out` is left untouched:
            # checked here, before any chunk writes).
            _check_unit_interval(u_given, "u")
        channels = len(self._handles)
        wshape = shape + ((channels,) if channels > 1 else ())
        results, targets = _outputs(out, [shape + (3,), wshape, shape], dtype, [wo_a, u_given] + parrs)
        params = self._flat_params(shape)
        u_c = u_given.astype(dtype) if u_given.dtype != dtype else u_given
        if u_c is not u_given and dtype is np.float32:
            # A fresh copy: keep float64 values just below 1 below 1 in float32.
            np.minimum(u_c, _BELOW_ONE_F32, out=u_c)
        wo_f, u_f = _rows(wo_a, shape + (3,), dtype), _rows(u_c, shape + (2,), dtype)
        h = self._handle
        wi_t, w_t, p_t = targets
        n = int(np.prod(shape, dtype=np.int64))
        wi = wi_t.reshape(-1, 3)
        w0 = w_t.reshape(-1) if channels == 1 else np.empty(n, dtype=dtype)
        if params:
            from . import _perelement

            got = _perelement.sample(h, params, np.ascontiguousarray(wo_f), np.ascontiguousarray(u_f), strategy, precision)
            wi[...], w0[...], p_t.reshape(-1)[...] = got[0].reshape(-1, 3), got[1], got[2]
        else:
            f = h.sample_f32 if precision == "f32" else h.sample_f64
            f(wo_f, u_f, strategy, (wi.reshape(-1), w0, p_t.reshape(-1)))
        if channels > 1:
            # The other channels' weights f_c cos / pdf at the first channel's draws.
            pdf = p_t.reshape(-1)
            cos, ok = wi[:, 2], pdf > 0
            ws = w_t.reshape(-1, channels)
            ws[:, 0] = w0
            fc = np.empty(n, dtype=dtype)
            for c, hc in enumerate(self._handles[1:], 1):
                if params:
                    _perelement.eval_dirs(hc, params, wi, np.ascontiguousarray(wo_f), precision, fc)
                else:
                    (hc.eval_dirs_f32 if precision == "f32" else hc.eval_dirs_f64)(wi, wo_f, fc)
                ws[:, c] = np.where(ok, fc * cos / np.where(ok, pdf, 1), 0)
        for res, t in zip(results, targets):
            if res is not t:
                res[...] = t
        if out is not None:
            return out
        wi_r, w_r, p_r = results
        return wi_r, _result(w_r, wshape), _result(p_r, shape)

    def pdf(
        self, wo: Any, wi: Any, strategy: str = "auto", precision: Optional[str] = None,
        out: Optional[npt.NDArray[Any]] = None,
    ) -> Any:
        """The solid-angle density with which :meth:`sample` draws ``wi`` given ``wo``
        (both (..., 3)), as ``fastbrdf sample --pdf``. BRDFs only; the dtype rule and ``out``
        of :meth:`eval`.

        >>> round(float(fastbrdf.Model("lambert").pdf([0, 0, 1], [0, 0, 1])), 6)
        0.31831
        """
        wo_a, wi_a = _vectors(wo, "wo", 3), _vectors(wi, "wi", 3)
        precision = _precision(precision, [wo_a, wi_a])
        dtype = _dtype(precision)
        pnames = list(self._arrays)
        parrs = [self._arrays[k] for k in pnames]
        shape = _broadcast(["wo", "wi"] + pnames, [wo_a.shape[:-1], wi_a.shape[:-1]] + [a.shape for a in parrs])
        result, target = _output(out, shape, dtype, [wo_a, wi_a] + parrs)
        params = self._flat_params(shape)
        wo_f, wi_f = _rows(wo_a, shape + (3,), dtype), _rows(wi_a, shape + (3,), dtype)
        h = self._handle
        flat = target.reshape(-1)
        if params:
            from . import _perelement

            flat[...] = _perelement.pdf(
                h, params, np.ascontiguousarray(wo_f), np.ascontiguousarray(wi_f), strategy, precision
            )
        else:
            (h.pdf_f32 if precision == "f32" else h.pdf_f64)(wo_f, wi_f, strategy, flat)
        if target is not result:
            result[...] = target
        if out is not None:
            return out
        return _result(result, shape)

    def _flat_params(self, shape: Tuple[int, ...]) -> Dict[str, np.ndarray]:
        """The per-element parameters broadcast to ``shape``, flat and float64 (each element's
        model is built from the exact value)."""
        return {k: _prepare(a, shape, np.float64).reshape(-1) for k, a in self._arrays.items()}

    @property
    def material(self) -> Optional[str]:
        """The MERL material whose published fit supplied parameters, if one was given.

        >>> fastbrdf.Model("pow", material="gold-metallic-paint").material
        'gold-metallic-paint'
        """
        return self._material

    @property
    def metal(self) -> Optional[str]:
        """The named metal that colours the model, if one was given.

        >>> fastbrdf.Model("cook-torrance", metal="gold").metal
        'gold'
        """
        return self._metal

    @property
    def channels(self) -> int:
        """1 for a grey model, 3 (R, G, B) for a coloured one (``R,G,B`` values, a metal).

        >>> fastbrdf.Model("cook-torrance", alpha=0.2, metal="gold").channels
        3
        """
        return len(self._handles)

    @property
    def spec(self) -> str:
        """The model as ``fastbrdf`` names it: ``id k=v ...`` with the values given (and a
        material's and a metal's), one string per channel joined by ``; `` when coloured.

        >>> fastbrdf.Model("ggx", alpha=0.3).spec
        'ggx alpha=0.3'
        """
        return "; ".join(str(h.spec) for h in self._handles)


def _precision(precision: Optional[str], arrays: List[np.ndarray]) -> str:
    """The dtype rule: ``precision`` when given, else ``f32`` when the inputs' promoted dtype
    is float32 (or float16), ``f64`` otherwise (float64, integers, Python numbers)."""
    if precision is not None:
        _dtype(precision)
        return precision
    dt = np.result_type(*[a.dtype for a in arrays], np.float16)
    return "f32" if dt.itemsize <= 4 else "f64"


def _output(
    out: Optional[np.ndarray], shape: Tuple[int, ...], dtype: Any, inputs: List[np.ndarray], name: str = "out"
) -> Tuple[np.ndarray, np.ndarray]:
    """``(result, target)``: the array returned and the one written (a temporary when ``out``
    shares memory with an input). ``out`` is checked: an ndarray (else ``TypeError``) of the
    result's dtype (``TypeError``) and shape, C-contiguous and writeable (``ValueError``)."""
    if out is None:
        r = np.empty(shape, dtype=dtype)
        return r, r
    if not isinstance(out, np.ndarray):
        raise TypeError(f"{name}: expected a numpy array, got {type(out).__name__}")
    if out.dtype != np.dtype(dtype):
        raise TypeError(f"{name}: dtype {out.dtype}, the result is {np.dtype(dtype)}")
    if out.shape != shape:
        raise ValueError(f"{name}: shape {out.shape}, the result has shape {shape}")
    if not out.flags.c_contiguous:
        raise ValueError(f"{name}: must be C-contiguous")
    if not out.flags.writeable:
        raise ValueError(f"{name}: is read-only")
    if any(np.may_share_memory(out, a) for a in inputs):
        return out, np.empty(shape, dtype=dtype)
    return out, out


def _outputs(
    out: Any, shapes: List[Tuple[int, ...]], dtype: Any, inputs: List[np.ndarray]
) -> Tuple[List[np.ndarray], List[np.ndarray]]:
    """:func:`_output` for a tuple of outputs (``out[0]``, ``out[1]``, ...), none sharing
    memory with an input or with another."""
    if out is None:
        fresh = [np.empty(s, dtype=dtype) for s in shapes]
        return fresh, fresh
    if not isinstance(out, (tuple, list)) or len(out) != len(shapes):
        raise TypeError(f"out: expected a tuple of {len(shapes)} numpy arrays, got {type(out).__name__}")
    results: List[np.ndarray] = []
    targets: List[np.ndarray] = []
    for i, (o, s) in enumerate(zip(out, shapes)):
        r, t = _output(o, s, dtype, inputs + results, f"out[{i}]")
        results.append(r)
        targets.append(t)
    return results, targets


def _rows(a: np.ndarray, shape: Tuple[int, ...], dtype: Any) -> np.ndarray:
    """``a`` broadcast to ``shape`` (..., k) as (N, k) rows of ``dtype`` for the native side,
    which reads any strides: a view of ``a`` (C-contiguous, transposed, a broadcast row)
    where one exists, no copy; else one copy (another dtype, or a broadcast the flat view
    cannot express)."""
    if a.dtype != dtype:
        a = a.astype(dtype)
    if a.shape != shape:
        a = np.broadcast_to(a, shape)
    return a.reshape(-1, shape[-1])


def _rebuild(id: str, params: Dict[str, Any], material: Optional[str] = None, metal: Optional[str] = None) -> Model:
    """Unpickles a :class:`Model` (see ``Model.__reduce__``)."""
    return Model(id, material=material, metal=metal, **params)


def _frozen(a: np.ndarray) -> np.ndarray:
    """A read-only copy of ``a``."""
    c = np.array(a, copy=True)
    c.flags.writeable = False
    return c


def _repr_value(v: Any) -> str:
    """A parameter value as Python source that rebuilds it (arrays as ``np.array(...)``)."""
    if isinstance(v, np.ndarray):
        return f"np.array({v.tolist()!r}, dtype=np.{v.dtype.name})"
    if isinstance(v, np.generic):
        return repr(v.item())
    return repr(v)

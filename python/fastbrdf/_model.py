"""``Model``: one model by id with its parameters, evaluated, sampled and its density computed
over numpy arrays."""

from __future__ import annotations

import json
from typing import Any, Dict, List, Optional, Tuple

import numpy as np

from . import _fastbrdf as _native
from ._arrays import (
    _BELOW_ONE_F32,
    _array,
    _broadcast,
    _check_unit_interval,
    _dtype,
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

    def __init__(self, id: str, **params: Any) -> None:
        if not isinstance(id, str):
            raise TypeError(f"model id: expected a string, got {type(id).__name__}")
        self._params = dict(params)
        self._handle = _native.Handle(id, _params(id, params))
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
        args = "".join(f", {k}={v!r}" for k, v in self._params.items())
        return f"fastbrdf.Model({self.id!r}{args})"

    def _key(self) -> Tuple[Any, ...]:
        return (self.id, tuple(self._handle.values))

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
        return (_rebuild, (self.id, dict(self._params)))

    @property
    def id(self) -> str:
        """The model id."""
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




def _rebuild(id: str, params: Dict[str, Any]) -> Model:
    """Unpickles a :class:`Model` (see ``Model.__reduce__``)."""
    return Model(id, **params)

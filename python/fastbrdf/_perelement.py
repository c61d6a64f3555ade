"""Per-element parameters: a numeric parameter given as a numpy array (a roughness map),
evaluated by :meth:`fastbrdf.Model.eval` with one value per element.

How: the native side (``fastbrdf::batch::per_element``) groups the elements by their
parameter values (equal bits, one group; a hash and a counting sort, O(n)), builds the model
of each distinct value set once (its spec, plan and batch kernel: what ``fastbrdf.Model(id,
alpha=v)`` builds) and evaluates each group's gathered inputs with that kernel (f32) or
scalar model (f64), so every element equals the model built for its values, bit for bit, in
both precisions. The cost: the kernels' speed plus O(n) grouping, and one build (a few
microseconds) per distinct value set per million elements; all-distinct continuous values
pay a build per element (``python/examples/perelement_cost.py`` measures it; the figures are
in the book's page ``python-arrays.md``).

Parameter values are checked when the ``Model`` is built: a value the model refuses (out of
its range, NaN) is a ``ValueError`` naming the parameter, the element's index and the value.
"""

from __future__ import annotations

from typing import Any, Dict, List, Tuple

import numpy as np

from . import _fastbrdf as _native

__all__: List[str] = []


def _values(a: np.ndarray) -> np.ndarray:
    """The values as float64, flat and contiguous (float32 and integers convert exactly, but
    integers beyond 2**53)."""
    return np.ascontiguousarray(np.asarray(a).reshape(-1), dtype=np.float64)


def _index(flat: int, shape: Tuple[int, ...]) -> str:
    """Element ``flat`` of an array of ``shape`` as numpy indexes it: ``12`` or ``1, 2``."""
    return ", ".join(str(int(i)) for i in np.unravel_index(flat, shape))


def check(handle: Any, arrays: Dict[str, np.ndarray]) -> None:
    """Checks per-element parameter values against one colour channel's model ``handle``:
    an unknown parameter is the registry's ``ValueError``, a choice parameter a
    ``TypeError``, and the first value the model refuses a ``ValueError`` naming the
    parameter, the element's index and the value.

    >>> fastbrdf.Model("ggx", alpha=np.array([0.1, 7.0]))
    Traceback (most recent call last):
    ValueError: model 'ggx': parameter alpha[1] = 7 is invalid: ...
    >>> fastbrdf.Model("cook-torrance", d=np.array([1.0]))
    Traceback (most recent call last):
    TypeError: model 'cook-torrance': parameter d is a choice: ...
    """
    for name, a in arrays.items():
        found = _native.perelement_check(handle, name, _values(a))
        if found is not None:
            i, msg = found
            msg = msg.replace(f"parameter {name} = ", f"parameter {name}[{_index(i, a.shape)}] = ", 1)
            raise ValueError(msg)


def _params(params: Dict[str, np.ndarray]) -> Tuple[List[str], List[np.ndarray]]:
    names = list(params)
    return names, [_values(params[k]) for k in names]


def eval_cols(
    handle: Any, params: Dict[str, np.ndarray], cols: List[np.ndarray], precision: str, out: np.ndarray
) -> None:
    """Evaluates columns (not BRDFs) with per-element ``params`` (flat, one value per
    element) into ``out`` (flat, of the precision's dtype): each element as the model built
    for its values evaluates it.

    >>> m = fastbrdf.Model("pow", n=np.array([1, 2], dtype=np.float32))
    >>> m.eval(np.array([0.5, 0.5], dtype=np.float32))
    array([0.5 , 0.25], dtype=float32)
    """
    names, values = _params(params)
    f = _native.perelement_eval_f32 if precision == "f32" else _native.perelement_eval_f64
    f(handle, names, values, cols, out)


def eval_dirs(
    handle: Any, params: Dict[str, np.ndarray], wi: np.ndarray, wo: np.ndarray, precision: str, out: np.ndarray
) -> None:
    """Evaluates a BRDF over (N, 3) ``wi``, ``wo`` with per-element ``params`` into ``out``.

    >>> m = fastbrdf.Model("cook-torrance", alpha=np.array([0.1, 0.5]))
    >>> v = m.eval([0.0, 0.0, 1.0], [0.0, 0.0, 1.0])
    >>> bool(v[0] > v[1])
    True
    """
    names, values = _params(params)
    f = _native.perelement_eval_dirs_f32 if precision == "f32" else _native.perelement_eval_dirs_f64
    f(handle, names, values, wi, wo, out)


def sample(
    handle: Any, params: Dict[str, np.ndarray], wo: np.ndarray, u: np.ndarray, strategy: str, precision: str
) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Samples a BRDF with per-element ``params`` (flat, one value per element) given (N, 3)
    ``wo`` and (N, 2) ``u`` in [0, 1) of the precision's dtype: ``(wi (N*3), weight (N), pdf
    (N))``, each element as ``Model.sample`` of the model built for its values (the hook of
    ``Model.sample`` for array parameters).

    >>> h = fastbrdf.Model("cook-torrance")._handle
    >>> wo, u = np.array([[0.0, 0.6, 0.8]] * 2), np.array([[0.3, 0.7]] * 2)
    >>> wi, w, p = fastbrdf._perelement.sample(h, {"alpha": np.array([0.1, 0.5])}, wo, u, "auto", "f64")
    >>> wi.shape, bool(p[0] > p[1])
    ((6,), True)
    """
    names, values = _params(params)
    f = _native.perelement_sample_f32 if precision == "f32" else _native.perelement_sample_f64
    wi, weight, pdf_ = f(handle, names, values, wo, u, strategy)
    return wi, weight, pdf_


def pdf(
    handle: Any, params: Dict[str, np.ndarray], wo: np.ndarray, wi: np.ndarray, strategy: str, precision: str
) -> np.ndarray:
    """The density of ``wi`` given ``wo`` (both (N, 3)) with per-element ``params`` (the hook
    of ``Model.pdf`` for array parameters).

    >>> h = fastbrdf.Model("cook-torrance")._handle
    >>> w = np.array([[0.0, 0.0, 1.0]] * 2)
    >>> p = fastbrdf._perelement.pdf(h, {"alpha": np.array([0.1, 0.5])}, w, w, "auto", "f64")
    >>> bool(p[0] > p[1] > 0)
    True
    """
    names, values = _params(params)
    f = _native.perelement_pdf_f32 if precision == "f32" else _native.perelement_pdf_f64
    out: np.ndarray = f(handle, names, values, wo, wi, strategy)
    return out

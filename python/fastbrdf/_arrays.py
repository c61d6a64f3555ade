"""Argument and array helpers shared by the package's modules (not public API): parameter
text, dtypes, shapes and broadcasting, as the rules of ``fastbrdf``'s docstring say."""

from __future__ import annotations

from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np

from . import _fastbrdf as _native

#: The most values a sequence of parameter values or angles may hold (the CLI's cap on its
#: ranges and lists).
MAX_VALUES: int = int(_native.MAX_VALUES)

_DTYPES = {"f32": np.float32, "f64": np.float64}
#: The largest float32 below 1: where a float64 ``u`` just below 1 rounds to 1 in float32.
_BELOW_ONE_F32 = np.nextafter(np.float32(1), np.float32(0))

Number = Union[int, float, str]

def _str(x: Any, name: str) -> str:
    """``x``, a string (else ``TypeError`` naming ``name``)."""
    if not isinstance(x, str):
        raise TypeError(f"{name}: expected a string, got {type(x).__name__}")
    return x


def _opt_str(x: Any, name: str) -> Optional[str]:
    """``x``, ``None`` or a string (else ``TypeError`` naming ``name``)."""
    return None if x is None else _str(x, name)


def _param_text(model: str, name: str, value: Any) -> str:
    """A parameter value as the text the CLI's ``--param NAME=VALUE`` would carry."""
    if isinstance(value, np.ndarray) and value.ndim == 0:
        value = value.item()
    if isinstance(value, (bool, np.bool_)):
        raise TypeError(f"model '{model}': parameter {name}: expected a number or a string, got bool")
    if isinstance(value, (tuple, list)):
        # (R, G, B): one value per colour channel, as the CLI's ``NAME=R,G,B``.
        if len(value) != 3:
            raise ValueError(
                f"model '{model}': parameter {name}: a sequence is one value per colour channel "
                f"(R, G, B): expected 3 values, got {len(value)} (per-element values: a numpy array)"
            )
        return ",".join(_param_text(model, name, v) for v in value)
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


def _triple(name: str, x: Any, count: int, top: float = 1e3) -> Tuple[float, ...]:
    v = _array(x, name).astype(np.float64).reshape(-1)
    if v.shape != (count,) or not np.all((v >= 0) & (v <= top)):
        raise ValueError(f"{name} {tuple(np.asarray(x).reshape(-1).tolist())}: expected {count} numbers from 0 to {top:g}")
    return tuple(float(a) for a in v)



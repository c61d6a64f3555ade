"""Measured BRDFs in MERL's ``.binary`` format (``Measured``, ``write_merl``) and registry
BRDFs fitted to them (``fit_measured``), as the CLI's ``fastbrdf measured info|eval|render``
and ``fastbrdf fit-measured``.

The format (Matusik et al. 2003, merl.com/brdf): three little-endian int32 dimensions (90, 90,
180: theta_half, theta_diff, phi_diff), then 90 * 90 * 180 little-endian float64 for red, then
green, then blue (34,992,012 bytes); a stored value times its channel's scale (1/1500,
1.15/1500, 1.66/1500) is the BRDF value, a negative one marks a sample that was not measured.
"""

from __future__ import annotations

import json
import os
import warnings
from typing import Any, Callable, Dict, List, Optional, Sequence, Union

import numpy as np

from . import _fastbrdf as _native
from ._arrays import _broadcast, _dtype, _params, _prepare, _result, _vectors
from ._render import _flag, _size

__all__ = ["Measured", "fit_measured", "write_merl"]

#: Bins of theta_half, theta_diff and phi_diff.
_DIMS = (90, 90, 180)
#: The channels' scales (R, G, B): a stored value times its scale is the BRDF value.
_SCALE = np.array([1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0])

PathLike = Union[str, "os.PathLike[str]"]


def _path(path: Any, name: str) -> str:
    if isinstance(path, Measured):
        return path.path
    if not isinstance(path, (str, os.PathLike)):
        raise TypeError(f"{name}: expected a path (str or os.PathLike), got {type(path).__name__}")
    p = os.fspath(path)
    return os.fsdecode(p) if isinstance(p, bytes) else p


def _int(name: str, v: Any) -> int:
    if isinstance(v, bool) or not isinstance(v, (int, np.integer)):
        raise TypeError(f"{name}: expected an int, got {type(v).__name__}")
    if v < 0:
        raise ValueError(f"{name} {v}: must not be negative")
    return int(v)


def write_merl(
    path: PathLike,
    values: Union[Callable[[np.ndarray, np.ndarray, np.ndarray], Any], Sequence[float], np.ndarray],
) -> None:
    """Writes a MERL ``.binary`` file (34,992,012 bytes, atomically: a temporary file renamed)
    tabulating ``values``: either a function ``f(theta_h, theta_d, phi_d)`` of the bins'
    centre angles in radians (arrays of shape (90, 90, 180), the library's
    ``measured::bin_centre``: theta_h ``((i + 0.5) / 90)^2 pi / 2``, theta_d
    ``(j + 0.5) / 90 pi / 2``, phi_d ``(k + 0.5) / 180 pi``) returning R, G, B BRDF values of
    shape (90, 90, 180, 3), or values broadcastable to that shape (one RGB triple for a
    constant BRDF). A negative value is written as a missing sample (-1); each value is
    divided by its channel's scale, as the format stores it. The same bytes as the library's
    ``measured::write_merl`` (used by the CLI's tests).

    >>> import os, tempfile
    >>> tmp = tempfile.TemporaryDirectory()
    >>> path = os.path.join(tmp.name, "grey.binary")
    >>> fastbrdf.write_merl(path, [0.1, 0.1, 0.1])
    >>> os.path.getsize(path)
    34992012
    >>> tmp.cleanup()
    """
    p = _path(path, "path")
    if callable(values):
        i, j, k = (np.arange(n, dtype=np.float64) + 0.5 for n in _DIMS)
        th = (i / _DIMS[0]) ** 2 * (np.pi / 2)
        td = j / _DIMS[1] * (np.pi / 2)
        pd = k / _DIMS[2] * np.pi
        grids = np.meshgrid(th, td, pd, indexing="ij")
        v = np.asarray(values(*grids))
    else:
        v = np.asarray(values)
    if v.dtype.kind not in "fiu":
        raise TypeError(f"values: dtype {v.dtype} is not supported: expected real numbers")
    try:
        v = np.broadcast_to(v.astype(np.float64, copy=False), _DIMS + (3,))
    except ValueError:
        raise ValueError(f"values: shape {v.shape} does not broadcast to (90, 90, 180, 3)") from None
    if not np.all(np.isfinite(v)):
        raise ValueError("values: not every value is a finite number")
    stored = np.where(v < 0, -1.0, v / _SCALE)
    # Channel-major: all of red (theta_h, theta_d, phi_d in C order), then green, then blue.
    body = np.ascontiguousarray(np.moveaxis(stored, -1, 0), dtype="<f8")
    tmp = f"{p}.tmp{os.getpid()}"
    try:
        with open(tmp, "wb") as f:
            f.write(np.array(_DIMS, dtype="<i4").tobytes())
            f.write(body.tobytes())
        os.replace(tmp, p)
    except OSError as e:
        # Name the path given, not the temporary file beside it.
        raise type(e)(e.errno, f"cannot write {p}: {e.strerror}") from e
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)


_TINY: List[str] = []


def _tiny() -> str:
    """A MERL file for the examples: Lambert with albedo (0.5, 0.4, 0.3), written once per
    process into a temporary folder that is removed at exit."""
    if not _TINY:
        import atexit
        import shutil
        import tempfile

        folder = tempfile.mkdtemp(prefix="fastbrdf-merl-")
        atexit.register(shutil.rmtree, folder, True)
        path = os.path.join(folder, "lambert.binary")
        write_merl(path, np.array([0.5, 0.4, 0.3]) / np.pi)
        _TINY.append(path)
    return _TINY[0]


class Measured:
    """A measured BRDF: a MERL ``.binary`` file, read once (at most the format's 34,992,012
    bytes plus one are read; the header is checked before anything else). A missing, short,
    long or malformed file (a wrong header, a NaN, infinite or implausibly large sample) is a
    ``ValueError`` naming the file. Pickles by value: unpickling reads the path again.

    >>> path = fastbrdf._measured._tiny()
    >>> m = fastbrdf.Measured(path)
    >>> m.info()["channels"][0]["mean"]
    0.159...
    """

    def __init__(self, path: PathLike) -> None:
        self._path = _path(path, "path")
        self._data = _native.MeasuredData(self._path)

    @property
    def path(self) -> str:
        """The file's path, as given (a ``pathlib.Path`` as its text).

        >>> import pathlib
        >>> path = fastbrdf._measured._tiny()
        >>> fastbrdf.Measured(pathlib.Path(path)).path == path
        True
        """
        return self._path

    def __repr__(self) -> str:
        """``fastbrdf.Measured('PATH')``: evaluating it reads the file again.

        >>> m = fastbrdf.Measured(fastbrdf._measured._tiny())
        >>> repr(m).startswith("fastbrdf.Measured('")
        True
        """
        return f"fastbrdf.Measured({self._path!r})"

    def __reduce__(self) -> Any:
        """Pickles the path (not the 35 MB of samples): unpickling reads the file again, so
        it must be readable where it is unpickled.

        >>> import pickle
        >>> m = fastbrdf.Measured(fastbrdf._measured._tiny())
        >>> pickle.loads(pickle.dumps(m)).path == m.path
        True
        """
        return (Measured, (self._path,))

    def info(self) -> Dict[str, Any]:
        """``fastbrdf measured info FILE --json``: the file, the dimensions, the samples per
        channel, the channels' scales, and per channel (red, green, blue) the min, max and
        mean of the valid samples (``None`` when it has none), the valid and missing counts.

        >>> m = fastbrdf.Measured(fastbrdf._measured._tiny())
        >>> info = m.info()
        >>> info["dims"], info["channels"][2]["missing"]
        ([90, 90, 180], 0)
        """
        out: Dict[str, Any] = json.loads(self._data.info_json())
        return out

    def eval(self, wi: Any, wo: Any, precision: str = "f32") -> Any:
        """The R, G, B values for directions ``wi``, ``wo`` of shape (..., 3) (local frame,
        normal +z, both pointing away from the surface, any length), broadcast against each
        other: an array of shape (..., 3), as ``fastbrdf measured eval`` (the reference
        code's nearest-bin lookup, the bin always found in f64). Below the horizon, a zero or
        non-finite vector, or a missing sample: 0. ``precision`` ``"f32"`` (default) returns
        float32, ``"f64"`` float64 (the package's array rules). The GIL is released.

        >>> m = fastbrdf.Measured(fastbrdf._measured._tiny())
        >>> m.eval([0, 0, 1], [0.5, 0, 0.866], precision="f64") * np.pi
        array([0.5, 0.4, 0.3])
        """
        dtype = _dtype(precision)
        wi_a, wo_a = _vectors(wi, "wi", 3), _vectors(wo, "wo", 3)
        shape = _broadcast(["wi", "wo"], [wi_a.shape[:-1], wo_a.shape[:-1]])
        wi_a, wo_a = _prepare(wi_a, shape + (3,), dtype), _prepare(wo_a, shape + (3,), dtype)
        f = self._data.eval_f32 if precision == "f32" else self._data.eval_f64
        return _result(f(wi_a.reshape(-1, 3), wo_a.reshape(-1, 3)), shape + (3,))

    def render(
        self,
        *,
        size: Union[str, Sequence[int], None] = None,
        width: Optional[int] = None,
        height: Optional[int] = None,
        spp: int = 2,
        lights: Sequence[str] = (),
        floor: bool = False,
        shadows: Union[bool, str] = True,
        env: Optional[str] = None,
        env_samples: int = 16,
        mesh: Optional[PathLike] = None,
    ) -> np.ndarray:
        """Renders the measured material on the built-in sphere (or ``mesh``: ``"face"``, the
        built-in face, or an OBJ file) on the CPU, as ``fastbrdf measured render --out
        FILE.exr``: the linear radiance film, float32 of shape (height, width, 3), top row
        first (no exposure, no sRGB). ``size`` is ``"WxH"`` or (W, H) (or give ``width`` and
        ``height``; 256 each by default); ``floor`` a bool, ``shadows`` a bool or the CLI's
        ``"on"``/``"off"``. ``lights`` are the CLI's ``--light`` specs
        (``dir:X,Y,Z[:R,G,B[:I]]``, ``point:...``), ``env`` ``sky``, ``white`` or a map
        file; ``env_samples`` as ``--env-samples`` (only the map is sampled: the data has no
        importance sampling, so it needs more than a model). The file is the whole BRDF: no
        diffuse weight or albedo applies. Deterministic; Ctrl-C stops it.

        >>> m = fastbrdf.Measured(fastbrdf._measured._tiny())
        >>> img = m.render(width=32, height=24, spp=1)
        >>> img.shape, img.dtype
        ((24, 32, 3), dtype('float32'))
        """
        w, h = _size(size, width, height)
        sizes = {"width": w, "height": h}
        sizes.update({n: _int(n, v) for n, v in (("spp", spp), ("env_samples", env_samples))})
        if isinstance(lights, str):
            lights = [lights]
        if env is not None and not isinstance(env, str):
            raise TypeError(f"env: expected a string, got {type(env).__name__}")
        mesh_path = None if mesh is None else _path(mesh, "mesh")
        flat = self._data.render(
            sizes["width"],
            sizes["height"],
            sizes["spp"],
            list(lights),
            _flag("floor", floor),
            _flag("shadows", shadows, on_off=True),
            env,
            sizes["env_samples"],
            mesh_path,
        )
        return flat.reshape(sizes["height"], sizes["width"], 3)


def fit_measured(
    data: Union[Measured, PathLike],
    model: str,
    *,
    free: Sequence[str] = (),
    metric: str = "ngan-l2",
    samples: int = 8000,
    restarts: int = 6,
    **params: Any,
) -> Dict[str, Any]:
    """Fits registry BRDF ``model`` (with per-channel diffuse and specular albedos) to the
    measured ``data`` (a ``Measured`` or a MERL file's path), as ``fastbrdf fit-measured
    --json``: the same keys and numbers (the fit is deterministic), with ``"picture"``
    ``None`` (no comparison picture is rendered; ``Measured.render`` draws the data) and
    ``"fit_seconds"`` this call's. ``params`` fix choices and values (the CLI's ``--param``,
    ``f="schlick"``); ``free`` names held parameters to fit (``--free f90``); ``metric`` is
    ``ngan-l2``, ``low-log`` or ``max``; ``samples`` the bins sampled with a fixed seed (0:
    every eligible bin); ``restarts`` the Nelder-Mead starts (1 to 64). The fitted model is
    ``rho_d[c] / pi + rho_s[c] * model(params)`` per channel c. Parameters the data do not
    determine are listed in ``"undetermined"`` and named in a ``UserWarning``, as the CLI
    warns. Runs on a worker thread; Ctrl-C stops it after the Nelder-Mead run in progress.

    >>> import os, tempfile
    >>> tmp = tempfile.TemporaryDirectory()
    >>> path = os.path.join(tmp.name, "shiny.binary")
    >>> fastbrdf.write_merl(path, lambda th, td, pd: np.stack(
    ...     [0.2 / np.pi + 0.5 * np.cos(th) ** 40] * 3, axis=-1))
    >>> r = fastbrdf.fit_measured(path, "blinn-phong", norm="none", samples=500, restarts=1)
    >>> round(r["params"]["n"], 3), [round(x, 4) for x in r["rho_d"]]
    (40.0, [0.2, 0.2, 0.2])
    >>> tmp.cleanup()
    """
    if not isinstance(model, str):
        raise TypeError(f"model: expected a string, got {type(model).__name__}")
    if not isinstance(metric, str):
        raise TypeError(f"metric: expected a string, got {type(metric).__name__}")
    if isinstance(free, str):
        free = [free]
    n_samples, n_restarts = _int("samples", samples), _int("restarts", restarts)
    measured = data if isinstance(data, Measured) else Measured(_path(data, "data"))
    doc = _native.fit_measured_json(
        measured._data, model, _params(model, params), list(free), metric, n_samples, n_restarts
    )
    out: Dict[str, Any] = json.loads(doc)
    und: List[str] = out["undetermined"]
    if und:
        names = und[0] if len(und) == 1 else f"{', '.join(und[:-1])} and {und[-1]}"
        warnings.warn(
            f"the data do not determine {names} separately: the fit moves along a flat "
            "direction of the model (only a combination of them is measured); fix one with "
            "a parameter NAME=VALUE",
            stacklevel=2,
        )
    return out

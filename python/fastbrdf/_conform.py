"""The conformance checks a renderer's BSDF must pass (``conform``), on a registry model or on
a BSDF written in Python, as the CLI's ``fastbrdf conform``."""

from __future__ import annotations

import json
from typing import Any, Dict, Optional

from . import _fastbrdf as _native
from ._arrays import _opt_str, _params, _str
from ._model import Model

__all__ = ["conform"]


def _source(x: Any, name: str, params: Dict[str, Any], material: Optional[str] = None, metal: Optional[str] = None) -> Any:
    """``x`` as the native function takes it: a registry model as a tuple, an object as itself."""
    if isinstance(x, str):
        return (x, _params(x, params), _opt_str(material, "material"), _opt_str(metal, "metal"))
    given = list(params) + [k for k, v in (("material", material), ("metal", metal)) if v is not None]
    if given:
        raise TypeError(f"{name}: parameters ({', '.join(given)}) apply to a registry id, not to a {type(x).__name__}")
    if isinstance(x, Model):
        arrays = [k for k, v in x.params.items() if getattr(v, "ndim", 0) > 0]
        if arrays:
            raise ValueError(f"{name}: per-element values ({', '.join(arrays)}) cannot be checked: give one value per parameter")
        return (x.id, _params(x.id, x.params), x.material, x.metal)
    if isinstance(x, tuple):
        # The native function would read a tuple as a registry model.
        raise TypeError(f"{name}: expected a registry id, a fastbrdf.Model or an object with eval(wi, wo), got tuple")
    return x


def conform(
    model: Any,
    *,
    reference: Any = None,
    full: bool = False,
    strategy: str = "auto",
    material: Optional[str] = None,
    metal: Optional[str] = None,
    **params: Any,
) -> Dict[str, Any]:
    """Checks a BSDF as a renderer needs it (``fastbrdf conform --json``): ``f`` finite and
    non-negative, finite for non-finite input, reciprocal, energy-conserving, and, when it
    samples, its sampler against its pdf (``chi2``), ``weight == f cos / pdf``, the pdf's
    integral, the pdf non-zero wherever ``f`` is, and ``pdf(wo, wi)`` equal to the pdf the
    sampler reports. Returns ``{model, mode, passed, checks: [{check, status, value, limit,
    summary, at}]}`` (status ``pass``, ``fail`` or ``skip``); a failed check is ``passed:
    False`` (nothing is raised).

    ``model`` (and ``reference``, compared against it: the ``reference`` check) is a registry
    id (with its parameters as keywords, and ``material`` and ``metal`` as for :class:`Model`;
    a ``reference`` id takes its defaults: give a :class:`Model` for others), a user's shader
    ``"file:PATH"`` (a BRDF Explorer ``.brdf`` file or a ``.wgsl``/``.glsl`` function, compiled
    on the GPU with its parameters as keywords, as the CLI's ``--model file:PATH``), a
    :class:`Model`, or any object with
    ``eval(wi, wo)`` and, optionally, ``sample(wo, u)`` and ``pdf(wo, wi)`` on numpy arrays, in
    fastbrdf's conventions (local frame, normal +z, both directions pointing away from the
    surface, ``f`` without the cosine):

    - ``eval(wi, wo)``: ``wi``, ``wo`` float64 (N, 3) -> ``f``, (N,) or (N, 3) (R, G, B);
    - ``sample(wo, u)``: ``u`` float64 (N, 2) in [0, 1) -> ``(wi (N, 3), weight (N,) or
      (N, 3), pdf (N,))`` with ``weight = f cos theta_i / pdf`` and ``pdf == 0`` where it
      draws nothing;
    - ``pdf(wo, wi)`` -> (N,), the solid-angle density of ``sample``'s ``wi``.

    Inputs are passed as the checks make them (not normalised; NaN and infinite components
    included: a BSDF must return finite values for them). Calls come in batches of thousands
    of rows, from several threads, each holding the GIL (calls overlap only where a method's
    code releases it, as numpy's does). What a method returns is checked: a wrong dtype or
    shape is a ``TypeError``/``ValueError`` naming the method (``eval returned shape (10,) for
    12 rows; ...``), and an exception it raises propagates with a note naming the call.
    ``strategy`` samples a registry model (``auto``, ``cosine``, ``lobe``, ``d-cos``,
    ``vndf``, ``twin``). ``full``: more pairs, angles and samples (minutes), else CI's sizes
    (seconds for a registry model). Ctrl-C stops it.

    >>> fastbrdf.conform("lambert")["passed"]
    True
    >>> import numpy as np
    >>> class Lambert:
    ...     def eval(self, wi, wo):
    ...         return np.where((wi[:, 2] > 0) & (wo[:, 2] > 0), 1.2 / np.pi, 0.0)
    >>> r = fastbrdf.conform(Lambert())
    >>> [c["check"] for c in r["checks"] if c["status"] == "fail"]
    ['energy']
    """
    _str(strategy, "strategy")
    return dict(
        json.loads(
            _native.conform_json(
                _source(model, "model", params, material, metal),
                None if reference is None else _source(reference, "reference", {}),
                bool(full),
                strategy,
            )
        )
    )

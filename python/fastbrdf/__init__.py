"""fastbrdf: fast BRDF and lobe approximations, from Python.

The same vocabulary as the ``fastbrdf`` command line: model ids and parameters as in
``fastbrdf models``, the same validation and the same error messages (raised as
``ValueError``), computed by the same Rust library.

>>> import numpy as np, fastbrdf
>>> m = fastbrdf.Model("flog", n=20)
>>> m.eval(np.array([1.0, 0.95], dtype=np.float32))      # float32 in: SIMD kernel
array([1.        , 0.3448...], dtype=float32)
>>> m.eval([1.0, 0.95])                                   # float64 in: the f64 model
array([1.        , 0.3448...])
>>> ct = fastbrdf.Model("cook-torrance", alpha=0.2, f="schlick")
>>> float(ct.eval([0.0, 0.0, 1.0], [0.3, 0.0, 0.95]))
0.0482...
>>> gold = fastbrdf.Model("cook-torrance", alpha=0.2, metal="gold")   # R, G, B channels
>>> gold.eval([0.0, 0.0, 1.0], [0.3, 0.0, 0.95]).shape
(3,)
>>> import pickle; pickle.loads(pickle.dumps(gold)) == gold           # ships to workers
True

Array rules (every function taking arrays):

- dtypes: float32 and float64 arrays (and anything ``numpy.asarray`` turns into a real or
  integer array: lists, scalars, integer arrays) are accepted; bool, complex, object and
  string arrays are a ``TypeError`` naming the dtype.
- the dtype rule: with ``precision=None`` (the default) a call keeps its inputs' float dtype
  (numpy's promotion of the inputs; per-element parameter arrays do not count: their values
  are always used exactly, as float64): float32 (or float16)
  evaluates in float32 through the SIMD batch kernels and returns float32; float64, integers
  and Python numbers evaluate the scalar f64 model and return float64. ``precision="f32"`` or
  ``"f64"`` chooses instead; input of another dtype is then converted (one copy).
- ``out=``: ``Model.eval`` writes into a given array of the result's shape and dtype
  (C-contiguous, writeable; it may be an input) and returns it, so a loop over large batches
  allocates nothing.
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
``RuntimeError``). Outside the arguments: an output file that cannot be written (``out=``,
``write_merl``) is an ``OSError`` naming the path, and ``render(gpu=True)`` without a GPU
adapter a ``RuntimeError``.
"""

from __future__ import annotations

from typing import List

from . import _analysis, _conform, _measured, _model, _perelement, _render, _tools
from . import _fastbrdf as _native
from ._analysis import *  # noqa: F401,F403
from ._arrays import MAX_VALUES
from ._conform import *  # noqa: F401,F403
from ._measured import *  # noqa: F401,F403
from ._model import *  # noqa: F401,F403
from ._render import *  # noqa: F401,F403
from ._tools import *  # noqa: F401,F403

#: The package's version: the Rust workspace's (the wheel's version).
__version__: str = str(_native.__version__)

#: How the native module was built: ``"release"`` (``pip install``, ``maturin build --release``:
#: what timings need) or ``"dev"`` (Cargo's dev profile, debug assertions on: the test suite's
#: wheel, several times slower).
BUILD: str = str(_native.BUILD)

#: The modules whose public names make up the package (each lists them in ``__all__``).
_MODULES = (_analysis, _conform, _measured, _model, _perelement, _render, _tools)

__all__: List[str] = sorted(
    ["BUILD", "MAX_VALUES", "__version__"] + [name for m in _MODULES for name in m.__all__]
)

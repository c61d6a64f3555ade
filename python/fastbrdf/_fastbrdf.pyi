"""Type stubs of the native module (python/src/). Use the package's public API
(``fastbrdf.Model`` and the functions in ``fastbrdf/__init__.py``): these take arrays of the
exact dtype, not broadcast (they copy non-contiguous or unaligned ones, and check lengths,
counts and values themselves)."""

from typing import Any, Dict, List, Optional, Sequence, Tuple

import numpy as np
import numpy.typing as npt

F32 = npt.NDArray[np.float32]
F64 = npt.NDArray[np.float64]

__version__: str
BUILD: str
MAX_VALUES: int
MAX_ITEMS: int
MAX_WEIGHT: float

def models_json() -> str: ...
def info_json(id: str) -> str: ...
def errors_json(model: str, reference: str, param: str, values: Sequence[float], zone: str) -> str: ...
def parse_range(text: str, default_step: float) -> List[float]: ...
def albedo_json(
    model: str,
    params: Sequence[Tuple[str, str]],
    angles: Sequence[float],
    as_brdf: str,
    norm: str,
    material: Optional[str] = None,
) -> str: ...
def render(
    model: str,
    params: Sequence[Tuple[str, str]],
    material: Optional[str],
    metal: Optional[str],
    scene: Dict[str, Any],
    gpu: bool = ...,
) -> F32: ...
def compare_json(
    models: Sequence[str],
    reference: Optional[str],
    measured: Optional[str],
    params: Sequence[Tuple[str, str]],
    material: Optional[str],
    metal: Optional[str],
    scene: Dict[str, Any],
    exposure: float,
    films: bool = ...,
) -> Tuple[str, Optional[F32]]: ...
def materials_json() -> str: ...
def metals_json() -> str: ...
def shader(
    model: str,
    params: Sequence[Tuple[str, str]],
    lang: str,
    runtime_params: bool,
    material: Optional[str] = None,
    metal: Optional[str] = None,
) -> str: ...

class Handle:
    def __init__(self, id: str, params: Sequence[Tuple[str, str]]) -> None: ...
    @property
    def id(self) -> str: ...
    @property
    def kind(self) -> str: ...
    @property
    def values(self) -> List[Tuple[str, object]]: ...
    @property
    def columns(self) -> Tuple[List[str], List[str]]: ...
    @property
    def simd(self) -> bool: ...
    @staticmethod
    def channels(
        id: str, params: Sequence[Tuple[str, str]], material: Optional[str] = None, metal: Optional[str] = None
    ) -> List["Handle"]: ...
    @property
    def spec(self) -> str: ...
    def eval_f32(self, cols: Sequence[F32], out: Optional[F32] = None) -> F32: ...
    def eval_f64(self, cols: Sequence[F64], out: Optional[F64] = None) -> F64: ...
    def eval_dirs_f32(self, wi: F32, wo: F32, out: Optional[F32] = None) -> F32: ...
    def eval_dirs_f64(self, wi: F64, wo: F64, out: Optional[F64] = None) -> F64: ...
    def sample_f32(
        self, wo: F32, u: F32, strategy_name: str, out: Optional[Tuple[F32, F32, F32]] = None
    ) -> Tuple[F32, F32, F32]: ...
    def sample_f64(
        self, wo: F64, u: F64, strategy_name: str, out: Optional[Tuple[F64, F64, F64]] = None
    ) -> Tuple[F64, F64, F64]: ...
    def pdf_f32(self, wo: F32, wi: F32, strategy_name: str, out: Optional[F32] = None) -> F32: ...
    def pdf_f64(self, wo: F64, wi: F64, strategy_name: str, out: Optional[F64] = None) -> F64: ...
    def strategies(self) -> List[str]: ...

# The CLI's analyses (python/src/tools.rs): each returns its command's --json object as text.
def check_json(model: Optional[str], full: bool) -> str: ...
def reproduce_json(speedups: Optional[str]) -> str: ...
def fit_json(family: str, reference: str, arg: str, values: Sequence[float], metric: str, normalized: bool) -> str: ...
def normalize_json(model: str, n: Sequence[float], fit: Optional[str]) -> str: ...
def lut_table(model: str, size: int, axis: str, out: Optional[str], format: Optional[str]) -> Tuple[str, F32, F32]: ...
def pareto_json(bench: Optional[str]) -> str: ...
def pareto_brdf_json(
    alpha: Sequence[float],
    reference: str,
    size: int,
    mesh: Optional[str],
    all: bool,
    quick: bool,
    front_on: str,
    grid: Optional[str],
    costs: Optional[str],
) -> str: ...
def chi2_json(
    model: str,
    params: Sequence[Tuple[str, str]],
    theta_i: float,
    strategy: str,
    samples: Optional[int],
    res: Optional[int],
    seed: int,
    full: bool,
    precision: str,
    out: Optional[str],
) -> str: ...

# Conformance checks (python/src/conform.rs): a registry model is (id, params, material, metal),
# anything else an object with eval (and maybe sample and pdf).
def conform_json(model: object, reference: Optional[object], full: bool, strategy: str) -> str: ...

# MERL measured data (python/src/measured.rs).
class MeasuredData:
    def __init__(self, path: str) -> None: ...
    def info_json(self) -> str: ...
    def eval_f32(self, wi: F32, wo: F32) -> F32: ...
    def eval_f64(self, wi: F64, wo: F64) -> F64: ...
    def render(
        self,
        width: int,
        height: int,
        spp: int,
        lights: Sequence[str],
        floor: bool,
        shadows: bool,
        env: Optional[str],
        env_samples: int,
        mesh: Optional[str],
    ) -> F32: ...

def fit_measured_json(
    data: MeasuredData,
    model: str,
    params: Sequence[Tuple[str, str]],
    free: Sequence[str],
    metric: str,
    samples: int,
    restarts: int,
) -> str: ...

# Per-element parameters (python/src/perelement.rs).
def perelement_check(handle: Handle, name: str, values: F64) -> Optional[Tuple[int, str]]: ...
def perelement_eval_f32(handle: Handle, names: Sequence[str], params: Sequence[F64], cols: Sequence[F32], out: F32) -> None: ...
def perelement_eval_f64(handle: Handle, names: Sequence[str], params: Sequence[F64], cols: Sequence[F64], out: F64) -> None: ...
def perelement_eval_dirs_f32(handle: Handle, names: Sequence[str], params: Sequence[F64], wi: F32, wo: F32, out: F32) -> None: ...
def perelement_eval_dirs_f64(handle: Handle, names: Sequence[str], params: Sequence[F64], wi: F64, wo: F64, out: F64) -> None: ...
def perelement_sample_f32(
    handle: Handle, names: Sequence[str], params: Sequence[F64], wo: F32, u: F32, strategy_name: str
) -> Tuple[F32, F32, F32]: ...
def perelement_sample_f64(
    handle: Handle, names: Sequence[str], params: Sequence[F64], wo: F64, u: F64, strategy_name: str
) -> Tuple[F64, F64, F64]: ...
def perelement_pdf_f32(handle: Handle, names: Sequence[str], params: Sequence[F64], wo: F32, wi: F32, strategy_name: str) -> F32: ...
def perelement_pdf_f64(handle: Handle, names: Sequence[str], params: Sequence[F64], wo: F64, wi: F64, strategy_name: str) -> F64: ...

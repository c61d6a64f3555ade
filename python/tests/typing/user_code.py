"""User code as a researcher writes it, checked by ``mypy --strict`` (python/tests/test_typing.py):
the overloads of ``Model.eval`` give each call its dtype."""

import numpy as np
import numpy.typing as npt
from typing_extensions import assert_type

import fastbrdf

m = fastbrdf.Model("ggx", alpha=0.3)
x32: npt.NDArray[np.float32] = np.linspace(0, 1, 5, dtype=np.float32)
x64: npt.NDArray[np.float64] = np.linspace(0, 1, 5)

assert_type(m.eval(x32), npt.NDArray[np.float32])
assert_type(m.eval(x64), npt.NDArray[np.float64])
assert_type(m.eval(x64, precision="f32"), npt.NDArray[np.float32])
assert_type(m.eval(x32, precision="f64"), npt.NDArray[np.float64])
assert_type(m.eval(0.5), np.float64)
out: npt.NDArray[np.float32] = np.empty(5, dtype=np.float32)
assert_type(m.eval(x32, out=out), npt.NDArray[np.float32])

b = fastbrdf.Model("cook-torrance", alpha=0.2, metal="gold")
wi: npt.NDArray[np.float32] = np.zeros((4, 3), dtype=np.float32)
assert_type(b.eval(wi, wi), npt.NDArray[np.float32])
assert_type(b.channels, int)
assert_type(fastbrdf.__version__, str)
models: list[dict[str, object]] = fastbrdf.models("brdf")

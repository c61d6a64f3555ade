"""Mitsuba's ``roughconductor`` (GGX) checked two ways: by ``fastbrdf.conform`` through a small
Python wrapper, and by Mitsuba's own chi-square harness at its defaults. Prints one table.

    DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM-19.so \\
        python python/examples/mitsuba_conform.py [--alpha 0.1,0.5] [--theta 0,20,45,60,75,85,89]
        [--ires 4] [--variant llvm_ad_rgb] [--full] [--skip-chi2]

The wrapper (:class:`RoughConductor`) is what a researcher writes to check a BSDF of their own:
an object with ``eval(wi, wo)``, ``sample(wo, u)`` and ``pdf(wo, wi)`` on numpy arrays, in
fastbrdf's conventions. Mitsuba's differ in three places, converted here:

- Mitsuba's ``si.wi`` is the direction the BSDF is seen from, fastbrdf's ``wo``; the direction
  its ``eval``/``pdf`` take (``wo``) and ``sample`` returns (``bs.wo``) is fastbrdf's ``wi``;
- Mitsuba's ``eval`` includes the cosine factor ``cos theta_i``: divided out here;
- its ``sample`` returns ``weight = f cos / pdf``, fastbrdf's weight too; a sample that it
  masks (``bs.pdf == 0`` or below the horizon) is reported with pdf 0 (no sample).

Mitsuba's chi-square harness (``mitsuba.chi2.ChiSquareTest`` on ``BSDFAdapter``) runs at its
defaults (res 101, ires 4, 10^6 samples, significance 0.01), once per incidence angle, in the
variant chosen (it needs a vectorised one: ``llvm_ad_rgb``, which needs libLLVM 16 or newer).
``--ires 16`` integrates its pdf on 16 x 16 points per cell instead of 4 x 4. A broken sampler
(:class:`WrongPdf`: drawn at alpha, pdf of 1.1 alpha) shows that conform's chi2 check fails
when it should.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import threading
import time
from typing import Any, Dict, List, Tuple

import numpy as np

os.environ.setdefault("DRJIT_LIBLLVM_PATH", "/usr/lib/x86_64-linux-gnu/libLLVM-19.so")

import drjit as dr  # noqa: E402
import mitsuba as mi  # noqa: E402

import fastbrdf  # noqa: E402


def set_variant(variant: str = "llvm_ad_rgb") -> None:
    """Sets Mitsuba's variant (once per process: the wrapper and the harness share it)."""
    if mi.variant() != variant:
        mi.set_variant(variant)


class RoughConductor:
    """Mitsuba's ``roughconductor`` (GGX by default, visible-normal sampling, Mitsuba's
    default material: a perfect conductor, Fresnel 1) in fastbrdf's conventions. Needs a
    vectorised variant (``llvm_ad_rgb``): every call is one Dr.Jit kernel over all rows.
    Calls are serialised by a lock (fastbrdf may call from several threads)."""

    def __init__(self, alpha: float, distribution: str = "ggx", **extra: Any) -> None:
        set_variant(mi.variant() or "llvm_ad_rgb")
        if not mi.variant().startswith(("llvm", "cuda")):
            raise ValueError(f"RoughConductor needs a vectorised Mitsuba variant, not {mi.variant()}")
        self.alpha = alpha
        self.bsdf = mi.load_dict({"type": "roughconductor", "distribution": distribution,
                                  "alpha": alpha, **extra})
        self.ctx = mi.BSDFContext()
        self.lock = threading.Lock()

    def __repr__(self) -> str:
        return f"mitsuba roughconductor ggx alpha={self.alpha}"

    @staticmethod
    def _vec(a: np.ndarray) -> Any:
        a = np.asarray(a, dtype=np.float32)
        return mi.Vector3f(a[:, 0], a[:, 1], a[:, 2])

    def _si(self, wo: np.ndarray) -> Any:
        si = dr.zeros(mi.SurfaceInteraction3f, len(wo))
        si.wi = self._vec(wo)  # Mitsuba's wi: the direction the surface is seen from
        return si

    @staticmethod
    def _rgb(c: Any) -> np.ndarray:
        return np.stack([np.asarray(c[i], dtype=np.float64) for i in range(3)], axis=1)

    def eval(self, wi: np.ndarray, wo: np.ndarray) -> np.ndarray:
        with self.lock:
            v = self._rgb(self.bsdf.eval(self.ctx, self._si(wo), self._vec(wi)))
        cos = np.asarray(wi, dtype=np.float64)[:, 2]
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where((cos > 0)[:, None], v / cos[:, None], 0.0)

    def sample(self, wo: np.ndarray, u: np.ndarray) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
        n = len(wo)
        with self.lock:
            u = np.asarray(u, dtype=np.float32)
            bs, w = self.bsdf.sample(self.ctx, self._si(wo), mi.Float(np.full(n, 0.5, np.float32)),
                                     mi.Point2f(u[:, 0], u[:, 1]))
            wi = np.stack([np.asarray(bs.wo[i], dtype=np.float64) for i in range(3)], axis=1)
            pdf = np.asarray(bs.pdf, dtype=np.float64)
            weight = self._rgb(w)
        valid = (pdf > 0) & (wi[:, 2] > 0)
        return wi, np.where(valid[:, None], weight, 0.0), np.where(valid, pdf, 0.0)

    def pdf(self, wo: np.ndarray, wi: np.ndarray) -> np.ndarray:
        with self.lock:
            return np.asarray(self.bsdf.pdf(self.ctx, self._si(wo), self._vec(wi)), dtype=np.float64)


class WrongPdf(RoughConductor):
    """A broken sampler to show that the chi-square check sees one: directions drawn by
    roughconductor at ``alpha``, while ``pdf`` and the reported pdf are those of ``alpha *
    scale`` (the weight is ``f cos / reported pdf``, so only the histogram is wrong)."""

    def __init__(self, alpha: float, scale: float = 1.1) -> None:
        super().__init__(alpha)
        self.other = RoughConductor(alpha * scale)

    def __repr__(self) -> str:
        return f"{super().__repr__()} with the pdf of alpha={self.other.alpha:g}"

    def pdf(self, wo: np.ndarray, wi: np.ndarray) -> np.ndarray:
        return self.other.pdf(wo, wi)

    def sample(self, wo: np.ndarray, u: np.ndarray) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
        wi, _, pdf = super().sample(wo, u)
        p = np.where(pdf > 0, self.pdf(wo, wi), 0.0)
        with np.errstate(divide="ignore", invalid="ignore"):
            weight = np.where((p > 0)[:, None], self.eval(wi, wo) * wi[:, 2:3] / p[:, None], 0.0)
        return wi, weight, p


def mitsuba_chi2(alpha: float, theta_deg: float, ires: int = 4) -> Tuple[bool, float]:
    """Mitsuba's chi-square test of roughconductor (GGX, ``alpha``) at its defaults (``ires``
    integration points per cell and axis: 4, its default), seen from ``theta_deg``: (passed,
    p-value)."""
    from mitsuba.chi2 import BSDFAdapter, ChiSquareTest, SphericalDomain

    t = math.radians(theta_deg)
    props = {"type": "roughconductor", "distribution": "ggx", "alpha": alpha}
    sample, pdf = BSDFAdapter("roughconductor", props, wi=mi.ScalarVector3f(math.sin(t), 0.0, math.cos(t)))
    test = ChiSquareTest(domain=SphericalDomain(), sample_func=sample, pdf_func=pdf, sample_dim=3,
                         ires=ires)
    ok = bool(test.run(quiet=True))
    return ok, float(test.p_value)


def floats(text: str) -> List[float]:
    return [float(x) for x in text.split(",") if x.strip()]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--alpha", default="0.1,0.5", help="GGX roughness values (comma-separated)")
    ap.add_argument("--theta", default="0,20,45,60,75,85,89",
                    help="incidence angles of Mitsuba's chi-square runs (degrees; conform --full's)")
    ap.add_argument("--ires", type=int, default=4, help="Mitsuba's pdf integration points per cell and axis")
    ap.add_argument("--variant", default="llvm_ad_rgb")
    ap.add_argument("--full", action="store_true", help="fastbrdf.conform(full=True)")
    ap.add_argument("--skip-chi2", action="store_true", help="only fastbrdf.conform")
    a = ap.parse_args()
    set_variant(a.variant)
    rows: List[Dict[str, Any]] = []
    for alpha in floats(a.alpha):
        t = time.perf_counter()
        r = fastbrdf.conform(RoughConductor(alpha), full=a.full)
        failed = [c["check"] for c in r["checks"] if c["status"] == "fail"]
        rows.append({"alpha": alpha, "harness": f"fastbrdf.conform ({r['mode']})", "theta": "-",
                     "result": "pass" if r["passed"] else "FAIL " + ",".join(failed),
                     "detail": f"{sum(c['status'] == 'pass' for c in r['checks'])} checks passed",
                     "seconds": time.perf_counter() - t})
        t = time.perf_counter()
        r = fastbrdf.conform(WrongPdf(alpha), full=a.full)
        failed = [c["check"] for c in r["checks"] if c["status"] == "fail"]
        rows.append({"alpha": alpha, "harness": "conform, pdf of 1.1 alpha", "theta": "-",
                     "result": "pass" if r["passed"] else "FAIL " + ",".join(failed),
                     "detail": "(a broken sampler)", "seconds": time.perf_counter() - t})
        if a.skip_chi2:
            continue
        for theta in floats(a.theta):
            t = time.perf_counter()
            ok, p = mitsuba_chi2(alpha, theta, a.ires)
            harness = "mitsuba.chi2 (defaults)" if a.ires == 4 else f"mitsuba.chi2 (ires {a.ires})"
            rows.append({"alpha": alpha, "harness": harness, "theta": f"{theta:g}",
                         "result": "pass" if ok else "FAIL", "detail": f"p = {p:.3g}",
                         "seconds": time.perf_counter() - t})
    print(f"Mitsuba {mi.__version__} roughconductor (GGX), variant {mi.variant()}")
    print(f"{'alpha':>5}  {'harness':<26} {'theta':>5}  {'result':<24} {'detail':<20} {'s':>6}")
    for r in rows:
        print(f"{r['alpha']:>5g}  {r['harness']:<26} {r['theta']:>5}  {r['result']:<24} "
              f"{r['detail']:<20} {r['seconds']:>6.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""``fastbrdf.conform`` on BSDFs written in Python (issue 31): correct ones pass, each broken
one fails exactly the check it breaks, a registry id passes, and what a user's method does
wrong (a shape, a dtype, an exception, Ctrl-C) is raised naming the method. The last test runs
the checks on Mitsuba's ``roughconductor`` through python/examples/mitsuba_conform.py's
wrapper (skipped without Mitsuba, failing under CI)."""

import importlib.util
import math
import os
import pathlib

import numpy as np
import pytest

import fastbrdf

ROOT = pathlib.Path(__file__).resolve().parents[2]
CHECKS = ["finite", "non-negative", "non-finite-input", "reciprocity", "energy", "reference",
          "chi2", "weight", "pdf-integral", "pdf-coverage", "pdf-sample"]


def failed(r):
    return [c["check"] for c in r["checks"] if c["status"] == "fail"]


def status(r):
    return {c["check"]: c["status"] for c in r["checks"]}


def upper(wi, wo):
    """Both directions finite and above the horizon (rows where a BRDF may be non-zero)."""
    fin = np.isfinite(wi).all(axis=1) & np.isfinite(wo).all(axis=1)
    with np.errstate(invalid="ignore"):
        return fin & (wi[:, 2] > 0) & (wo[:, 2] > 0)


# -- correct BSDFs ------------------------------------------------------------------------


class Lambert:
    """Lambert of albedo ``albedo``, cosine-weighted sampling. Subclasses override ``eval``
    (the sampler's weight is always ``eval * cos / pdf``) or ``cone`` (the sampler's
    largest theta)."""

    cone = math.pi / 2

    def __init__(self, albedo=1.0):
        self.k = albedo / math.pi

    def eval(self, wi, wo):
        return np.where(upper(wi, wo), self.k, 0.0)

    def density(self, wo, wi):
        s2 = math.sin(self.cone) ** 2
        with np.errstate(invalid="ignore"):
            inside = upper(wi, wo) & (wi[:, 2] >= math.cos(self.cone) - 1e-12)
        return np.where(inside, wi[:, 2] / (math.pi * s2), 0.0)

    def sample(self, wo, u):
        r = np.sqrt(u[:, 0]) * math.sin(self.cone)
        phi = 2 * math.pi * u[:, 1]
        wi = np.stack([r * np.cos(phi), r * np.sin(phi), np.sqrt(np.maximum(0.0, 1 - r * r))], axis=1)
        pdf = self.density(wo, wi)
        with np.errstate(divide="ignore", invalid="ignore"):
            weight = np.where(pdf > 0, self.eval(wi, wo) * wi[:, 2] / pdf, 0.0)
        return wi, weight, pdf

    def pdf(self, wo, wi):
        return self.density(wo, wi)


class GGX:
    """GGX microfacet reflection (Fresnel 1, height-correlated Smith), visible-normal
    sampling (Heitz 2018). Returns R, G, B (equal) to exercise channels."""

    def __init__(self, alpha):
        self.a = alpha

    def __repr__(self):
        return f"numpy GGX alpha={self.a}"

    def lam(self, w):
        z2 = w[:, 2] ** 2
        return 0.5 * (np.sqrt(1 + self.a ** 2 * (1 - z2) / z2) - 1)

    def d(self, h):
        a2 = self.a ** 2
        return a2 / (math.pi * (h[:, 2] ** 2 * (a2 - 1) + 1) ** 2)

    def eval(self, wi, wo):
        ok = upper(wi, wo)
        wi, wo = np.where(ok[:, None], wi, [0, 0, 1]), np.where(ok[:, None], wo, [0, 0, 1])
        h = wi + wo
        h /= np.linalg.norm(h, axis=1)[:, None]
        f = self.d(h) / (1 + self.lam(wi) + self.lam(wo)) / (4 * wi[:, 2] * wo[:, 2])
        return np.repeat(np.where(ok, f, 0.0)[:, None], 3, axis=1)

    def pdf(self, wo, wi):
        ok = upper(wi, wo)
        wi, wo = np.where(ok[:, None], wi, [0, 0, 1]), np.where(ok[:, None], wo, [0, 0, 1])
        h = wi + wo
        h /= np.linalg.norm(h, axis=1)[:, None]
        return np.where(ok, self.d(h) / (1 + self.lam(wo)) / (4 * wo[:, 2]), 0.0)

    def sample(self, wo, u):
        a = self.a
        v = np.stack([a * wo[:, 0], a * wo[:, 1], wo[:, 2]], axis=1)
        v /= np.linalg.norm(v, axis=1)[:, None]
        l2 = v[:, 0] ** 2 + v[:, 1] ** 2
        with np.errstate(invalid="ignore", divide="ignore"):
            t1 = np.where((l2 > 0)[:, None], np.stack([-v[:, 1], v[:, 0], 0 * l2], axis=1) / np.sqrt(l2)[:, None],
                          [1.0, 0.0, 0.0])
        t2 = np.cross(v, t1)
        r, phi = np.sqrt(u[:, 0]), 2 * math.pi * u[:, 1]
        p1, p2 = r * np.cos(phi), r * np.sin(phi)
        s = 0.5 * (1 + v[:, 2])
        p2 = (1 - s) * np.sqrt(1 - p1 ** 2) + s * p2
        nh = p1[:, None] * t1 + p2[:, None] * t2 + np.sqrt(np.maximum(0, 1 - p1 ** 2 - p2 ** 2))[:, None] * v
        h = np.stack([a * nh[:, 0], a * nh[:, 1], np.maximum(0, nh[:, 2])], axis=1)
        h /= np.linalg.norm(h, axis=1)[:, None]
        wi = 2 * np.sum(wo * h, axis=1)[:, None] * h - wo
        pdf = self.pdf(wo, wi)
        with np.errstate(divide="ignore", invalid="ignore"):
            weight = np.where(pdf > 0, self.eval(wi, wo)[:, 0] * wi[:, 2] / pdf, 0.0)
        return wi, weight, pdf


# -- broken ones: each breaks one property -----------------------------------------------


class PdfTooLarge(Lambert):
    """pdf() and the sampler's pdf both 5% too large; weight = f cos / the reported pdf."""

    def density(self, wo, wi):
        return 1.05 * super().density(wo, wi)


class WeightWithoutCosine(Lambert):
    def sample(self, wo, u):
        wi, weight, pdf = super().sample(wo, u)
        with np.errstate(divide="ignore", invalid="ignore"):
            return wi, np.where(pdf > 0, weight / wi[:, 2], 0.0), pdf


class NonReciprocal(Lambert):
    """Depends on wi only."""

    def eval(self, wi, wo):
        return np.where(upper(wi, wo), 0.25 * (0.5 + wi[:, 2]), 0.0)


class Gain(Lambert):
    def __init__(self):
        super().__init__(1.2)


class NanAtGrazing(Lambert):
    """NaN where a direction lies exactly on the horizon."""

    def eval(self, wi, wo):
        fin = np.isfinite(wi).all(axis=1) & np.isfinite(wo).all(axis=1)
        grazing = fin & ((wi[:, 2] == 0) | (wo[:, 2] == 0))
        return np.where(grazing, np.nan, super().eval(wi, wo))


class NegativeLobe(Lambert):
    """Symmetric, below 1 in albedo, negative where both directions are grazing."""

    def eval(self, wi, wo):
        ok = upper(wi, wo)
        with np.errstate(invalid="ignore"):
            f = (0.9 - (1 - wi[:, 2]) * (1 - wo[:, 2])) / math.pi
        return np.where(ok, f, 0.0)


class Cone60(Lambert):
    """Samples only theta < 60 degrees (renormalised): pdf 0 where f is not."""

    cone = math.radians(60)


BROKEN = [(PdfTooLarge, "pdf-integral"), (WeightWithoutCosine, "weight"), (NonReciprocal, "reciprocity"),
          (Gain, "energy"), (NanAtGrazing, "finite"), (NegativeLobe, "non-negative"), (Cone60, "pdf-coverage")]


def test_a_correct_lambert_passes():
    r = fastbrdf.conform(Lambert())
    assert r["passed"], failed(r)
    assert r["model"] == "Lambert" and r["mode"] == "ci"
    assert [c["check"] for c in r["checks"]] == CHECKS
    assert status(r)["reference"] == "skip" and status(r)["chi2"] == "pass"


def test_a_numpy_ggx_with_vndf_sampling_passes():
    r = fastbrdf.conform(GGX(0.3))
    assert r["passed"], [(c["check"], c["summary"]) for c in r["checks"] if c["status"] == "fail"]
    assert r["model"] == "numpy GGX alpha=0.3"


def test_it_matches_the_registry_ggx_as_reference():
    # The numpy GGX against cook-torrance set to the same BRDF (GGX, height-correlated
    # Smith, Fresnel 1): the reference check passes; at another alpha it fails.
    ct = fastbrdf.Model("cook-torrance", alpha=0.3, d="ggx", g="smith-ggx-correlated")
    assert status(fastbrdf.conform(GGX(0.3), reference=ct))["reference"] == "pass"
    assert failed(fastbrdf.conform(GGX(0.33), reference=ct)) == ["reference"]


@pytest.mark.parametrize("cls, check", BROKEN, ids=[c.__name__ for c, _ in BROKEN])
def test_each_broken_bsdf_fails_exactly_its_check(cls, check):
    r = fastbrdf.conform(cls())
    assert failed(r) == [check], [(c["check"], c["summary"]) for c in r["checks"] if c["status"] == "fail"]
    assert not r["passed"]


def test_a_bsdf_built_on_fastbrdf_passes():
    # Its methods run fastbrdf's own rayon work inside the callbacks (which run on rayon's
    # threads): nothing deadlocks.
    lam = fastbrdf.Model("lambert")

    class OnFastbrdf:
        def eval(self, wi, wo):
            ok = np.isfinite(wi).all(axis=1) & np.isfinite(wo).all(axis=1)
            wi, wo = np.where(ok[:, None], wi, [0.0, 0.0, 1.0]), np.where(ok[:, None], wo, [0.0, 0.0, 1.0])
            return np.where(ok, lam.eval(wi, wo), 0.0)

        def sample(self, wo, u):
            return lam.sample(wo, u)

        def pdf(self, wo, wi):
            return lam.pdf(wo, wi)

    r = fastbrdf.conform(OnFastbrdf())
    assert r["passed"], failed(r)


def test_without_sample_and_pdf_the_sampling_checks_skip():
    class EvalOnly:
        def eval(self, wi, wo):
            return Lambert().eval(wi, wo)

    r = fastbrdf.conform(EvalOnly())
    assert r["passed"] and all(status(r)[c] == "skip" for c in CHECKS[5:])


def test_a_registry_id_passes():
    r = fastbrdf.conform("cook-torrance", alpha=0.3, d="ggx")
    assert r["passed"], failed(r)
    assert r["model"] == "cook-torrance alpha=0.3 d=ggx"
    assert fastbrdf.conform(fastbrdf.Model("cook-torrance", alpha=0.3, d="ggx")) == r
    gold = fastbrdf.conform("cook-torrance", alpha=0.3, d="ggx", metal="gold", strategy="d-cos")
    assert gold["passed"], failed(gold)


def test_the_record_is_the_cli_s(cli):
    import json

    r = fastbrdf.conform("cook-torrance", alpha=0.3, d="ggx")
    code, out, err = cli("conform", "cook-torrance", "--param", "alpha=0.3", "--param", "d=ggx", "--json")
    assert code == 0, err
    assert json.loads(out) == r


# -- errors --------------------------------------------------------------------------------


class Returns(Lambert):
    """eval returns what ``make(f)`` makes of the correct values."""

    def __init__(self, make):
        super().__init__()
        self.make = make

    def eval(self, wi, wo):
        return self.make(super().eval(wi, wo))


@pytest.mark.parametrize("make, exc, text", [
    (lambda f: f[:-1], ValueError, "eval returned shape (2,) for 3 rows; expected (3,) or (3, 3)"),
    (lambda f: np.stack([f, f], axis=1), ValueError, "eval returned shape (3, 2) for 3 rows"),
    (lambda f: f.astype(complex), TypeError, "eval returned an array of dtype complex128"),
    (lambda f: f > 0, TypeError, "eval returned an array of dtype bool"),
    (lambda f: None, TypeError, "eval returned an array of dtype object"),
])
def test_what_eval_returns_is_checked(make, exc, text):
    with pytest.raises(exc, match=text.replace("(", r"\(").replace(")", r"\)")):
        fastbrdf.conform(Returns(make))


def test_a_shape_that_changes_after_the_first_call_is_named():
    class Shrinks(Lambert):
        calls = 0

        def eval(self, wi, wo):
            self.calls += 1
            f = super().eval(wi, wo)
            return f if self.calls == 1 else f[:-1]

    with pytest.raises(ValueError, match=r"eval returned shape \((\d+),\) for (\d+) rows"):
        fastbrdf.conform(Shrinks())


@pytest.mark.parametrize("bad, exc, text", [
    (lambda wi, w, p: (wi, w), ValueError, "sample returned 2 items: expected 3"),
    (lambda wi, w, p: 3.0, TypeError, "sample returned float: expected a tuple"),
    (lambda wi, w, p: (wi[:, :2], w, p), ValueError, "sample's wi returned shape"),
    (lambda wi, w, p: (wi, w, p[:, None]), ValueError, "sample's pdf returned shape"),
])
def test_what_sample_returns_is_checked(bad, exc, text):
    class Bad(Lambert):
        def sample(self, wo, u):
            return bad(*super().sample(wo, u))

    with pytest.raises(exc, match=text):
        fastbrdf.conform(Bad())


def test_an_exception_of_a_method_propagates_with_a_note():
    class Raises(Lambert):
        def pdf(self, wo, wi):
            raise ZeroDivisionError("boom")

    with pytest.raises(ZeroDivisionError, match="boom") as e:
        fastbrdf.conform(Raises())
    notes = getattr(e.value, "__notes__", ["calling pdf(wo, wi) of Raises"])
    assert any("pdf(wo, wi) of Raises" in n for n in notes), notes


def test_keyboard_interrupt_propagates():
    class Interrupted(Lambert):
        def eval(self, wi, wo):
            if len(wi) > 3:  # after the probe call
                raise KeyboardInterrupt
            return super().eval(wi, wo)

    with pytest.raises(KeyboardInterrupt):
        fastbrdf.conform(Interrupted())


def test_ctrl_c_stops_it():
    # SIGINT (Ctrl-C) while the checks wait on a slow evaluator: KeyboardInterrupt within a
    # call or two, not after the whole run (about 100 calls of 50 ms).
    import signal
    import threading
    import time

    class Slow(Lambert):
        def eval(self, wi, wo):
            time.sleep(0.05)
            return super().eval(wi, wo)

    timer = threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT))
    t = time.perf_counter()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            fastbrdf.conform(Slow())
    finally:
        timer.cancel()
    assert time.perf_counter() - t < 2.0


def test_wrong_arguments_raise():
    with pytest.raises(TypeError, match="object with eval"):
        fastbrdf.conform(3)
    with pytest.raises(TypeError, match="has sample but no pdf"):
        fastbrdf.conform(type("S", (), {"eval": Lambert.eval, "sample": Lambert.sample, "k": 0.3})())
    with pytest.raises(TypeError, match="parameters"):
        fastbrdf.conform(Lambert(), alpha=0.3)
    with pytest.raises(ValueError, match="strategy"):
        fastbrdf.conform(Lambert(), strategy="vndf")
    with pytest.raises(ValueError, match="strategy 'nope'"):
        fastbrdf.conform("lambert", strategy="nope")
    with pytest.raises(ValueError, match="nope"):
        fastbrdf.conform("nope")
    with pytest.raises(ValueError, match="flog"):
        fastbrdf.conform("flog")  # a lobe, not a BRDF
    with pytest.raises(TypeError, match="reference"):
        fastbrdf.conform(Lambert(), reference=3)
    with pytest.raises(ValueError, match="per-element"):
        fastbrdf.conform(fastbrdf.Model("cook-torrance", alpha=np.array([0.1, 0.2])))


# -- Mitsuba's roughconductor --------------------------------------------------------------


def mitsuba_wrapper():
    """python/examples/mitsuba_conform.py as a module, in Mitsuba's llvm_ad_rgb variant."""
    try:
        import drjit as dr
        import mitsuba  # noqa: F401
    except ImportError as e:  # pragma: no cover - depends on the environment
        if os.environ.get("CI"):
            pytest.fail(f"mitsuba is not installed (tools/test.sh installs it): {e}")
        pytest.skip(f"mitsuba is not installed: {e}")
    missing = pytest.fail if os.environ.get("FASTBRDF_NEED_LLVM") else pytest.skip
    if not dr.has_backend(dr.JitBackend.LLVM) or tuple(dr.detail.llvm_version()) < (16,):
        missing("Dr.Jit found no libLLVM 16+ (install libllvm19 or set DRJIT_LIBLLVM_PATH)")
    spec = importlib.util.spec_from_file_location("mitsuba_conform", ROOT / "python" / "examples" / "mitsuba_conform.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    module.set_variant("llvm_ad_rgb")
    return module


@pytest.mark.parametrize("alpha", [0.1, 0.5])
def test_mitsuba_roughconductor_passes(alpha):
    mc = mitsuba_wrapper()
    r = fastbrdf.conform(mc.RoughConductor(alpha))
    assert r["passed"], [(c["check"], c["summary"]) for c in r["checks"] if c["status"] == "fail"]
    assert status(r)["chi2"] == "pass"


def test_a_mitsuba_sampler_with_a_wrong_pdf_fails_chi2():
    # Drawn by roughconductor at alpha 0.1, its pdf (reported and pdf()) that of 0.11: only
    # the histogram is wrong, and only chi2 fails.
    mc = mitsuba_wrapper()
    r = fastbrdf.conform(mc.WrongPdf(0.1))
    assert failed(r) == ["chi2"], [(c["check"], c["summary"]) for c in r["checks"] if c["status"] == "fail"]


LVP = "/usr/share/vulkan/icd.d/lvp_icd.x86_64.json"
USER = ROOT / "crates" / "gpu" / "tests" / "data" / "user"


def test_a_users_shader_file_is_checked_as_the_cli_checks_it(monkeypatch):
    """``file:PATH`` as the CLI's ``--model file:PATH``: a WGSL shader that samples, compiled on
    the GPU (lavapipe: the Vulkan driver tools/test.sh installs)."""
    if os.path.exists(LVP) and not os.environ.get("VK_ICD_FILENAMES") and not os.environ.get("VK_DRIVER_FILES"):
        monkeypatch.setenv("VK_ICD_FILENAMES", LVP)
    monkeypatch.setenv("WGPU_BACKEND", os.environ.get("WGPU_BACKEND", "vulkan"))
    good = fastbrdf.conform(f"file:{USER / 'ggx_sampled.wgsl'}", alpha=0.4)
    assert good["passed"], good
    assert status(good)["chi2"] == "pass"
    bad = fastbrdf.conform(f"file:{USER / 'broken_pdf_scaled.wgsl'}")
    assert failed(bad) == ["pdf-integral"]
    with pytest.raises(ValueError, match="alpha"):
        fastbrdf.conform(f"file:{USER / 'ggx_sampled.wgsl'}", alpha=7)
    with pytest.raises(ValueError, match=r"compile_error.wgsl:7:"):
        fastbrdf.conform(f"file:{USER / 'compile_error.wgsl'}")

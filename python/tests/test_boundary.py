"""The package's boundary (issue 27): outputs too large for memory raise MemoryError, long
calls stop on Ctrl-C, sequences are capped as the CLI caps its ranges, bad values are refused
naming the argument, and no PanicException (a BaseException) ever reaches a user."""

import subprocess
import sys
import textwrap

import numpy as np
import pytest

import fastbrdf
from fastbrdf import _fastbrdf as native


def python(code, timeout):
    """Runs `code` in a fresh interpreter: an abort or a hang fails the test, not pytest."""
    try:
        return subprocess.run(
            [sys.executable, "-c", textwrap.dedent(code)], capture_output=True, text=True, timeout=timeout
        )
    except subprocess.TimeoutExpired as e:
        pytest.fail(f"did not finish in {timeout} s (stdout {e.stdout!r})")


# ---------------------------------------------------------------------------------------------
# Memory: an output the address space cannot hold is a MemoryError, as numpy's own.

MEMORY = """
import resource
import numpy as np
import fastbrdf
from fastbrdf import _fastbrdf as native

def mapped():
    for line in open("/proc/self/status"):
        if line.startswith("VmSize:"):
            return int(line.split()[1]) * 1024

# Start the worker threads (and their allocator arenas) before the limit.
fastbrdf.Model("flog").eval(np.zeros(2_000_000, np.float32))
fastbrdf.Model("lambert").eval(np.zeros((300_000, 3), np.float32), np.zeros((300_000, 3), np.float32))
ZEROS = {ZEROS}   # untouched pages: address space, not memory
# What is mapped now plus 256 MiB: every output asked for below is larger.
resource.setrlimit(resource.RLIMIT_AS, (mapped() + (256 << 20), resource.getrlimit(resource.RLIMIT_AS)[1]))
try:
    {CALL}
except MemoryError as e:
    print("MemoryError:", e)
else:
    print("no error")
"""


@pytest.mark.parametrize(
    "zeros, call",
    [
        # The case: 400e6 float32 cosines, a 1.6 GB output.
        ("np.zeros(400_000_000, np.float32)", "fastbrdf.Model('flog').eval(ZEROS)"),
        ("np.zeros(200_000_000)", "fastbrdf.Model('flog').eval(ZEROS, precision='f64')"),
        # Shadowing terms run the scalar model per element.
        ("np.zeros(400_000_000, np.float32)", "fastbrdf.Model('smith-ggx').eval(ZEROS)"),
        ("np.zeros((100_000_000, 3), np.float32)", "fastbrdf.Model('lambert').eval(ZEROS, ZEROS)"),
        ("np.zeros((50_000_000, 3))", "fastbrdf.Model('lambert').eval(ZEROS, ZEROS, precision='f64')"),
        ("np.zeros((100_000_000, 3), np.float32)", "fastbrdf.Model('lambert').pdf(ZEROS, ZEROS)"),
        ("np.zeros((50_000_000, 3))", "fastbrdf.Model('lambert').pdf(ZEROS, ZEROS, precision='f64')"),
        # wo and u (3 + 2 columns): the outputs (wi, weight, pdf) take 5 columns.
        (
            "np.zeros((100_000_000, 3), np.float32), np.zeros((100_000_000, 2), np.float32)",
            "fastbrdf.Model('lambert').sample(*ZEROS)",
        ),
        (
            "np.zeros((50_000_000, 3)), np.zeros((50_000_000, 2))",
            "native.Handle('lambert', []).sample_f64(*ZEROS, 'auto')",
        ),
    ],
)
def test_an_output_too_large_is_a_memory_error(zeros, call):
    p = python(MEMORY.replace("{ZEROS}", zeros).replace("{CALL}", call), timeout=120)
    assert p.returncode == 0, f"exit {p.returncode}: {p.stderr[-2000:]}"
    assert p.stdout.startswith("MemoryError:"), p.stdout + p.stderr[-2000:]


@pytest.mark.parametrize("headroom", [256, 600])
def test_a_render_too_large_is_a_memory_error(headroom):
    # 8192 x 4096 (2^25 pixels, the largest size allowed): a 384 MiB output and a 384 MiB film.
    # With 256 MiB to spare the output fails first (numpy's MemoryError); with 600 MiB the
    # output fits and the renderer's film does not (it aborted the interpreter before).
    code = (
        MEMORY.replace("{ZEROS}", "None")
        .replace("(256 << 20)", f"({headroom} << 20)")
        .replace("{CALL}", "fastbrdf.render('ggx', width=8192, height=4096, spp=1)")
    )
    p = python(code, timeout=120)
    assert p.returncode == 0, f"exit {p.returncode}: {p.stderr[-2000:]}"
    assert p.stdout.startswith("MemoryError:"), p.stdout + p.stderr[-2000:]


# ---------------------------------------------------------------------------------------------
# Long calls: sequences are capped as the CLI caps its ranges, and Ctrl-C stops a call.


def test_sequences_are_capped_as_the_cli_caps_ranges():
    cap = native.MAX_VALUES
    assert cap == 1_000_000
    # One more than the cap, the last value invalid: the count is refused first.
    over = np.append(np.full(cap, 10.0), 0.0)
    with pytest.raises(ValueError, match=r"^n: 1000001 values; at most 1000000 are allowed"):
        fastbrdf.errors("flog", "pow", n=over)
    with pytest.raises(ValueError, match=r"^alpha: 1000001 values; at most 1000000 are allowed"):
        fastbrdf.errors("beckmann-approx", "beckmann", alpha=np.append(np.full(cap, 0.5), -1.0))
    with pytest.raises(ValueError, match=r"^angles: 1000001 values; at most 1000000 are allowed"):
        fastbrdf.albedo("ward", angles=np.append(np.zeros(cap), 90.0))
    # The private module checks the same (a plain list, as it is typed).
    with pytest.raises(ValueError, match=r"^values: 1000001 values; at most 1000000 are allowed"):
        native.errors_json("flog", "pow", "n", [10.0] * cap + [0.0], "all")
    with pytest.raises(ValueError, match=r"^angles: 1000001 values; at most 1000000 are allowed"):
        native.albedo_json("ward", [], [0.0] * cap + [90.0], "phong", "energy")


INTERRUPT = """
import os, signal, threading, time
import numpy as np
import fastbrdf

{SETUP}
t0 = time.perf_counter()
threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT)).start()
try:
    {CALL}
except KeyboardInterrupt:
    print("interrupted", time.perf_counter() - t0)
else:
    print("finished", time.perf_counter() - t0)
"""


@pytest.mark.parametrize(
    "setup, call",
    [
        # The case, at the cap: a million sweeps (minutes).
        ("", "fastbrdf.errors('flog', 'pow', n=np.full(1_000_000, 10.0))"),
        ("", "fastbrdf.albedo('ward', alpha=0.02, angles=np.linspace(0, 89, 100_000))"),
        # Grid antialiasing: every pixel takes the 16 x 16 samples (adaptive takes them at edges only).
        ("", "fastbrdf.render('ggx', alpha=0.3, width=2048, height=2048, spp=16, aa='grid')"),
        # 1e8 draws (the cap): the core's chi-square test checks its hook every 4096 draws.
        ("", "fastbrdf.chi2('cook-torrance', alpha=0.3, samples=100_000_000)"),
    ],
)
def test_ctrl_c_stops_a_long_call(setup, call):
    p = python(INTERRUPT.replace("{SETUP}", setup).replace("{CALL}", call), timeout=90)
    assert p.returncode == 0, p.stderr[-2000:]
    word, seconds = p.stdout.split()
    # SIGINT comes at 0.5 s; the call itself takes far longer than 3 s.
    assert word == "interrupted" and float(seconds) < 3.0, p.stdout


def test_a_single_long_evaluation_stops_on_ctrl_c():
    """One call over 1.5e8 to 6e8 elements (several seconds, whatever the build): before the
    chunking, SIGINT waited for the whole call."""
    code = """
    import os, signal, threading, time
    import numpy as np
    import fastbrdf

    m = fastbrdf.Model("smith-ggx", alpha=0.3)
    probe = np.zeros(15_000_000)
    t0 = time.perf_counter()
    m.eval(probe, precision="f64")
    per = (time.perf_counter() - t0) / probe.size
    n = int(min(6e8, max(1.5e8, 4.0 / per)))
    x = np.zeros(n)   # untouched pages; the output is written only until the interrupt
    t0 = time.perf_counter()
    threading.Timer(0.2, lambda: os.kill(os.getpid(), signal.SIGINT)).start()
    try:
        m.eval(x, precision="f64")
    except KeyboardInterrupt:
        print("interrupted", time.perf_counter() - t0, n * per)
    else:
        print("finished", time.perf_counter() - t0, n * per)
    """
    p = python(code, timeout=120)
    assert p.returncode == 0, p.stderr[-2000:]
    word, seconds, whole = p.stdout.split()
    assert float(whole) > 1.0, f"the call is too short to tell ({whole} s)"
    assert word == "interrupted" and float(seconds) < 0.2 + float(whole) / 4, p.stdout


# ---------------------------------------------------------------------------------------------
# Validation at the boundary.


def test_empty_angles_are_refused():
    with pytest.raises(ValueError, match="^angles: no values"):
        fastbrdf.albedo("ward", angles=[])
    with pytest.raises(ValueError, match="^angles: no values"):
        native.albedo_json("ward", [], [], "phong", "energy")
    with pytest.raises(ValueError, match="^n: no values"):
        fastbrdf.errors("flog", "pow", n=np.zeros(0))


@pytest.mark.parametrize("precision", ["f32", "f64"])
@pytest.mark.parametrize("bad", [1.0, 1.5, -0.25, np.nan, np.inf, -np.inf])
def test_sample_refuses_u_outside_the_unit_interval(precision, bad):
    m = fastbrdf.Model("cook-torrance", alpha=0.3)
    u = np.array([[0.2, 0.3], [0.5, bad], [0.1, 0.1]])
    with pytest.raises(ValueError, match=r"^u: .* is outside \[0, 1\)"):
        m.sample([0, 0, 1], u, precision=precision)
    # The private module refuses it too.
    dtype = np.float32 if precision == "f32" else np.float64
    h = native.Handle("cook-torrance", [("alpha", "0.3")])
    f = h.sample_f32 if precision == "f32" else h.sample_f64
    with pytest.raises(ValueError, match=r"^u: .* is outside \[0, 1\)"):
        f(np.tile(np.array([0, 0, 1], dtype), (3, 1)), u.astype(dtype), "auto")
    # Column-major u (read in place) and u already of the precision's dtype (checked by the
    # native call alone): the same refusal, naming the same element.
    for given in (u.astype(dtype), np.asfortranarray(u.astype(dtype))):
        with pytest.raises(ValueError, match=r"^u: .* \(row 1, column 1\) is outside \[0, 1\)"):
            m.sample(np.tile([0.0, 0.0, 1.0], (3, 1)).astype(dtype), given, precision=precision)
        with pytest.raises(ValueError, match=r"^u: .* \(row 1, column 1\) is outside \[0, 1\)"):
            f(np.tile(np.array([0, 0, 1], dtype), (3, 1)), given, "auto")


def test_sample_u_just_below_one_in_f64_still_samples_in_f32():
    """0.99999999 rounds to 1.0 in float32: the package keeps it below 1."""
    m = fastbrdf.Model("cook-torrance", alpha=0.3)
    wi, w, p = m.sample([0.3, 0, 0.95], [[0.99999999, 0.5]])
    assert np.isfinite(w).all() and np.isfinite(wi).all()


def unaligned(n, dtype=np.float32, fill=0.5):
    """`n` values `fill` at an odd address (not aligned for `dtype`), as the issue builds them."""
    raw = bytearray(b"\0" + np.full(n, fill, dtype).tobytes())
    a = np.frombuffer(raw, dtype, offset=1, count=n)
    assert not a.flags.aligned
    return a


def test_unaligned_arrays_are_copied_and_computed():
    x = unaligned(1000)
    m = fastbrdf.Model("flog", n=20)
    want = m.eval(np.full(1000, 0.5, np.float32))
    np.testing.assert_array_equal(m.eval(x), want)
    np.testing.assert_array_equal(native.Handle("flog", [("n", "20")]).eval_f32([x]), want)
    np.testing.assert_array_equal(m.eval(unaligned(1000, np.float64), precision="f64"), m.eval(np.full(1000, 0.5), precision="f64"))
    w = unaligned(300).reshape(100, 3)
    b = fastbrdf.Model("cook-torrance", alpha=0.3)
    np.testing.assert_array_equal(b.eval(w, w), b.eval(np.ascontiguousarray(w), np.ascontiguousarray(w)))
    np.testing.assert_array_equal(native.Handle("lambert", []).eval_dirs_f32(w, w), fastbrdf.Model("lambert").eval(w, w))


def test_the_private_module_reads_fortran_order_in_its_own_order():
    w = np.random.default_rng(3).random((50, 3)) + [0, 0, 0.5]
    h = native.Handle("cook-torrance", [("alpha", "0.3")])
    np.testing.assert_array_equal(h.eval_dirs_f64(np.asfortranarray(w), w), h.eval_dirs_f64(w, w))


def test_the_private_module_checks_lengths_and_counts():
    h = native.Handle("smith-ggx", [("alpha", "0.3")])
    with pytest.raises(ValueError, match=r"^cols: column 1 has 4 values, column 0 has 3"):
        h.eval_f32([np.zeros(3, np.float32), np.zeros(4, np.float32)])
    with pytest.raises(ValueError, match=r"^cols: column 1 has 4 values, column 0 has 3"):
        h.eval_f64([np.zeros(3), np.zeros(4)])
    with pytest.raises(TypeError, match=r"^cols: model 'smith-ggx' takes cos_v \(optionally cos_l\), got 3 column"):
        h.eval_f64([np.zeros(3)] * 3)
    b = native.Handle("lambert", [])
    for f, dtype in ((b.eval_dirs_f32, np.float32), (b.eval_dirs_f64, np.float64)):
        with pytest.raises(ValueError, match=r"^wo: 4 rows, wi has 3"):
            f(np.zeros((3, 3), dtype), np.zeros((4, 3), dtype))
    with pytest.raises(ValueError, match=r"^u: 4 rows, wo has 3"):
        b.sample_f32(np.zeros((3, 3), np.float32), np.zeros((4, 2), np.float32), "auto")
    with pytest.raises(ValueError, match=r"^wi: 2 rows, wo has 3"):
        b.pdf_f64(np.zeros((3, 3)), np.zeros((2, 3)), "auto")
    # Complex values are not real numbers (float() of numpy's would drop the imaginary part).
    for z in (1j, np.complex64(2 + 1j), np.complex128(3 + 0j)):
        with pytest.raises(TypeError, match=r"^values\[1\]: expected a real number, got complex"):
            native.errors_json("flog", "pow", "n", [10.0, z], "all")


RENDER_SCENE = dict(
    width=8, height=8, spp=1, weights=(0.6, 0.4), albedo=(0.8, 0.8, 0.8), lights=[], floor=False, shadows=False,
    env=None, env_samples=1, mesh=None, texture=None, bump=None,
)
RENDER_ARGS = dict(model="pow", params=[], material=None, metal=None, gpu=False, **RENDER_SCENE)


def render_native(**change):
    """The private render with the public defaults, `change` applied (scene keys go into the
    scene dict)."""
    args = {**RENDER_ARGS, **change}
    scene = {k: args.pop(k) for k in RENDER_SCENE}
    return native.render(args["model"], args["params"], args["material"], args["metal"], scene, args["gpu"])


def test_the_private_render_checks_its_numbers():
    assert render_native().shape == (8 * 8 * 3,)
    for name, bad in [("albedo", (-1.0, 0.5, 0.5)), ("albedo", (0.5, float("nan"), 0.5)), ("weights", (-0.5, 1)),
                      ("weights", (1, float("inf"))), ("weights", (1e4, 0)), ("bump", (1, -1)), ("bump", (0, 1))]:
        with pytest.raises(ValueError, match=f"^{name}"):
            render_native(**{name: bad})
    for name in ("width", "height", "spp", "env_samples"):
        with pytest.raises(ValueError, match=f"^{name}"):
            render_native(**{name: -1})
        with pytest.raises(ValueError, match=f"^{name}"):
            render_native(**{name: 10**30})
    with pytest.raises(TypeError, match="scene: unknown key 'size'"):
        native.render("pow", [], None, None, {**RENDER_SCENE, "size": 1})
    with pytest.raises(TypeError, match="scene: no 'bump'"):
        native.render("pow", [], None, None, {k: v for k, v in RENDER_SCENE.items() if k != "bump"})


# ---------------------------------------------------------------------------------------------
# Fuzz: every public and private function, bad inputs; only ValueError, TypeError or
# MemoryError may come out (never PanicException, RuntimeError, OverflowError, SystemError).


class Lying:
    """A sequence that claims 2^62 items (a capacity taken from len() would abort)."""

    def __len__(self):
        return 1 << 62

    def __getitem__(self, i):
        if i >= 3:
            raise IndexError(i)
        return 0.5


class Endless:
    """A sequence that says it has one item and goes on (to 3e6 items, so that a reader
    without a cap stays bounded here: its memory, not the machine's)."""

    def __len__(self):
        return 1

    def __getitem__(self, i):
        if i >= 3_000_000:
            raise IndexError(i)
        return 0.5


def bad_arrays():
    f32 = np.float32
    return [
        np.zeros(0), np.zeros((0, 3)), np.zeros((0, 2)), np.array([np.nan]), np.array([np.inf, -np.inf]),
        np.array([-1.0]), np.array([1e300]), np.array([1e-320]), np.zeros((2, 2)), np.zeros((2, 3, 3)),
        np.zeros((3, 3), f32)[:, ::2], np.zeros((4, 3))[::2], np.asfortranarray(np.ones((4, 3))),
        np.zeros((2, 3), ">f8"), np.zeros(3, ">f4"), unaligned(6).reshape(2, 3), unaligned(4).reshape(2, 2),
        np.array([True]), np.array(["a"]), np.array([1j]), np.array([None]), np.zeros(3, np.float16),
        np.array([2**70], dtype=object), np.zeros((1, 0)), np.zeros(()), [], [[]], [[1, 2, 3], [4, 5]], None, "x", 1e400,
        10**30, -1, object(), Lying(), np.nan,
    ]


BAD_SCALARS = [None, "", "x" * 10_000, -1, 0, 10**30, -(10**30), 1e400, float("nan"), float("inf"), 1.5, True,
               object(), [], (), ("a",), b"x", "\0", "\udcff"]


def fuzz_calls():
    """(label, callable) for each bad input of each function."""
    arrays = bad_arrays()
    ok3 = np.array([[0.3, 0.0, 0.95]] * 2)
    ok2 = np.array([[0.2, 0.3]] * 2)
    out = []
    lobe, brdf, env, shadow = (fastbrdf.Model("flog"), fastbrdf.Model("cook-torrance"),
                               fastbrdf.Model("env-brdf-approx"), fastbrdf.Model("smith-ggx"))
    for i, a in enumerate(arrays):
        for p in ("f32", "f64"):
            out += [
                (f"lobe.eval #{i} {p}", lambda a=a, p=p: lobe.eval(a, precision=p)),
                (f"env.eval #{i} {p}", lambda a=a, p=p: env.eval(a, a, precision=p)),
                (f"shadow.eval #{i} {p}", lambda a=a, p=p: shadow.eval(a, a, precision=p)),
                (f"brdf.eval wi #{i} {p}", lambda a=a, p=p: brdf.eval(a, ok3, precision=p)),
                (f"brdf.eval wo #{i} {p}", lambda a=a, p=p: brdf.eval(ok3, a, precision=p)),
                (f"brdf.sample wo #{i} {p}", lambda a=a, p=p: brdf.sample(a, ok2, precision=p)),
                (f"brdf.sample u #{i} {p}", lambda a=a, p=p: brdf.sample(ok3, a, precision=p)),
                (f"brdf.pdf #{i} {p}", lambda a=a, p=p: brdf.pdf(ok3, a, precision=p)),
            ]
        out += [
            (f"errors n #{i}", lambda a=a: fastbrdf.errors("flog", "pow", n=a)),
            (f"errors alpha #{i}", lambda a=a: fastbrdf.errors("beckmann-approx", "beckmann", alpha=a)),
            (f"albedo angles #{i}", lambda a=a: fastbrdf.albedo("lambert", angles=a)),
            (f"render albedo #{i}", lambda a=a: fastbrdf.render("pow", width=4, height=4, albedo=a)),
            (f"render weights #{i}", lambda a=a: fastbrdf.render("pow", width=4, height=4, weights=a)),
        ]
        for name, h in (("lobe", native.Handle("flog", [])), ("brdf", native.Handle("cook-torrance", [])),
                        ("env", native.Handle("env-brdf-approx", [])), ("shadow", native.Handle("smith-ggx", []))):
            out += [
                (f"native {name}.eval_f32 #{i}", lambda h=h, a=a: h.eval_f32([a])),
                (f"native {name}.eval_f64 #{i}", lambda h=h, a=a: h.eval_f64([a, a])),
                (f"native {name}.eval_f64 list #{i}", lambda h=h, a=a: h.eval_f64(a)),
                (f"native {name}.eval_dirs_f32 #{i}", lambda h=h, a=a: h.eval_dirs_f32(a, a)),
                (f"native {name}.eval_dirs_f64 #{i}", lambda h=h, a=a: h.eval_dirs_f64(a, ok3)),
                (f"native {name}.sample_f32 #{i}", lambda h=h, a=a: h.sample_f32(a, a, "auto")),
                (f"native {name}.sample_f64 #{i}", lambda h=h, a=a: h.sample_f64(ok3, a, "auto")),
                (f"native {name}.pdf_f32 #{i}", lambda h=h, a=a: h.pdf_f32(a, a, "auto")),
                (f"native {name}.pdf_f64 #{i}", lambda h=h, a=a: h.pdf_f64(ok3, a, "auto")),
            ]
        out += [
            (f"native errors_json #{i}", lambda a=a: native.errors_json("flog", "pow", "n", a, "all")),
            (f"native albedo_json #{i}", lambda a=a: native.albedo_json("lambert", [], a, "phong", "energy")),
            (f"native Handle params #{i}", lambda a=a: native.Handle("flog", a)),
            (f"native eval_f32 cols #{i}", lambda a=a: native.Handle("flog", []).eval_f32(a)),
        ]
    for j, s in enumerate(BAD_SCALARS):
        out += [
            (f"Model id #{j}", lambda s=s: fastbrdf.Model(s)),
            (f"Model param #{j}", lambda s=s: fastbrdf.Model("flog", n=s)),
            (f"Model unknown param #{j}", lambda s=s: fastbrdf.Model("flog", q=s)),
            (f"models kind #{j}", lambda s=s: fastbrdf.models(s)),
            (f"eval precision #{j}", lambda s=s: lobe.eval(0.5, precision=s)),
            (f"sample strategy #{j}", lambda s=s: brdf.sample(ok3, ok2, strategy=s)),
            (f"pdf strategy #{j}", lambda s=s: brdf.pdf(ok3, ok3, strategy=s)),
            (f"errors model #{j}", lambda s=s: fastbrdf.errors(s, "pow", n=10)),
            (f"errors reference #{j}", lambda s=s: fastbrdf.errors("flog", s, n=10)),
            (f"errors n scalar #{j}", lambda s=s: fastbrdf.errors("flog", "pow", n=s)),
            (f"errors zone #{j}", lambda s=s: fastbrdf.errors("flog", "pow", n=10, zone=s)),
            (f"albedo model #{j}", lambda s=s: fastbrdf.albedo(s, angles=[0])),
            (f"albedo angles scalar #{j}", lambda s=s: fastbrdf.albedo("lambert", angles=s)),
            (f"albedo as_brdf #{j}", lambda s=s: fastbrdf.albedo("pow", angles=[0], as_brdf=s)),
            (f"albedo norm #{j}", lambda s=s: fastbrdf.albedo("pow", angles=[0], norm=s)),
            (f"albedo param #{j}", lambda s=s: fastbrdf.albedo("pow", angles=[0], n=s)),
            (f"shader model #{j}", lambda s=s: fastbrdf.shader(s)),
            (f"shader lang #{j}", lambda s=s: fastbrdf.shader("flog", lang=s)),
            (f"shader param #{j}", lambda s=s: fastbrdf.shader("flog", n=s)),
            (f"native info_json #{j}", lambda s=s: native.info_json(s)),
            (f"native parse_range text #{j}", lambda s=s: native.parse_range(s, 1.0)),
            (f"native parse_range step #{j}", lambda s=s: native.parse_range("0..1", s)),
            (f"native errors_json param #{j}", lambda s=s: native.errors_json("flog", "pow", s, [10.0], "all")),
            (f"native errors_json zone #{j}", lambda s=s: native.errors_json("flog", "pow", "n", [10.0], s)),
            (f"native errors_json values #{j}", lambda s=s: native.errors_json("flog", "pow", "n", [s], "all")),
            (f"native albedo_json as_brdf #{j}", lambda s=s: native.albedo_json("pow", [], [0.0], s, "energy")),
            (f"native albedo_json angles #{j}", lambda s=s: native.albedo_json("pow", [], [s], "phong", "energy")),
            (f"native albedo_json params #{j}", lambda s=s: native.albedo_json("pow", [("n", s)], [0.0], "phong", "energy")),
            (f"native shader lang #{j}", lambda s=s: native.shader("flog", [], s, False)),
            (f"native shader runtime #{j}", lambda s=s: native.shader("flog", [], "wgsl", s)),
            (f"native Handle id #{j}", lambda s=s: native.Handle(s, [])),
            (f"native Handle param #{j}", lambda s=s: native.Handle("flog", [("n", s)])),
            (f"native sample strategy #{j}", lambda s=s: native.Handle("lambert", []).sample_f64(ok3, ok2, s)),
        ]
        for k in ("width", "height", "spp", "env_samples"):
            out.append((f"render {k} #{j}", lambda s=s, k=k: fastbrdf.render("pow", **{"width": 4, "height": 4, k: s})))
        for k in ("lights", "env", "floor", "shadows", "mesh", "texture", "bump", "material", "metal", "size"):
            out.append((f"render {k} #{j}", lambda s=s, k=k: fastbrdf.render("pow", width=4, height=4, **{k: s})))
        for k in ("models", "reference", "measured", "exposure", "mesh", "material", "metal"):
            kw = {"models": ["flog"], "reference": "pow", "size": "4x4", "spp": 1}
            out.append((f"compare {k} #{j}", lambda s=s, k=k, kw=kw: fastbrdf.compare(**{**kw, k: s})))
        # (gpu: True would look for an adapter, whose absence is a RuntimeError by design.)
        for k in [k for k in RENDER_ARGS if k != "gpu"]:
            out.append((f"native render {k} #{j}", lambda s=s, k=k: render_native(**{k: s})))
    # Huge and endless inputs.
    out += [
        ("render huge", lambda: fastbrdf.render("pow", width=8192, height=8192)),
        ("render huge native", lambda: render_native(width=1 << 31, height=1 << 31)),
        ("render spp 10**6", lambda: fastbrdf.render("pow", width=4, height=4, spp=10**6)),
        ("render env_samples 10**6", lambda: fastbrdf.render("pow", width=4, height=4, env_samples=10**6)),
        ("render lights endless", lambda: render_native(lights=Endless())),
        ("native errors_json endless", lambda: native.errors_json("flog", "pow", "n", Endless(), "all")),
        ("native albedo_json endless", lambda: native.albedo_json("lambert", [], Endless(), "phong", "energy")),
        ("native Handle params endless", lambda: native.Handle("flog", Endless())),
        ("native eval cols endless", lambda: native.Handle("flog", []).eval_f64(Endless())),
        ("parse_range huge", lambda: native.parse_range("0..1e300", 1.0)),
        ("errors range huge", lambda: fastbrdf.errors("flog", "pow", n="1..1e12")),
        ("eval 2**31 broadcast", lambda: lobe.eval(np.broadcast_to(np.float32(0.5), (1 << 36,)))),
    ]
    return out


@pytest.mark.filterwarnings("ignore::RuntimeWarning")
def test_fuzz_only_value_type_or_memory_errors_come_out():
    escaped = []
    calls = fuzz_calls()
    for label, f in calls:
        try:
            f()
        except (ValueError, TypeError, MemoryError):
            pass
        except BaseException as e:  # noqa: B036 - PanicException derives from BaseException
            escaped.append(f"{label}: {type(e).__name__}: {str(e)[:200]}")
    assert len(calls) > 1000
    assert not escaped, "\n".join(escaped[:60]) + f"\n({len(escaped)} in all)"

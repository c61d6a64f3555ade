"""fastbrdf against Mitsuba 3 end to end from numpy: eval, sample and pdf of a GGX BRDF over N
float32 direction pairs, in millions of elements per second, measured interleaved in one run.

    DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM-19.so \\
        target/python-wheel-venv/bin/python python/examples/sample_cost.py [--n 1e6,1e7] [--repeats 5]
        [--variant llvm_ad_rgb] [--mitsuba-max-n 1e7] [--no-mitsuba] [--input-sets 1]
        [--warm-call] [--settle 50]

fastbrdf: ``Model("cook-torrance", d="ggx", alpha=0.3)`` on (N, 3) and (N, 2) float32 arrays,
with fresh outputs and with ``out=`` buffers reused from call to call, and on column-major
copies of the same arrays (``fastbrdf columns``: ``np.asfortranarray``, Mitsuba's layout, made
outside the timing as Mitsuba's columns are; read in place), with fresh outputs and with
``out=``. Mitsuba:
``roughconductor`` (GGX, alpha 0.3, its default visible-normal sampling) through
``bsdf.eval/sample/pdf`` on ``mi.Vector3f`` built from the same values given as float32 numpy
columns (its own layout, made outside the timing), and as ``... from rows`` from the (N, 3)
and (N, 2) rows fastbrdf reads (the columns copied out with ``np.ascontiguousarray`` inside
the timing, as a user holding rows would call it), the results converted back to numpy
arrays (after ``dr.eval``); "vs Mitsuba" compares each fastbrdf figure with Mitsuba's given
the same layout (rows with ``from rows``, columns with columns); its ``eval`` includes the
cosine factor and its weight is RGB, as its variant computes them. Mitsuba's first call per operation and size (which JIT-compiles the
kernel) and a second warm-up call are excluded from the figures; the first call's time is
printed apart. Each figure is the best of --repeats rounds, every method timed once per round
(interleaved, so that a busy machine slows all of them alike). Prints the CPU's name, the
thread counts and a markdown table, with ns per element (to see any super-linear cost at large
N; 1e8 needs about 6 GB of memory for fastbrdf's arrays, which is why Mitsuba stops at
--mitsuba-max-n). ``--input-sets K`` makes K sets of inputs and round r uses set r mod K, so
that no call finds the previous call's inputs in the CPU's caches (each set has its own
``out=`` buffers and Mitsuba columns; every set is warmed up). ``--warm-call`` calls each
method once, untimed, right before its timed call: on the shared 2-core VM a call of a few
milliseconds that follows the other library's calls (or any idle moment: its worker threads
asleep, the caches cold) took up to twice as long as the same call repeated, whichever library
it was; the warm call measures both in their steady state. ``--settle MS`` sleeps MS
milliseconds before each method's calls (before its warm call), as a script that calls now
and then, between other work, would: no call then shares the cores with the other library's
idle threads (after each call Dr.Jit's worker spins about 20 ms; fastbrdf's helpers linger
as long as the call lasted, at most 5 ms, ``fastbrdf::par::linger``), and each library's
threads have been idle before the warm call (with ``--warm-call`` the timed call follows it
at once, as a script's second call would). The script measures what each library's threads
do after a call and prints it: the CPU time the whole process uses in the 100 ms after one
``pdf`` call of each (the least of three tries), as ``idle threads after a call``.
"""

import argparse
import os
import resource
import sys
import time

import numpy as np

import fastbrdf


def cpu_name():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    import platform

    return platform.processor() or "unknown CPU"


def hemisphere(rng, n):
    """Unit float32 vectors above the horizon, made in pieces (1e8 of them fit in memory)."""
    out = np.empty((n, 3), np.float32)
    for lo in range(0, n, 1 << 22):
        hi = min(n, lo + (1 << 22))
        v = rng.normal(size=(hi - lo, 3))
        v[:, 2] = np.abs(v[:, 2])
        out[lo:hi] = v / np.linalg.norm(v, axis=1, keepdims=True)
    return out


def cpu_seconds():
    """CPU time used by every thread of this process so far."""
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


def idle_cpu_ms(f, window=0.1, tries=3):
    """Milliseconds of CPU the process uses in the `window` seconds after a call of `f` (its
    threads still running once the call returned), the least of `tries`."""
    best = float("inf")
    for _ in range(tries):
        f()
        c0 = cpu_seconds()
        time.sleep(window)
        best = min(best, cpu_seconds() - c0)
    return best * 1e3


def fastbrdf_ops(n, wi, wo, u):
    m = fastbrdf.Model("cook-torrance", d="ggx", alpha=0.3)
    f, p = np.empty(n, np.float32), np.empty(n, np.float32)
    bufs = (np.empty((n, 3), np.float32), np.empty(n, np.float32), np.empty(n, np.float32))
    # Column-major copies (Mitsuba's layout, made outside the timing as its columns are): read
    # in place, with no deinterleaving.
    wic, woc, uc = (np.asfortranarray(a) for a in (wi, wo, u))
    return {
        ("eval", "fastbrdf"): lambda: m.eval(wi, wo),
        ("eval", "fastbrdf out="): lambda: m.eval(wi, wo, out=f),
        ("eval", "fastbrdf columns"): lambda: m.eval(wic, woc),
        ("eval", "fastbrdf columns out="): lambda: m.eval(wic, woc, out=f),
        ("sample", "fastbrdf"): lambda: m.sample(wo, u),
        ("sample", "fastbrdf out="): lambda: m.sample(wo, u, out=bufs),
        ("sample", "fastbrdf columns"): lambda: m.sample(woc, uc),
        ("sample", "fastbrdf columns out="): lambda: m.sample(woc, uc, out=bufs),
        ("pdf", "fastbrdf"): lambda: m.pdf(wo, wi),
        ("pdf", "fastbrdf out="): lambda: m.pdf(wo, wi, out=p),
        ("pdf", "fastbrdf columns"): lambda: m.pdf(woc, wic),
        ("pdf", "fastbrdf columns out="): lambda: m.pdf(woc, wic, out=p),
    }


def mitsuba_ops(variant, n, wi, wo, u):
    """Mitsuba's calls, or a reason they cannot run. Returns (ops, first-call seconds)."""
    try:
        import drjit as dr
        import mitsuba as mi

        mi.set_variant(variant)
    except Exception as e:  # not installed, or no libLLVM for llvm_* variants
        return f"{variant} unavailable ({type(e).__name__}: {str(e).splitlines()[0][:120]})", {}
    bsdf = mi.load_dict({"type": "roughconductor", "distribution": "ggx", "alpha": 0.3})
    ctx = mi.BSDFContext()
    def cols(a):
        """Mitsuba's own layout: one contiguous float32 column per component of rows `a`."""
        return [np.ascontiguousarray(a[:, k]) for k in range(a.shape[1])]

    woc, wic, uc = (cols(a) for a in (wo, wi, u))

    def si():
        s = dr.zeros(mi.SurfaceInteraction3f, n)
        s.wi = mi.Vector3f(*woc)
        return s

    def ev():
        v = bsdf.eval(ctx, si(), mi.Vector3f(*wic))
        dr.eval(v)
        return np.asarray(v)

    def sa():
        bs, w = bsdf.sample(ctx, si(), mi.Float(uc[0]), mi.Point2f(uc[0], uc[1]))
        dr.eval(bs.wo, w, bs.pdf)
        return np.asarray(bs.wo), np.asarray(w), np.asarray(bs.pdf)

    def pd():
        v = bsdf.pdf(ctx, si(), mi.Vector3f(*wic))
        dr.eval(v)
        return np.asarray(v)

    # From the same (N, 3) and (N, 2) rows fastbrdf reads: the columns made inside the timing
    # (numpy copies of the strided column views), as a user holding rows would call Mitsuba.
    def si_rows():
        s = dr.zeros(mi.SurfaceInteraction3f, n)
        s.wi = mi.Vector3f(*cols(wo))
        return s

    def ev_rows():
        v = bsdf.eval(ctx, si_rows(), mi.Vector3f(*cols(wi)))
        dr.eval(v)
        return np.asarray(v)

    def sa_rows():
        c = cols(u)
        bs, w = bsdf.sample(ctx, si_rows(), mi.Float(c[0]), mi.Point2f(c[0], c[1]))
        dr.eval(bs.wo, w, bs.pdf)
        return np.asarray(bs.wo), np.asarray(w), np.asarray(bs.pdf)

    def pd_rows():
        v = bsdf.pdf(ctx, si_rows(), mi.Vector3f(*cols(wi)))
        dr.eval(v)
        return np.asarray(v)

    ops = {
        ("eval", variant): ev,
        ("sample", variant): sa,
        ("pdf", variant): pd,
        ("eval", variant + " from rows"): ev_rows,
        ("sample", variant + " from rows"): sa_rows,
        ("pdf", variant + " from rows"): pd_rows,
    }
    first = {}
    for k, f in ops.items():
        t0 = time.perf_counter()
        f()  # JIT compilation (the columns' call; the rows' reuse its kernel)
        first.setdefault(k[0], time.perf_counter() - t0)
        f()  # second warm-up
    return ops, first


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", default="1e6,1e7", help="comma-separated sizes")
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--variant", default="llvm_ad_rgb")
    ap.add_argument("--mitsuba-max-n", type=float, default=1e7)
    ap.add_argument("--no-mitsuba", action="store_true")
    ap.add_argument("--input-sets", type=int, default=1, help="input sets used in turn (1: the same every call)")
    ap.add_argument("--warm-call", action="store_true", help="call each method once, untimed, right before its timed call")
    ap.add_argument("--settle", type=float, default=0.0, metavar="MS",
                    help="sleep MS milliseconds before each method's calls, so that the other library's idle threads have stopped (0: no pause)")
    a = ap.parse_args()
    sizes = [int(float(x)) for x in a.n.split(",")]
    print(f"CPU: {cpu_name()}, {os.cpu_count()} logical cores; "
          f"RAYON_NUM_THREADS={os.environ.get('RAYON_NUM_THREADS', 'unset (all cores)')}")
    build = getattr(fastbrdf, "BUILD", "unknown")
    if build != "release":
        print(f"sample_cost.py: this fastbrdf is a {build} build, not a release one: its figures "
              "are several times slower than a user's (the test suite's wheel is built in Cargo's "
              "dev profile); build one with `maturin build --release` and install it, or put its "
              "files first on PYTHONPATH", file=sys.stderr)
    print(f"fastbrdf {fastbrdf.__version__} ({build} build); best of {a.repeats} interleaved rounds{'; each timed call after an untimed one' if a.warm_call else ''}"
          f"{f'; {a.settle:g} ms pause before each method' if a.settle > 0 else ''}; float32 inputs; "
          f"{max(1, a.input_sets)} input set(s) in turn\n")
    print("| op | N | who | M elements/s | ns/element | vs Mitsuba (same layout) | Mitsuba's first (JIT) call |")
    print("|---|---|---|---|---|---|---|", flush=True)
    for n in sizes:
        rows = []
        rng = np.random.default_rng(1)
        sets, first = [], {}
        for i in range(max(1, a.input_sets)):
            wi, wo = hemisphere(rng, n), hemisphere(rng, n)
            u = rng.random((n, 2), dtype=np.float32)
            ops = fastbrdf_ops(n, wi, wo, u)
            if not a.no_mitsuba and n <= a.mitsuba_max_n:
                mops, f1 = mitsuba_ops(a.variant, n, wi, wo, u)
                if isinstance(mops, str):
                    print(mops)
                else:
                    ops.update(mops)
                    first = first or f1  # the first set's calls compile the kernels
            for f in ops.values():
                f()  # warm-up (fastbrdf: page in the out= buffers)
            sets.append(ops)
        idle = {w: idle_cpu_ms(sets[0][k]) for k, w in (
            (("pdf", "fastbrdf columns"), "fastbrdf"), (("pdf", a.variant), a.variant)) if k in sets[0]}
        print(f"idle threads after a call, N = {n:.0e} (pdf; CPU ms used in the 100 ms after it returned): "
              + ", ".join(f"{w} {v:.1f}" for w, v in idle.items()), flush=True)
        best = dict.fromkeys(sets[0], float("inf"))
        for rep in range(a.repeats):
            for k, f in sets[rep % len(sets)].items():
                if a.settle > 0:
                    time.sleep(a.settle / 1e3)
                if a.warm_call:
                    f()  # untimed: the same call's steady state follows
                t0 = time.perf_counter()
                r = f()
                best[k] = min(best[k], time.perf_counter() - t0)
                del r
        pk = ("pdf", a.variant)
        if pk in sets[0]:
            # Mitsuba's pdf against fastbrdf's on the same pairs: its figure is of real values.
            mine, theirs = sets[0][("pdf", "fastbrdf")](), sets[0][pk]()
            ok = int(np.count_nonzero(np.abs(mine - theirs) <= 1e-4 * np.maximum(mine, 1)))
            print(f"pdf, N = {n:.0e}: {a.variant}'s values within 1e-4 (relative) of fastbrdf's at {ok} of {n} pairs")
        for (op, who), t in best.items():
            # Against Mitsuba given the same layout: fastbrdf's rows against Mitsuba from rows,
            # its columns against Mitsuba's columns.
            rows_in = not who.startswith("fastbrdf columns")
            mit = best.get((op, a.variant + (" from rows" if rows_in else "")))
            ratio = f"{mit / t:.2f}x" if mit and not who.startswith(a.variant) else ""
            rows.append((op, n, who, n / t / 1e6, t / n * 1e9, ratio, first.get(op) if who == a.variant else None))
        del sets, ops, wi, wo, u
        rows.sort(key=lambda r: ["eval", "sample", "pdf"].index(r[0]))
        for op, n, who, rate, ns, ratio, jit in rows:  # one size's rows, printed as it ends
            jit_s = f"{jit:.2f} s" if jit is not None else ""
            print(f"| {op} | {n:.0e} | {who} | {rate:.1f} | {ns:.2f} | {ratio} | {jit_s} |", flush=True)


if __name__ == "__main__":
    main()

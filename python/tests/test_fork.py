"""A child process made by ``fork()`` after the parent ran threaded batches (``multiprocessing``'s
default start method on Linux before Python 3.14): rayon's threads do not survive the fork, and
the child's first threaded call used to wait for them for ever. Each call here runs in such a
child, must return within the timeout, and must give the parent's values."""

import multiprocessing as mp

import numpy as np
import pytest

import fastbrdf

pytestmark = pytest.mark.skipif(
    "fork" not in mp.get_all_start_methods(), reason="no fork() on this platform"
)

N = 50_000  # about 12 chunks of 4096: threaded
M = fastbrdf.Model("cook-torrance", d="ggx", alpha=0.3)


def pairs(n, seed):
    rng = np.random.default_rng(seed)
    v = rng.normal(size=(2, n, 3))
    v[..., 2] = np.abs(v[..., 2])
    v /= np.linalg.norm(v, axis=-1, keepdims=True)
    return v[0].astype(np.float32), v[1].astype(np.float32)


WI, WO = pairs(N, 1)
U = np.random.default_rng(2).random((N, 2), dtype=np.float32)


def calls():
    """Every kind of threaded work the package does: batches (rows and columns, f32 and f64),
    sampling, densities, per-element parameters, a sweep, an albedo curve and a render."""
    return {
        "eval rows": lambda: M.eval(WI, WO),
        "eval columns": lambda: M.eval(np.asfortranarray(WI), np.asfortranarray(WO)),
        "eval f64": lambda: M.eval(WI.astype(np.float64), WO.astype(np.float64)),
        "sample": lambda: M.sample(WO, U)[2],
        "pdf": lambda: M.pdf(WO, WI),
        "per-element alpha": lambda: fastbrdf.Model(
            "cook-torrance", d="ggx", alpha=np.linspace(0.1, 0.9, N)
        ).eval(WI, WO),
        "errors": lambda: np.array(
            [r["max_abs"] for r in fastbrdf.errors("flog", "pow", n=[10, 100])]
        ),
        "albedo": lambda: np.array(
            [r["albedo"] for r in fastbrdf.albedo("cook-torrance", angles=[0, 60])["rows"]]
        ),
        "render": lambda: fastbrdf.render("cook-torrance", d="ggx", alpha=0.3, width=24, height=16, spp=1),
        "lut": lambda: fastbrdf.lut(size=8)["table"],
        "normalize": lambda: np.array([r["int"] for r in fastbrdf.normalize("pow", n=[10, 100])["rows"]]),
        "measured": lambda: fastbrdf.Measured(fastbrdf._measured._tiny()).eval(WI, WO),
        "conform": lambda: np.array(fastbrdf.conform("lambert")["passed"]),
    }


def run(name):
    return np.asarray(calls()[name]())


@pytest.mark.parametrize("name", list(calls()))
def test_a_forked_child_runs_threaded_calls(name):
    want = run(name)  # the parent runs it first: its threads exist when the child is made
    M.eval(WI, WO)
    with mp.get_context("fork").Pool(1) as pool:
        got = pool.apply_async(run, (name,)).get(timeout=60)
    np.testing.assert_array_equal(got, want)


def in_fork(f, timeout):
    """``f()`` in a child made by ``fork()`` (a plain, non-daemonic process, so that it may have
    children too), its result sent back through a pipe; a child that does not answer within
    ``timeout`` seconds is killed and the call fails."""
    ctx = mp.get_context("fork")
    parent_end, child_end = ctx.Pipe()
    p = ctx.Process(target=_send, args=(f, child_end))
    p.start()
    try:
        if not parent_end.poll(timeout):
            raise TimeoutError(f"the forked child's {f.__name__} did not return in {timeout} s")
        ok, value = parent_end.recv()
    finally:
        p.kill()
        p.join()
    if not ok:
        raise RuntimeError(f"in the forked child: {value}")
    return value


def _send(f, conn):
    try:
        conn.send((True, f()))
    except BaseException as e:  # reported to the parent
        conn.send((False, repr(e)))
    conn.close()


def _eval():
    return M.eval(WI, WO)


def _eval_then_fork_again():
    _eval()  # the child's own pool, made and used before its child is made
    return in_fork(_eval, 60)


def test_a_grandchild_too():
    want = _eval()
    np.testing.assert_array_equal(in_fork(_eval_then_fork_again, 120), want)

"""Models travel by value: a reduced python/examples/dask_sweep.py on a real LocalCluster
(worker processes, so every Model is pickled and rebuilt), a multiprocessing.Pool round trip,
copy.deepcopy and joblib, each equal to the single-process result."""

import copy
import multiprocessing
import os
import pathlib
import pickle
import sys

import numpy as np
import pytest

import fastbrdf

EXAMPLES = pathlib.Path(__file__).resolve().parents[1] / "examples"
# The example as a module (workers import it by name: spawned processes inherit sys.path).
sys.path.insert(0, str(EXAMPLES))
import dask_sweep  # noqa: E402

sys.path.remove(str(EXAMPLES))

# dask[distributed] is a test dependency (tools/test.sh installs it): missing, this fails.
from dask.distributed import Client, LocalCluster  # noqa: E402


@pytest.fixture(scope="module")
def small():
    pairs = dask_sweep.grid(2)  # 2 roughnesses x 8 shadowing terms x 3 Fresnel terms
    dirs = dask_sweep.directions(2000)
    return pairs, dirs, dask_sweep.errors(pairs, dirs)


def test_the_grid_is_what_the_example_says(small):
    pairs, _, serial = small
    assert len(pairs) == 2 * len(dask_sweep.SHADOWING) * len(dask_sweep.FRESNEL) == len(serial)
    # Every approximation differs from the exact model somewhere, and no error is NaN.
    assert all(r["max_abs"] > 0 and np.isfinite(r["rms"]) for r in serial)
    # The exact models of one roughness are one value (equal, one hash), not 24 objects.
    assert len({exact for _, exact in pairs}) == 2


def test_a_local_cluster_gives_the_single_process_rows(small, monkeypatch):
    pairs, dirs, serial = small
    # The workers import dask_sweep by name: they start with this sys.path.
    monkeypatch.syspath_prepend(str(EXAMPLES))
    with LocalCluster(
        # A free port for the HTTP server: dashboard_address=None still takes 8787 (a warning
        # when another cluster, another test run's, holds it).
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address="127.0.0.1:0"
    ) as cluster, Client(cluster) as client:
        assert len(client.scheduler_info()["workers"]) == 2
        rows = dask_sweep.sweep_dask(client, pairs, dirs, chunk=5)
        # A Model goes to a worker process and comes back equal.
        m = pairs[7][0]
        back = client.submit(lambda x: x, m, pure=False).result()
        values = client.submit(lambda x: x.values, m, pure=False).result()
        # Both workers did some of the chunks.
        ran = client.run(lambda dask_worker: dask_worker.state.executed_count)
    assert rows == serial
    assert back == m and back is not m and values == m.values
    assert len(ran) == 2 and all(n > 0 for n in ran.values()), ran


def _eval_chunk(args):
    model, cos = args
    return model.eval(cos, precision="f64")


def test_a_multiprocessing_pool_round_trip():
    models = [fastbrdf.Model("flog", n=n) for n in (5, 50, 500)] + [fastbrdf.Model("ggx", alpha=0.3)]
    cos = np.linspace(0.0, 1.0, 1001)
    # spawn: a fresh interpreter that rebuilds each Model from its pickle.
    with multiprocessing.get_context("spawn").Pool(2) as pool:
        back = pool.map(pickle.loads, [pickle.dumps(m) for m in models])
        values = pool.map(_eval_chunk, [(m, cos) for m in models])
    assert back == models
    for m, v in zip(models, values):
        np.testing.assert_array_equal(v, m.eval(cos, precision="f64"))


def test_deepcopy_and_pickle_give_an_equal_independent_model():
    m = fastbrdf.Model("cook-torrance", d="ggx", g="smith-ggx-correlated", f="schlick", alpha=0.25)
    for c in (copy.deepcopy(m), copy.copy(m), pickle.loads(pickle.dumps(m, protocol=pickle.HIGHEST_PROTOCOL))):
        assert c == m and hash(c) == hash(m) and c is not m
        assert c.values == m.values and c.params == m.params
        wi, wo = np.array([0.2, 0.1, 0.97]), np.array([-0.3, 0.0, 0.95])
        assert c.eval(wi, wo, precision="f64") == m.eval(wi, wo, precision="f64")
    # A different parameter is a different model, after the round trip too.
    other = pickle.loads(pickle.dumps(fastbrdf.Model("cook-torrance", d="ggx", g="smith-ggx-correlated", f="schlick", alpha=0.26)))
    assert other != m


def test_joblib_if_installed(small, monkeypatch):
    # Optional for a user; tools/test.sh installs it, so under CI a missing joblib fails.
    joblib = pytest.importorskip("joblib") if not os.environ.get("CI") else __import__("joblib")
    pairs, dirs, serial = small
    monkeypatch.syspath_prepend(str(EXAMPLES))  # loky's workers import dask_sweep by name
    with joblib.parallel_config(backend="loky", n_jobs=2):
        parts = joblib.Parallel()(joblib.delayed(dask_sweep.errors)(c, dirs) for c in dask_sweep.chunks(pairs, 12))
    assert [r for rows in parts for r in rows] == serial

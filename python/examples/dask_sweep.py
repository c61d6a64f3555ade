"""Scaling an error sweep with dask.distributed (docs/book/src/python-scaling.md).

A grid of Cook-Torrance configurations (GGX with each approximate shadowing term and each
approximate Fresnel term, at many roughnesses) is evaluated against the exact one (GGX with the
height-correlated Smith term and the exact dielectric Fresnel term of the same index, eta = 1.5
being f0 = 0.04) over the same random directions. Each task gets a chunk of (approximation,
exact) ``fastbrdf.Model`` pairs, pickled by value, and the directions, scattered once to every
worker; the rows come back with ``client.gather`` and must equal the single-process sweep.

    python python/examples/dask_sweep.py                          # a LocalCluster, 2 workers
    python python/examples/dask_sweep.py --alphas 16 --directions 20000   # smaller
    python python/examples/dask_sweep.py --scheduler tcp://host:8786      # a real cluster

Only fastbrdf, numpy and dask[distributed] are needed (on the workers too).
"""

from __future__ import annotations

import argparse
import os
import time
from typing import Any, Dict, List, Sequence, Tuple

import numpy as np

import fastbrdf

#: The approximate shadowing-masking terms of GGX compared with the exact one.
SHADOWING = (
    "smith-ggx",
    "smith-ggx-correlated-fast",
    "smith-ggx-correlated-fast-tuned",
    "smith-ggx-joint-approx",
    "schlick-ggx",
    "kelemen",
    "neumann",
    "v-cavity",
)
#: The approximate Fresnel terms (f0 = 0.04, the reflectance of eta = 1.5 at normal incidence).
FRESNEL = ("schlick", "schlick-sg", "schlick-sg-tuned")

Pair = Tuple[fastbrdf.Model, fastbrdf.Model]


def grid(alphas: int) -> List[Pair]:
    """Every (approximation, exact) pair: each shadowing term with each Fresnel term at
    ``alphas`` roughnesses from 0.02 to 1 (geometric)."""
    pairs = []
    for alpha in np.geomspace(0.02, 1.0, alphas):
        a = float(alpha)
        exact = fastbrdf.Model("cook-torrance", d="ggx", g="smith-ggx-correlated", f="dielectric", eta=1.5, alpha=a)
        for g in SHADOWING:
            for f in FRESNEL:
                pairs.append((fastbrdf.Model("cook-torrance", d="ggx", g=g, f=f, f0=0.04, alpha=a), exact))
    return pairs


def directions(n: int, seed: int = 1) -> Tuple[np.ndarray, np.ndarray]:
    """``n`` pairs (wi, wo) of directions drawn uniformly on the upper hemisphere (float64)."""
    rng = np.random.default_rng(seed)

    def hemisphere(m: int) -> np.ndarray:
        z = rng.random(m)
        phi = 2.0 * np.pi * rng.random(m)
        r = np.sqrt(1.0 - z * z)
        return np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=-1)

    return hemisphere(n), hemisphere(n)


def errors(pairs: Sequence[Pair], dirs: Tuple[np.ndarray, np.ndarray]) -> List[Dict[str, Any]]:
    """One row per pair: the largest and the RMS error of f cos(theta_i) and the relative
    error of its mean (the albedo's bias), both models evaluated in f64."""
    # Arrays that dask deserialises can be unaligned (here the first one was): fastbrdf copies
    # such an input on every call (its array rules), so realign them once per task.
    wi, wo = (np.require(a, np.float64, ["C", "A"]) for a in dirs)
    rows = []
    for approx, exact in pairs:
        fa = approx.eval(wi, wo, precision="f64") * wi[:, 2]
        fe = exact.eval(wi, wo, precision="f64") * wi[:, 2]
        d = fa - fe
        rows.append(
            {
                "g": approx.values["g"],
                "f": approx.values["f"],
                "alpha": approx.values["alpha"],
                "max_abs": float(np.max(np.abs(d))),
                "rms": float(np.sqrt(np.mean(d * d))),
                "mean_rel": float(abs(fa.mean() - fe.mean()) / fe.mean()),
            }
        )
    return rows


def chunks(pairs: Sequence[Pair], size: int) -> List[List[Pair]]:
    """The pairs in consecutive chunks of ``size`` (one task each)."""
    return [list(pairs[i : i + size]) for i in range(0, len(pairs), size)]


def sweep_dask(client: Any, pairs: Sequence[Pair], dirs: Tuple[np.ndarray, np.ndarray], chunk: int) -> List[Dict[str, Any]]:
    """The sweep on a dask cluster: the directions scattered once to every worker, one task
    per chunk of pairs (the Models pickled by value), the rows gathered in order."""
    dirs_future = client.scatter(dirs, broadcast=True)
    futures = client.map(errors, chunks(pairs, chunk), dirs=dirs_future, pure=False)
    return [row for rows in client.gather(futures) for row in rows]


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--alphas", type=int, default=64, help="roughnesses in the grid (x 24 configurations)")
    p.add_argument("--directions", type=int, default=200_000, help="(wi, wo) pairs per configuration")
    p.add_argument("--chunk", type=int, default=24, help="configurations per task")
    p.add_argument("--workers", type=int, default=2, help="LocalCluster worker processes (one thread each)")
    p.add_argument("--scheduler", help="a running scheduler's address (tcp://host:8786) instead of a LocalCluster")
    args = p.parse_args()

    import dask
    from dask.distributed import Client, LocalCluster

    # Two of dask's worker defaults cost these short, numpy-heavy tasks: the sampling profiler
    # (a thread that takes the GIL every 10 ms) and MALLOC_TRIM_THRESHOLD_=65536 in the
    # workers' environment (glibc then maps and unmaps every large array: system time). With
    # both off a task took 15 to 20% less time here (2 cores, load 2.7). On a real cluster give
    # `dask worker` the same settings (DASK_DISTRIBUTED__WORKER__PROFILE__ENABLED=False, and
    # distributed.nanny.pre-spawn-environ in its config file).
    dask.config.set(
        {
            "distributed.worker.profile.enabled": False,
            "distributed.nanny.pre-spawn-environ": {"OMP_NUM_THREADS": 1, "MKL_NUM_THREADS": 1, "OPENBLAS_NUM_THREADS": 1},
        }
    )

    pairs = grid(args.alphas)
    dirs = directions(args.directions)
    load = os.getloadavg()[0]
    print(f"{len(pairs)} configurations x {args.directions} direction pairs; {os.cpu_count()} cores, load {load:.1f}")

    t = time.perf_counter()
    serial = errors(pairs, dirs)
    t_serial = time.perf_counter() - t
    print(f"one process: {t_serial:.2f} s")

    if args.scheduler:
        client = Client(args.scheduler)
        cluster = None
    else:
        t = time.perf_counter()
        cluster = LocalCluster(n_workers=args.workers, threads_per_worker=1, processes=True, dashboard_address="127.0.0.1:0")
        client = Client(cluster)
        print(f"LocalCluster of {args.workers} workers started in {time.perf_counter() - t:.2f} s")
    try:
        workers = len(client.scheduler_info()["workers"])
        t = time.perf_counter()
        distributed = sweep_dask(client, pairs, dirs, args.chunk)
        t_dask = time.perf_counter() - t
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    print(f"dask, {workers} workers: {t_dask:.2f} s ({t_serial / t_dask:.2f}x)")
    assert distributed == serial, "the distributed sweep differs from the single-process one"
    print("equal to the single-process sweep: yes")

    worst = sorted(serial, key=lambda r: -r["max_abs"])[:3]
    for r in worst:
        print(f"  largest error: g={r['g']} f={r['f']} alpha={r['alpha']:.3f}: max |d f cos| {r['max_abs']:.3g}")


if __name__ == "__main__":
    main()

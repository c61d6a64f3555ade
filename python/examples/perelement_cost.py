"""The cost of per-element parameters (``fastbrdf.Model(..., alpha=array)``): millions of
elements per second, float32, for a scalar ``alpha`` and for ``alpha`` arrays with 1, 256 and
all-distinct values, on the GGX distribution (``eval(cos_h)``) and on Cook-Torrance
(``eval(wi, wo)``; with ``d=ggx`` and by default, Beckmann with the exact Smith term, both SIMD
kernels since issue 30 vectorised its ``erfc``), with numpy evaluating the GGX formula on the
same arrays for scale.

    target/python-venv/bin/python python/examples/perelement_cost.py [--n 1048576] [--repeats 5]

Each figure is the best of --repeats runs. The all-distinct case runs on --n-distinct
elements (a model is built per element: it is slow) and also prints the build's cost, in
microseconds per distinct value (its time less the 1-value case's per element).
"""

import argparse
import sys
import time

import numpy as np

import fastbrdf


def best(f, repeats):
    f()  # warm-up
    t = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        f()
        t.append(time.perf_counter() - t0)
    return min(t)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=1 << 20)
    ap.add_argument("--n-distinct", type=int, default=1 << 14)
    ap.add_argument("--repeats", type=int, default=5)
    a = ap.parse_args()
    if fastbrdf.BUILD != "release":
        print(f"{sys.argv[0]}: a {fastbrdf.BUILD} build of fastbrdf (the test suite's wheel?): its "
              "timings are several times a release build's", file=sys.stderr)
    rng = np.random.default_rng(1)
    n, nd = a.n, a.n_distinct
    cos = rng.uniform(0, 1, n).astype(np.float32)
    wi = rng.normal(size=(n, 3)).astype(np.float32)
    wo = rng.normal(size=(n, 3)).astype(np.float32)
    wi[:, 2], wo[:, 2] = np.abs(wi[:, 2]), np.abs(wo[:, 2])
    levels = np.linspace(0.05, 1.0, 256, dtype=np.float32)
    alphas = {
        "scalar alpha": None,
        "array, 1 value": np.full(n, 0.3, dtype=np.float32),
        "array, 256 values": levels[rng.integers(0, 256, n)],
        "array, all distinct": rng.uniform(0.05, 1.0, nd).astype(np.float32),
    }
    print(f"float32, n = {n} (all distinct: {nd}); M elements/s (best of {a.repeats})")
    per_one = {}
    for kind, model, extra, args in (
        ("ggx", "ggx", {}, lambda k: (cos[:k],)),
        ("ct d=ggx", "cook-torrance", {"d": "ggx"}, lambda k: (wi[:k], wo[:k])),
        ("cook-torrance", "cook-torrance", {}, lambda k: (wi[:k], wo[:k])),
    ):
        for label, alpha in alphas.items():
            k = n if alpha is None else alpha.size
            m = fastbrdf.Model(model, alpha=0.3 if alpha is None else alpha, **extra)
            x = args(k)
            t = best(lambda: m.eval(*x), a.repeats if k == n else 1)
            print(f"  {kind:14} {label:20} {k / t / 1e6:9.2f}")
            if label == "array, 1 value":
                per_one[kind] = t / k
            if label == "array, all distinct":
                print(f"  {kind:14} {'build per value':20} {(t / k - per_one[kind]) * 1e6:9.2f} us")
    c = cos.astype(np.float32)
    al = alphas["array, 256 values"]

    def numpy_ggx():
        a2 = al * al
        d = a2 * c * c + (1 - c * c)
        return a2 / (np.float32(np.pi) * d * d)

    t = best(numpy_ggx, a.repeats)
    print(f"  {'ggx':14} {'numpy formula':20} {n / t / 1e6:9.2f}")


if __name__ == "__main__":
    main()

"""Times fastbrdf's Mitsuba plug-in against Mitsuba's native roughconductor on the same scene,
in the same run, and prints the ratio (plug-in time / native time) per variant.

    target/python-venv/bin/python python/examples/mitsuba_cost.py [--res 64] [--spp 16]
        [--variants scalar_rgb,llvm_ad_rgb]

The scene: a GGX conductor sphere (alpha 0.3) filling the frame, a spherical lamp and a constant
environment, path tracer of depth 2 (direct lighting with MIS). Each time is the best of
--repeats renders after one warm-up render (which compiles the kernels in llvm variants). A
variant that cannot be set (no libLLVM for llvm_*) is reported and skipped.
"""

import argparse
import sys
import time

import drjit as dr
import mitsuba as mi

import fastbrdf
import fastbrdf.mitsuba as fm


def scene(bsdf, res, spp):
    return mi.load_dict({
        "type": "scene",
        "integrator": {"type": "path", "max_depth": 2, "hide_emitters": True},
        "sensor": {
            "type": "perspective", "fov": 30,
            "to_world": mi.ScalarTransform4f().look_at(origin=[0, 0, 2.2], target=[0, 0, 0], up=[0, 1, 0]),
            "film": {"type": "hdrfilm", "width": res, "height": res, "rfilter": {"type": "box"}},
            "sampler": {"type": "independent", "sample_count": spp},
        },
        "sphere": {"type": "sphere", "bsdf": bsdf},
        "lamp": {"type": "sphere", "center": [1.5, 1.5, 3], "radius": 0.7,
                 "emitter": {"type": "area", "radiance": {"type": "rgb", "value": 8.0}}},
        "env": {"type": "constant", "radiance": {"type": "rgb", "value": 0.2}},
    })


def best_time(s, repeats):
    with fm.evaluated_mode():
        dr.eval(mi.render(s, seed=0))  # warm-up (kernel compilation in llvm variants)
        best = float("inf")
        for seed in range(1, repeats + 1):
            t = time.perf_counter()
            img = mi.render(s, seed=seed)
            dr.eval(img)
            dr.sync_thread()
            best = min(best, time.perf_counter() - t)
    return best


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--res", type=int, default=64)
    ap.add_argument("--spp", type=int, default=16)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--variants", default="scalar_rgb,llvm_ad_rgb")
    a = ap.parse_args()
    if fastbrdf.BUILD != "release":
        print(f"{sys.argv[0]}: a {fastbrdf.BUILD} build of fastbrdf (the test suite's wheel?): its "
              "timings are several times a release build's", file=sys.stderr)
    ours = {"type": "fastbrdf", "model": "cook-torrance", "d": "ggx", "g": "smith-ggx",
            "f": "conductor", "eta": 0.2, "k": 3.0, "alpha": 0.3}
    native = {"type": "roughconductor", "distribution": "ggx", "alpha": 0.3, "eta": 0.2, "k": 3.0}
    print(f"{a.res}x{a.res} pixels, {a.spp} spp, best of {a.repeats}")
    for variant in a.variants.split(","):
        try:
            fm.register(variant)
        except Exception as e:  # e.g. no libLLVM for llvm_* variants
            print(f"{variant}: unavailable ({str(e).splitlines()[0]})")
            continue
        t_ours = best_time(scene(ours, a.res, a.spp), a.repeats)
        t_native = best_time(scene(native, a.res, a.spp), a.repeats)
        print(f"{variant}: plug-in {t_ours * 1e3:.1f} ms, roughconductor {t_native * 1e3:.1f} ms, "
              f"ratio {t_ours / t_native:.1f}")


if __name__ == "__main__":
    main()

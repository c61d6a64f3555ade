#!/usr/bin/env python3
"""Writes stored reference values of Mitsuba 3's `roughconductor` (Beckmann, no visible-normal
sampling; `eval` only) for fastbrdf's `cook-torrance` test (crates/fastbrdf/tests/mitsuba.rs).

Mitsuba's eval returns f(wi, wo) * cos(theta_o) = F D G / (4 cos theta_i), with D the
normalised Beckmann, G = G1(wi) G1(wo) with Walter's rational G1, and F the exact conductor
Fresnel at dot(wi, m). It runs in single precision (scalar_rgb).

Run: pip install mitsuba==3.9.1 && python3 tools/mitsuba_reference.py > crates/fastbrdf/tests/data/mitsuba_roughconductor.csv
"""
import math
import random

import mitsuba as mi

mi.set_variant("scalar_rgb")
random.seed(20261122)


def hemisphere():
    z = 0.02 + 0.98 * random.random()
    r = math.sqrt(1 - z * z)
    phi = 2 * math.pi * random.random()
    return [r * math.cos(phi), r * math.sin(phi), z]


print(f"# mitsuba {mi.__version__} scalar_rgb roughconductor beckmann sample_visible=false; value = eval(wi, wo)[0]")
print("alpha,eta,k,wi_x,wi_y,wi_z,wo_x,wo_y,wo_z,value")
for alpha in [0.05, 0.1, 0.3, 0.6, 1.0]:
    for eta, k in [(0.2, 3.9), (1.5, 0.0), (0.47, 2.4)]:
        bsdf = mi.load_dict({"type": "roughconductor", "distribution": "beckmann", "alpha": alpha,
                             "sample_visible": False, "eta": eta, "k": k})
        for i in range(30):
            wi = hemisphere()
            if i % 2 == 0:
                wo = hemisphere()
            else:  # near the mirror direction, where the lobe is
                s = min(0.5, 2 * alpha)
                m = [-wi[0] + s * (random.random() - 0.5), -wi[1] + s * (random.random() - 0.5), wi[2]]
                l = math.sqrt(sum(x * x for x in m))
                wo = [m[0] / l, m[1] / l, max(m[2] / l, 0.02)]
                l = math.sqrt(sum(x * x for x in wo))
                wo = [x / l for x in wo]
            si = mi.SurfaceInteraction3f()
            si.wi = mi.Vector3f(wi)
            ctx = mi.BSDFContext()
            v = bsdf.eval(ctx, si, mi.Vector3f(wo))
            print(",".join(f"{x:.9g}" for x in [alpha, eta, k, *wi, *wo, v[0]]))

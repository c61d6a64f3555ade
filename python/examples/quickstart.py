"""A tour of the fastbrdf Python package (run by python/tests/test_api.py).

    python python/examples/quickstart.py
"""

import numpy as np

import fastbrdf

# The registry, as `fastbrdf models --json`.
lobes = [m["id"] for m in fastbrdf.models("lobe")]
print(f"{len(fastbrdf.models())} models, lobes: {', '.join(lobes[:6])}, ...")

# A lobe on a million cosines: f32 through the SIMD kernel, no copy of the input.
flog = fastbrdf.Model("flog", n=20)
c = np.linspace(0.8, 1.0, 1_000_000, dtype=np.float32)
v = flog.eval(c)
exact = fastbrdf.Model("pow", n=20).eval(c.astype(np.float64), precision="f64")
print(f"flog n=20 vs pow: max |error| {np.abs(v - exact).max():.4f} on [0.8, 1]")
print(f"flog's documented f32 bound: {flog.info['f32_bound']:g}; formula: {flog.info['formula']}")

# A full BRDF on (..., 3) directions, broadcasting one view direction against many lights.
ct = fastbrdf.Model("cook-torrance", d="ggx", g="smith-ggx-correlated", alpha=0.3, f="schlick")
wo = np.array([0.3, 0.0, 0.95])
theta = np.radians(np.arange(0, 90, 15))
wi = np.stack([-np.sin(theta), np.zeros_like(theta), np.cos(theta)], axis=-1)
print("cook-torrance:", np.array2string(ct.eval(wi, wo, precision="f64"), precision=4))

# Importance sampling: wi, weight = f cos / pdf, and the pdf of what was drawn.
u = np.random.default_rng(1).random((100_000, 2))
wi_s, weight, pdf = ct.sample(wo, u)
print(f"MC albedo at wo: {weight.mean():.4f} (strategy {ct.strategies()[0]})")

# The error of an approximation against its reference, as `fastbrdf errors`.
for row in fastbrdf.errors("flog", "pow", n=[10, 100, 1000]):
    print(f"flog vs pow, n={row['n']:g}: max_abs {row['max_abs']:.4f}")

# Albedo, a render (linear float32, H x W x 3) and a shader.
print("lambert albedo:", [round(r["albedo"], 6) for r in fastbrdf.albedo("lambert", angles=[0, 45])["rows"]])
img = fastbrdf.render("flog", n=50, width=64, height=64)
print(f"render: {img.shape} {img.dtype}, peak {img.max():.3f}")
print(fastbrdf.shader("flog", lang="glsl", n=20).splitlines()[0])

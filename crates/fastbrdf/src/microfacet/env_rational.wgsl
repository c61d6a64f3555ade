// WGSL twin of microfacet/env_rational.rs (see microfacet/mod.wgsl): rational fits of the split-sum terms.

/// P(x, y) = c0 + c1 x + c2 y + c3 x y + c4 x^2 + c5 y^2 + c6 x^2 y + c7 x y^2 + c8 x^2 y^2, by
/// Horner in y for each power of x, then in x (as env_rational::poly).
fn fb_env_rational_poly(x: f32, y: f32, c: array<f32, 9>) -> f32 {
    let p0 = y * (y * c[5] + c[2]) + c[0];
    let p1 = y * (y * c[7] + c[3]) + c[1];
    let p2 = y * (y * c[8] + c[6]) + c[4];
    return x * (x * p2 + p1) + p0;
}

/// env-brdf-materialx(-tuned): one term, numerator over denominator, clamped at 0.
fn fb_env_rational(cos_v: f32, alpha: f32, num: array<f32, 9>, den: array<f32, 9>) -> f32 {
    return max(fb_env_rational_poly(cos_v, alpha, num) / fb_env_rational_poly(cos_v, alpha, den), 0.0);
}

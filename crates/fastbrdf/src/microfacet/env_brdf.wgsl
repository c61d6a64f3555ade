// WGSL twin of microfacet/env_brdf.rs (see microfacet/mod.wgsl): the split-sum terms of GGX.

/// Gauss-Legendre, 24 points on [-1, 1]: the positive half of the nodes and their weights
/// (twin: env_brdf::GL24, checked by a test).
const FB_GL24_X = array<f32, 12>(0.9951872f, 0.9747286f, 0.93827456f, 0.88641554f, 0.82000196f, 0.74012417f, 0.64809364f, 0.5454215f, 0.43379351f, 0.31504267f, 0.19111887f, 0.064056896f);
const FB_GL24_W = array<f32, 12>(0.01234123f, 0.02853139f, 0.044277437f, 0.059298586f, 0.07334648f, 0.086190164f, 0.097618654f, 0.10744427f, 0.115505666f, 0.12167047f, 0.12583746f, 0.1279382f);

/// cos(x) for x in [0, pi] as env_brdf::cos_0_pi (the same polynomial).
fn fb_env_cos(x: f32) -> f32 {
    let y = x - 1.5707964;
    let y2 = y * y;
    var p = -1.0 / 6227020800.0;
    p = p * y2 + 1.0 / 39916800.0;
    p = p * y2 - 1.0 / 362880.0;
    p = p * y2 + 1.0 / 5040.0;
    p = p * y2 - 1.0 / 120.0;
    p = p * y2 + 1.0 / 6.0;
    p = p * y2 - 1.0;
    return y * p;
}

/// One u node of env-brdf's rule: the phi integral over the live range (see env_brdf.rs).
/// u and w = 1 - u both given, each without cancellation (see env_brdf.rs).
fn fb_env_ring(u: f32, w: f32, wu: f32, full: bool, mu: f32, alpha: f32, sv: f32, mlv: f32, bias: bool) -> f32 {
    let a2 = alpha * alpha;
    let d = w + a2 * u;
    let ch = sqrt(w / d);
    let sh = alpha * sqrt(u / d);
    var pm = 3.14159265;
    if (!full) {
        let qd = 2.0 * ch * sh * sv;
        var q = mu * ((a2 * u - w) / d);
        q = select(1.0, q / qd, qd > 0.0);
        q = min(max(q, -1.0), 1.0);
        pm = acos(q);
    }
    var acc = 0.0;
    for (var i = 0; i < 12; i++) {
        for (var sgn = -1.0; sgn <= 1.0; sgn += 2.0) {
            let phi = pm * (0.5 * (sgn * FB_GL24_X[i] + 1.0));
            let vh = sv * sh * fb_env_cos(phi) + mu * ch;
            let cl = max(2.0 * vh * ch - mu, 9.094947e-13);
            let tl2 = (1.0 - cl) * (1.0 + cl) / (cl * cl);
            let ll = a2 * tl2 / (2.0 * (sqrt(1.0 + a2 * tl2) + 1.0));
            let g_over_mu = 1.0 / (mu * (1.0 + ll) + mlv);
            let m = max(1.0 - vh, 0.0);
            let f5 = m * m * m * m * m;
            let wf = select(1.0 - f5, f5, bias);
            acc += FB_GL24_W[i] * wf * vh * g_over_mu / ch;
        }
    }
    return acc * pm * 0.5 * wu;
}

/// env-brdf: the split-sum scale (bias = false) or bias of GGX with height-correlated Smith,
/// by the product Gauss-Legendre rule of env_brdf.rs (cos_v in [0, 1], alpha clamped).
fn fb_env_dfg(cos_v: f32, alpha: f32, bias: bool) -> f32 {
    let mu = max(cos_v, 9.536743e-7);
    let a2 = alpha * alpha;
    let sv = sqrt(max((1.0 - mu) * (1.0 + mu), 0.0));
    let mlv = a2 * sv * sv / (2.0 * (sqrt(mu * mu + a2 * sv * sv) + mu));
    let t1 = mu / (1.0 + sv);
    let t12 = t1 * t1;
    let u1 = t12 / (a2 + t12);
    let w1 = a2 / (a2 + t12);
    let u2 = 1.0 / (1.0 + a2 * t12);
    let w2 = a2 * t12 / (1.0 + a2 * t12);
    let du = w1 - w2;
    var sum = 0.0;
    for (var i = 0; i < 12; i++) {
        for (var sgn = -1.0; sgn <= 1.0; sgn += 2.0) {
            let t = 0.5 * (sgn * FB_GL24_X[i] + 1.0);
            let tc = 0.5 * (1.0 - sgn * FB_GL24_X[i]);
            let wt = 0.5 * FB_GL24_W[i];
            sum += fb_env_ring(u1 * t, w1 + u1 * tc, u1 * wt, true, mu, alpha, sv, mlv, bias);
            let tt = du * t * t;
            sum += fb_env_ring(u2 - tt, w2 + tt, du * 2.0 * t * wt, false, mu, alpha, sv, mlv, bias);
        }
    }
    return max(sum * 0.31830988, 0.0);
}

/// env-brdf-approx(-tuned) (Karis 2014, EnvBRDFApprox): k = c0 (4), c1 (4), the exp2 rate,
/// the two output slopes; r = sqrt(alpha); the bias clamped at 0.
fn fb_env_approx(cos_v: f32, alpha: f32, k: array<f32, 11>, bias: bool) -> f32 {
    let r = sqrt(alpha);
    let px = r * k[0] + k[4];
    let py = r * k[1] + k[5];
    let a004 = min(px * px, exp2(k[8] * cos_v)) * px + py;
    let v = select(k[9] * a004 + (r * k[2] + k[6]), k[10] * a004 + (r * k[3] + k[7]), bias);
    return max(v, 0.0);
}

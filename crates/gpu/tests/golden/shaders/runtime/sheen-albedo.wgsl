// fastbrdf 0.1.0 (env): sheen-albedo
// Made by: fastbrdf shader --model sheen-albedo --lang wgsl --runtime-params
//
// Formula: E(mu, alpha) = integral of D_charlie V cos_i over the hemisphere (sheen colour 1), product Gauss-Legendre 48 x 48 in (cos_i, phi); mu in [0.001, 1], alpha in [0.07, 1]
// Source: Estevez and Kulla 2017 (Charlie D and V); Neubelt and Pettineo 2013 (V); KHR_materials_sheen (albedo scaling)
// Note: ops are per quadrature point (2304 points, plus 48 visibility terms); within 1e-4 of adaptive quadrature; the reference of the sheen rows of the DFG ledger
// Parameters (this export: v = charlie):
//   v: the sheen visibility whose albedo: charlie (Estevez and Kulla's fitted Lambda) or neubelt (Neubelt and Pettineo) (one of charlie, neubelt, default charlie)
// Error bounds: none documented (an exact model or a reference).
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Runtime parameters: none (the model has no numeric parameter) (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_sheen_albedo(cos_v, alpha): n.v and the GGX roughness alpha (the look-up table's axes); specular albedo = f0 scale + bias; returns f32.

/// The quadrature's Gauss-Legendre rule on [0, 1], (node, weight) (as sheen::quadrature_nodes,
/// to f32; checked by sheen_albedo's tests).
const FB_SHEEN_GL48 = array<vec2<f32>, 48>(
    vec2<f32>(0.00061449636f, 0.001576673f),
    vec2<f32>(0.0032349138f, 0.003663777f),
    vec2<f32>(0.007937708f, 0.0057386174f),
    vec2<f32>(0.014704204f, 0.007789658f),
    vec2<f32>(0.023506148f, 0.00980808f),
    vec2<f32>(0.034306653f, 0.011785381f),
    vec2<f32>(0.04706043f, 0.013713255f),
    vec2<f32>(0.06171399f, 0.015583614f),
    vec2<f32>(0.07820587f, 0.017388612f),
    vec2<f32>(0.0964669f, 0.019120676f),
    vec2<f32>(0.116420485f, 0.020772541f),
    vec2<f32>(0.13798293f, 0.02233728f),
    vec2<f32>(0.1610638f, 0.023808328f),
    vec2<f32>(0.1855663f, 0.025179518f),
    vec2<f32>(0.21138763f, 0.026445094f),
    vec2<f32>(0.23841952f, 0.027599752f),
    vec2<f32>(0.26654854f, 0.028638646f),
    vec2<f32>(0.29565677f, 0.02955742f),
    vec2<f32>(0.32562205f, 0.03035222f),
    vec2<f32>(0.35631874f, 0.031019712f),
    vec2<f32>(0.3876181f, 0.031557094f),
    vec2<f32>(0.41938883f, 0.03196212f),
    vec2<f32>(0.45149764f, 0.03223308f),
    vec2<f32>(0.48380992f, 0.03236885f),
    vec2<f32>(0.5161901f, 0.03236885f),
    vec2<f32>(0.5485023f, 0.03223308f),
    vec2<f32>(0.58061117f, 0.03196212f),
    vec2<f32>(0.6123819f, 0.031557094f),
    vec2<f32>(0.6436812f, 0.031019712f),
    vec2<f32>(0.6743779f, 0.03035222f),
    vec2<f32>(0.70434326f, 0.02955742f),
    vec2<f32>(0.7334514f, 0.028638646f),
    vec2<f32>(0.76158047f, 0.027599752f),
    vec2<f32>(0.78861237f, 0.026445094f),
    vec2<f32>(0.8144337f, 0.025179518f),
    vec2<f32>(0.8389362f, 0.023808328f),
    vec2<f32>(0.8620171f, 0.02233728f),
    vec2<f32>(0.8835795f, 0.020772541f),
    vec2<f32>(0.9035331f, 0.019120676f),
    vec2<f32>(0.9217941f, 0.017388612f),
    vec2<f32>(0.938286f, 0.015583614f),
    vec2<f32>(0.95293957f, 0.013713255f),
    vec2<f32>(0.96569335f, 0.011785381f),
    vec2<f32>(0.97649384f, 0.00980808f),
    vec2<f32>(0.9852958f, 0.007789658f),
    vec2<f32>(0.9920623f, 0.0057386174f),
    vec2<f32>(0.9967651f, 0.003663777f),
    vec2<f32>(0.9993855f, 0.001576673f)
);

/// mu in [0.001, 1] and alpha in [0.07, 1] (as sheen_albedo::clamp).
fn fb_sheen_e_clamp(mu: f32, alpha: f32) -> vec2<f32> {
    return vec2<f32>(min(max(mu, 0.001), 1.0), min(max(alpha, 0.07), 1.0));
}

/// sheen-albedo: E(mu, alpha) by the 48 x 48 product rule in (cos theta_i, phi), phi on [0, pi]
/// doubled (as sheen::albedo_quadrature, in f32).
fn fb_sheen_e_quadrature(mu_in: f32, alpha_in: f32, charlie: bool) -> f32 {
    let c = fb_sheen_e_clamp(mu_in, alpha_in);
    let mu = c.x;
    let a = c.y;
    let t = (1.0 - a) * (1.0 - a);
    let l = array<f32, 5>(
        21.5473 + (25.3245 - 21.5473) * t,
        3.82987 + (3.32435 - 3.82987) * t,
        0.19823 + (0.16801 - 0.19823) * t,
        -1.97760 + (-1.27393 + 1.97760) * t,
        -4.32054 + (-4.85967 + 4.32054) * t,
    );
    let l_half = fb_sheen_l(0.5, l);
    let norm = (2.0 + 1.0 / a) / 6.2831855;
    let expo = 0.5 / a;
    let so = sqrt(max(1.0 - mu * mu, 0.0));
    // One local copy: a compiler may materialise a constant array once per dynamic access.
    var nodes = FB_SHEEN_GL48;
    var sum = 0.0;
    for (var i = 0; i < 48; i++) {
        let ct = nodes[i].x;
        let st = sqrt(max(1.0 - ct * ct, 0.0));
        var v = fb_sheen_v_neubelt(mu, ct);
        if charlie {
            v = fb_sheen_v_charlie(mu, ct, l, l_half);
        }
        var inner = 0.0;
        for (var j = 0; j < 48; j++) {
            let phi = 3.1415927 * nodes[j].x;
            let hx = st * cos(phi) + so;
            let hy = st * sin(phi);
            let hz = ct + mu;
            let s2 = hx * hx + hy * hy;
            inner += nodes[j].y * fb_sheen_d(s2 / (s2 + hz * hz), norm, expo);
        }
        sum += nodes[i].y * v * ct * inner;
    }
    return sum * 6.2831855;
}

fn fb_sheen_d(sin2_h: f32, norm: f32, expo: f32) -> f32 {
    return norm * pow(max(sin2_h, 0.0), expo);
}

fn fb_sheen_l(x: f32, l: array<f32, 5>) -> f32 {
    return l[0] / (1.0 + l[1] * pow(max(x, 0.0), l[2])) + l[3] * x + l[4];
}

fn fb_sheen_lambda(mu: f32, l: array<f32, 5>, l_half: f32) -> f32 {
    if mu < 0.5 {
        return exp(fb_sheen_l(mu, l));
    }
    return exp(2.0 * l_half - fb_sheen_l(1.0 - mu, l));
}

fn fb_sheen_v_charlie(cos_o: f32, cos_i: f32, l: array<f32, 5>, l_half: f32) -> f32 {
    let s = 1.0 + (fb_sheen_lambda(cos_o, l, l_half) + fb_sheen_lambda(cos_i, l, l_half));
    return 1.0 / (s * (4.0 * (cos_o * cos_i)));
}

fn fb_sheen_v_neubelt(cos_o: f32, cos_i: f32) -> f32 {
    return 1.0 / (4.0 * (cos_i + cos_o - cos_i * cos_o));
}

/// sheen-albedo: E(mu, alpha) = integral of D_charlie V cos_i over the hemisphere (sheen colour 1), product Gauss-Legendre 48 x 48 in (cos_i, phi); mu in [0.001, 1], alpha in [0.07, 1]
/// Source: Estevez and Kulla 2017 (Charlie D and V); Neubelt and Pettineo 2013 (V); KHR_materials_sheen (albedo scaling). Instance: runtime parameters none; fixed: v = charlie.
fn fb_sheen_albedo(cos_v: f32, alpha: f32) -> f32 {
    let v = select(0.0, min(cos_v, 1.0), cos_v > 0.0);
    let a = select(0.005f, min(alpha, 1.0f), alpha > 0.005f);
    return fb_sheen_e_quadrature(v, a, true);
}

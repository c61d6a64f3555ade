//! The explorer's fixed plot grids (the in-plane polar plot, the theta_h x theta_d slice, the
//! lobe and error curves' abscissae) and the luminance the plots show of RGB values: a leaf
//! that the plots of registry models (`plots.rs`) and of users' models (`user.rs`) share.

/// Points of the in-plane polar plot, of the lobe and error curves, and the side of the
/// theta_h x theta_d slice: fixed on the server, not requested.
pub(super) const POLAR_POINTS: usize = 181;
const CURVE_POINTS: usize = 256;
pub(super) const SLICE: usize = 48;

/// The direction pairs of the in-plane polar plot at incidence `ti_deg`: theta_o from -90 (the
/// incident side: wi is at -theta_i) to 90 degrees (the mirror direction is at +theta_i).
pub(super) fn polar_pairs(ti_deg: f64) -> Vec<([f64; 3], [f64; 3])> {
    let ti = ti_deg.to_radians();
    let wi = [ti.sin(), 0.0, ti.cos()];
    (0..POLAR_POINTS)
        .map(|k| {
            let t = -90.0 + 180.0 * k as f64 / (POLAR_POINTS - 1) as f64;
            let r = t.to_radians();
            (wi, [-r.sin(), 0.0, r.cos()])
        })
        .collect()
}

/// The direction pairs of the theta_h x theta_d slice at phi_d = 90 degrees (rows theta_d,
/// columns theta_h).
pub(super) fn slice_pairs() -> Vec<([f64; 3], [f64; 3])> {
    let mut slice = Vec::with_capacity(SLICE * SLICE);
    for jd in 0..SLICE {
        let td = (jd as f64 + 0.5) / SLICE as f64 * std::f64::consts::FRAC_PI_2;
        for jh in 0..SLICE {
            let th = (jh as f64 + 0.5) / SLICE as f64 * std::f64::consts::FRAC_PI_2;
            // d in h's frame (phi_d = 90 degrees), rotated by theta_h about y.
            let d = [0.0, td.sin(), td.cos()];
            let (s, c) = th.sin_cos();
            let wi = [c * d[0] + s * d[2], d[1], -s * d[0] + c * d[2]];
            let h = [s, 0.0, c];
            let k = 2.0 * (h[0] * wi[0] + h[1] * wi[1] + h[2] * wi[2]);
            let wo = [k * h[0] - wi[0], k * h[1] - wi[1], k * h[2] - wi[2]];
            slice.push((wi, wo));
        }
    }
    slice
}

/// Rec. 709 luminance of an RGB BRDF value: what the plots show of measured data.
pub(super) fn luminance(c: [f64; 3]) -> f64 {
    0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
}

/// The lobe and error curves' abscissae, degrees.
pub(super) fn curve_theta() -> Vec<f64> {
    (0..CURVE_POINTS)
        .map(|k| 89.9 * k as f64 / (CURVE_POINTS - 1) as f64)
        .collect()
}

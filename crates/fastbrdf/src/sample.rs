//! Importance sampling of the full BRDFs (issue 15): the shared pieces.
//!
//! Every BRDF family samples in its own file (`BrdfForm::strategies`, `sample_wi`, `pdf_wi`);
//! the densities they draw from are written here once, generic over the precision:
//! - [`cosine`]: the cosine-weighted hemisphere (`pdf = cos theta / pi`), valid for every BRDF;
//! - [`CosDist`]: a density of a cosine `c` in [0, 1] about an axis with uniform azimuth
//!   (solid-angle pdf `pdf_c(c) / (2 pi)`), inverted in closed form: `c^m` (`pow`,
//!   `beckmann-pow`, `ward-pow`), the power-g forms `max(0, 1 + s (c - 1))^g`, and
//!   exponentials `exp(r (c - 1))` (`sg` and its `exp2` relatives). Lobes declare theirs
//!   (`LobeForm::cos_dist`); a lobe without one samples its exact twin `pow` at the same `n`;
//! - [`Micro`]: the exact (anisotropic) Beckmann and GGX distributions of normals, sampled by
//!   `D cos theta_h` (Walter et al. 2007; Walter 2005's note for Ward is Beckmann's) or by
//!   their visible normals (GGX: Heitz 2018; Beckmann: Heitz & d'Eon 2014 as in Mitsuba,
//!   [`Micro::sample_vndf`]).
//!
//! A half vector `h` drawn with solid-angle density `p_h` gives `wi = 2 (wo.h) h - wo` with
//! `pdf(wi) = p_h / (4 wo.h)`; `h` with `wo.h <= 0` is no sample (it would be counted under the
//! other half vector `-h`, whose density is 0). Directions below `COS_MIN` are no sample:
//! their probability is the strategy's missing mass, and `pdf` integrates over the upper
//! hemisphere to 1 minus it. The weight `f cos_i / pdf` is computed with the model's own
//! evaluation ([`crate::model::Brdf::sample`]), so it is exact for the model whatever was
//! sampled.

use crate::real::Real;
use crate::vec3::{V3, dot};
use std::fmt;

/// How a BRDF draws `wi` given `wo` (`fastbrdf sample --strategy`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Strategy {
    /// The model's default: the first of its [`crate::model::Brdf::strategies`].
    Auto,
    /// Cosine-weighted hemisphere (every BRDF).
    Cosine,
    /// The model's own lobe, inverted in closed form (Phong around the mirror, Blinn-Phong's
    /// half vector, `ward-pow`'s and `beckmann-pow`'s `cos^e`).
    Lobe,
    /// Half vector from `D cos theta_h` (Beckmann, GGX, Ward: Walter 2005).
    DCos,
    /// Half vector from the visible normals of `wo` (GGX: Heitz 2018; Beckmann: Heitz &
    /// d'Eon 2014).
    Vndf,
    /// The exact twin's sampling (`pow` for lobes without a closed-form inverse, Beckmann for
    /// the power forms of D and Ward), weighted by `f / pdf`.
    Twin,
}

impl Strategy {
    /// Every strategy, `auto` first.
    pub const ALL: [Strategy; 6] = [
        Strategy::Auto,
        Strategy::Cosine,
        Strategy::Lobe,
        Strategy::DCos,
        Strategy::Vndf,
        Strategy::Twin,
    ];
    /// The CLI's name.
    pub fn name(self) -> &'static str {
        match self {
            Strategy::Auto => "auto",
            Strategy::Cosine => "cosine",
            Strategy::Lobe => "lobe",
            Strategy::DCos => "d-cos",
            Strategy::Vndf => "vndf",
            Strategy::Twin => "twin",
        }
    }
    /// The strategy of a CLI name.
    pub fn parse(s: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|x| x.name() == s)
    }
}

impl fmt::Display for Strategy {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// One sample of `wi` given `wo`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample<T> {
    /// Unit incident direction, above `COS_MIN`.
    pub wi: V3<T>,
    /// `f(wi, wo) cos theta_i / pdf`.
    pub weight: T,
    /// The solid-angle density of `wi` (equal to `pdf(wo, wi)`).
    pub pdf: T,
}

/// `2 pi`.
fn two_pi<T: Real>() -> T {
    T::c(std::f64::consts::TAU)
}

/// `u` kept inside [0, 1) (an f32 rounding of an f64 number may reach 1).
#[inline]
pub fn unit_interval<T: Real>(u: T) -> T {
    let below = T::one() - T::epsilon();
    if u >= T::zero() {
        u.min(below)
    } else {
        T::zero()
    }
}

/// An orthonormal frame `(t, b)` completing the unit `axis` (Duff et al. 2017).
pub fn frame<T: Real>(n: V3<T>) -> (V3<T>, V3<T>) {
    let sign = if n[2] >= T::zero() {
        T::one()
    } else {
        -T::one()
    };
    let a = -T::one() / (sign + n[2]);
    let b = n[0] * n[1] * a;
    (
        [T::one() + sign * n[0] * n[0] * a, sign * b, -sign * n[0]],
        [b, sign + n[1] * n[1] * a, -n[1]],
    )
}

/// The direction at cosine `c` from `axis` and azimuth `2 pi u` about it.
pub fn about<T: Real>(axis: V3<T>, c: T, u: T) -> V3<T> {
    let c = c.max(-T::one()).min(T::one());
    let s = ((T::one() - c) * (T::one() + c)).max(T::zero()).sqrt();
    let (sp, cp) = (two_pi::<T>() * u).sin_cos();
    let (t, b) = frame(axis);
    let mut w = [T::zero(); 3];
    for k in 0..3 {
        w[k] = s * (cp * t[k] + sp * b[k]) + c * axis[k];
    }
    w
}

/// Cosine-weighted hemisphere about +z.
pub fn cosine<T: Real>(u: [T; 2]) -> V3<T> {
    let u = u.map(unit_interval);
    about(
        [T::zero(), T::zero(), T::one()],
        (T::one() - u[0]).sqrt(),
        u[1],
    )
}

/// Its density, `cos theta / pi` (0 below the horizon).
pub fn cosine_pdf<T: Real>(wi: V3<T>) -> T {
    wi[2].max(T::zero()) * T::FRAC_1_PI()
}

/// `wi = 2 (wo.h) h - wo`, or `None` when `wo.h <= 0`.
pub fn reflect_about<T: Real>(wo: V3<T>, h: V3<T>) -> Option<V3<T>> {
    let d = dot(wo, h);
    if !(d > T::zero()) {
        return None;
    }
    let k = d + d;
    Some([k * h[0] - wo[0], k * h[1] - wo[1], k * h[2] - wo[2]])
}

/// The half vector of unit `wi`, `wo` and `wo.h`, or `None` when it is not in the upper
/// hemisphere or `wo.h <= 0`.
pub fn half<T: Real>(wo: V3<T>, wi: V3<T>) -> Option<(V3<T>, T)> {
    let s = [wi[0] + wo[0], wi[1] + wo[1], wi[2] + wo[2]];
    let h = crate::vec3::normalize(s)?;
    let d = dot(wo, h);
    (h[2] > T::zero() && d > T::zero()).then_some((h, d))
}

/// A density of the cosine `c` in [0, 1] about an axis, azimuth uniform: solid-angle pdf
/// `pdf_c(c) / (2 pi)`. Each is proportional to a lobe and inverted in closed form.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CosDist {
    /// `(m + 1) c^m`, `m > -1`: `c = u^(1 / (m + 1))`.
    Pow { m: f64 },
    /// `max(0, 1 + s (c - 1))^g` normalised (power-g forms): with `x = 1 + s (c - 1)` from
    /// `x0 = max(0, 1 - s)` to 1, `x = (x0^(g+1) + u (1 - x0^(g+1)))^(1/(g+1))`.
    PowerG { s: f64, g: f64 },
    /// `exp(r (c - 1))` normalised (spherical Gaussians):
    /// `c = 1 + ln(e^-r + u (1 - e^-r)) / r`.
    Exp { r: f64 },
}

impl CosDist {
    /// The cosine for `u` in [0, 1).
    pub fn sample<T: Real>(&self, u: T) -> T {
        let u = unit_interval(u);
        let one = T::one();
        let c = match *self {
            CosDist::Pow { m } => u.powf(T::c(1.0 / (m + 1.0))),
            CosDist::PowerG { s, g } => {
                let a = (1.0 - s).max(0.0).powf(g + 1.0);
                let x = (T::c(a) + u * T::c(1.0 - a)).powf(T::c(1.0 / (g + 1.0)));
                one + (x - one) / T::c(s)
            }
            CosDist::Exp { r } => {
                let e = (-r).exp();
                one + (T::c(e) + u * T::c(-(-r).exp_m1())).ln() / T::c(r)
            }
        };
        c.max(T::zero()).min(one)
    }

    /// The density of `c` on [0, 1] (0 outside).
    pub fn pdf<T: Real>(&self, c: T) -> T {
        // A unit-vector dot product may round above 1.
        if !(c >= T::zero() && c <= T::c(1.0 + 1e-6)) {
            return T::zero();
        }
        let c = c.min(T::one());
        match *self {
            CosDist::Pow { m } => T::c(m + 1.0) * c.powf(T::c(m)),
            CosDist::PowerG { s, g } => {
                let a = (1.0 - s).max(0.0).powf(g + 1.0);
                let x = (T::one() + T::c(s) * (c - T::one())).max(T::zero());
                T::c(s * (g + 1.0) / (1.0 - a)) * x.powf(T::c(g))
            }
            CosDist::Exp { r } => T::c(r / -(-r).exp_m1()) * (T::c(r) * (c - T::one())).exp(),
        }
    }

    /// A direction about `axis` (unit) for `u`.
    pub fn sample_dir<T: Real>(&self, axis: V3<T>, u: [T; 2]) -> V3<T> {
        about(axis, self.sample(u[0]), unit_interval(u[1]))
    }

    /// The solid-angle density of the unit direction `w` about `axis`.
    pub fn pdf_dir<T: Real>(&self, axis: V3<T>, w: V3<T>) -> T {
        self.pdf(dot(axis, w)) / two_pi::<T>()
    }
}

/// The exact distributions of normals that sampling draws from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MicroKind {
    Beckmann,
    Ggx,
}

/// An exact, normalised, possibly anisotropic distribution of normals (slopes `ax`, `ay`
/// along the frame's x and y): what `D cos` and visible-normal sampling draw from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Micro {
    pub kind: MicroKind,
    pub ax: f64,
    pub ay: f64,
}

impl Micro {
    /// `(h_x^2 / ax^2 + h_y^2 / ay^2) / h_z^2 = tan^2 theta_h / alpha(phi)^2`.
    fn slope2<T: Real>(&self, h: V3<T>) -> T {
        let (ax, ay) = (T::c(self.ax), T::c(self.ay));
        ((h[0] / ax) * (h[0] / ax) + (h[1] / ay) * (h[1] / ay)) / (h[2] * h[2])
    }

    /// The normalised `D(h)` (`integral D cos theta_h = 1`); 0 below the horizon.
    pub fn d<T: Real>(&self, h: V3<T>) -> T {
        if !(h[2] > T::zero()) {
            return T::zero();
        }
        let q = self.slope2(h);
        let c2 = h[2] * h[2];
        let k = T::c(1.0 / (std::f64::consts::PI * self.ax * self.ay));
        match self.kind {
            MicroKind::Beckmann => k * (-q).exp() / (c2 * c2),
            MicroKind::Ggx => {
                let t = c2 * (T::one() + q);
                k / (t * t)
            }
        }
    }

    /// A half vector with density `D(h) cos theta_h` (Walter et al. 2007, anisotropic as
    /// pbrt: the azimuth `atan(ay/ax tan(2 pi u2))`, then `tan^2 theta_h`).
    pub fn sample_dcos<T: Real>(&self, u: [T; 2]) -> V3<T> {
        let u = u.map(unit_interval);
        let (sp, cp) = (two_pi::<T>() * u[1]).sin_cos();
        let (ax, ay) = (T::c(self.ax), T::c(self.ay));
        let (x, y) = (ax * cp, ay * sp);
        let r = (x * x + y * y).sqrt();
        let (cphi, sphi) = (x / r, y / r);
        // 1 / alpha(phi)^2.
        let inv_a2 = (cphi / ax) * (cphi / ax) + (sphi / ay) * (sphi / ay);
        let tan2 = match self.kind {
            MicroKind::Beckmann => -(-u[0]).ln_1p() / inv_a2,
            MicroKind::Ggx => u[0] / (T::one() - u[0]) / inv_a2,
        };
        let c = T::one() / (T::one() + tan2).sqrt();
        let s = (tan2 / (T::one() + tan2)).sqrt();
        [s * cphi, s * sphi, c]
    }

    /// The solid-angle density of [`Self::sample_dcos`]'s `h`.
    pub fn pdf_dcos<T: Real>(&self, h: V3<T>) -> T {
        self.d(h) * h[2].max(T::zero())
    }

    /// Smith's `Lambda` of the direction `w` (unit, `w_z > 0`).
    pub fn lambda<T: Real>(&self, w: V3<T>) -> T {
        let (ax, ay) = (T::c(self.ax), T::c(self.ay));
        // alpha^2 tan^2 theta of w.
        let a2t2 = ((w[0] * ax) * (w[0] * ax) + (w[1] * ay) * (w[1] * ay)) / (w[2] * w[2]);
        match self.kind {
            MicroKind::Ggx => ((T::one() + a2t2).sqrt() - T::one()) * T::c(0.5),
            MicroKind::Beckmann => {
                if !(a2t2 > T::zero()) {
                    return T::zero();
                }
                let a = T::one() / a2t2.sqrt();
                let half = T::c(0.5);
                (a.erf() - T::one()) * half
                    + (-(a * a)).exp() * half / (a * T::c(std::f64::consts::PI.sqrt()))
            }
        }
    }

    /// The masking term `G1(w) = 1 / (1 + Lambda(w))`.
    pub fn g1<T: Real>(&self, w: V3<T>) -> T {
        T::one() / (T::one() + self.lambda(w))
    }

    /// A visible normal of `wo` (unit, `wo_z > 0`): density `G1(wo) max(0, wo.h) D(h) / wo_z`.
    /// GGX: Heitz 2018, "Sampling the GGX Distribution of Visible Normals" (JCGT 7(4)).
    /// Beckmann: the visible slopes of Heitz & d'Eon 2014 as Mitsuba 0.5 implements them
    /// (`sampleVisible11`: Newton's method on the slope CDF in the erf domain).
    pub fn sample_vndf<T: Real>(&self, wo: V3<T>, u: [T; 2]) -> V3<T> {
        let u = u.map(unit_interval);
        let (ax, ay) = (T::c(self.ax), T::c(self.ay));
        let one = T::one();
        let zero = T::zero();
        match self.kind {
            MicroKind::Ggx => {
                let vh = crate::vec3::normalize([ax * wo[0], ay * wo[1], wo[2]])
                    .unwrap_or([zero, zero, one]);
                let lensq = vh[0] * vh[0] + vh[1] * vh[1];
                let t1 = if lensq > zero {
                    let inv = one / lensq.sqrt();
                    [-vh[1] * inv, vh[0] * inv, zero]
                } else {
                    [one, zero, zero]
                };
                let t2 = [
                    vh[1] * t1[2] - vh[2] * t1[1],
                    vh[2] * t1[0] - vh[0] * t1[2],
                    vh[0] * t1[1] - vh[1] * t1[0],
                ];
                let r = u[0].sqrt();
                let (sp, cp) = (two_pi::<T>() * u[1]).sin_cos();
                let p1 = r * cp;
                let p2 = r * sp;
                let s = T::c(0.5) * (one + vh[2]);
                let p2 = (one - s) * (one - p1 * p1).max(zero).sqrt() + s * p2;
                let pz = (one - p1 * p1 - p2 * p2).max(zero).sqrt();
                let nh = [
                    p1 * t1[0] + p2 * t2[0] + pz * vh[0],
                    p1 * t1[1] + p2 * t2[1] + pz * vh[1],
                    p1 * t1[2] + p2 * t2[2] + pz * vh[2],
                ];
                crate::vec3::normalize([ax * nh[0], ay * nh[1], nh[2].max(zero)])
                    .unwrap_or([zero, zero, one])
            }
            MicroKind::Beckmann => {
                // Stretch wo to the unit-roughness configuration, sample the slopes there,
                // rotate them to wo's azimuth, unstretch.
                let w = crate::vec3::normalize([ax * wo[0], ay * wo[1], wo[2]])
                    .unwrap_or([zero, zero, one]);
                let (sx, sy) = beckmann_visible_slopes(w[2].f64(), u[0].f64(), u[1].f64());
                let r = (w[0] * w[0] + w[1] * w[1]).sqrt();
                let (cphi, sphi) = if r > zero {
                    (w[0] / r, w[1] / r)
                } else {
                    (one, zero)
                };
                let (sx, sy) = (T::c(sx), T::c(sy));
                let mx = (cphi * sx - sphi * sy) * ax;
                let my = (sphi * sx + cphi * sy) * ay;
                crate::vec3::normalize([-mx, -my, one]).unwrap_or([zero, zero, one])
            }
        }
    }

    /// The solid-angle density of [`Self::sample_vndf`]'s `h` given `wo`.
    pub fn pdf_vndf<T: Real>(&self, wo: V3<T>, h: V3<T>) -> T {
        let d = dot(wo, h);
        if !(d > T::zero() && wo[2] > T::zero()) {
            return T::zero();
        }
        self.g1(wo) * d * self.d(h) / wo[2]
    }
}

/// `erf^-1(x)` for `x` in (-1, 1): Giles' single-precision approximation refined by two
/// Newton steps on `erf` (double precision).
fn erfinv(x: f64) -> f64 {
    let x = x.clamp(-1.0 + 1e-16, 1.0 - 1e-16);
    let w = -((1.0 - x) * (1.0 + x)).ln();
    let mut p;
    if w < 5.0 {
        let w = w - 2.5;
        p = 2.810_226_36e-08;
        for c in [
            3.432_739_39e-07,
            -3.523_387_7e-06,
            -4.391_506_54e-06,
            0.000_218_580_87,
            -0.001_253_725_03,
            -0.004_177_681_64,
            0.246_640_727,
            1.501_409_41,
        ] {
            p = c + p * w;
        }
    } else {
        let w = w.sqrt() - 3.0;
        p = -0.000_200_214_257;
        for c in [
            0.000_100_950_558,
            0.001_349_343_22,
            -0.003_673_428_44,
            0.005_739_507_73,
            -0.007_622_461_3,
            0.009_438_870_47,
            1.001_674_06,
            2.832_976_82,
        ] {
            p = c + p * w;
        }
    }
    let mut y = p * x;
    for _ in 0..2 {
        let e = libm::erf(y) - x;
        y -= e / (std::f64::consts::FRAC_2_SQRT_PI * (-y * y).exp());
    }
    y
}

/// Visible slopes of the unit-roughness Beckmann distribution seen at `cos_theta`
/// (Heitz & d'Eon 2014; Mitsuba 0.5's `sampleVisible11`, with a bracketed Newton search
/// run to 1e-12 rather than 1e-5 so that the density is exact to the chi-square test's
/// resolution). Slopes of the facing microfacet, in the frame where `wo` has azimuth 0.
fn beckmann_visible_slopes(cos_theta: f64, u1: f64, u2: f64) -> (f64, f64) {
    let inv_sqrt_pi = 1.0 / std::f64::consts::PI.sqrt();
    let u1 = u1.max(1e-12);
    let u2 = u2.clamp(1e-12, 1.0 - 1e-12);
    if cos_theta > 0.99999 {
        let r = (-(1.0 - u1).ln()).sqrt();
        let (s, c) = (std::f64::consts::TAU * u2).sin_cos();
        return (r * c, r * s);
    }
    let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    let tan_theta = sin_theta / cos_theta;
    let cot_theta = 1.0 / tan_theta;
    // Search in the erf domain: b = erf(slope_x).
    let mut a = -1.0;
    let mut c = libm::erf(cot_theta);
    let theta = cos_theta.acos();
    let fit = 1.0 + theta * (-0.876 + theta * (0.4265 - 0.0594 * theta));
    let mut b = c - (1.0 + c) * (1.0 - u1).powf(fit);
    let norm = 1.0 / (1.0 + c + inv_sqrt_pi * tan_theta * (-cot_theta * cot_theta).exp());
    for _ in 0..100 {
        if !(b >= a && b <= c) {
            b = 0.5 * (a + c);
        }
        let inv = erfinv(b);
        let value = norm * (1.0 + b + inv_sqrt_pi * tan_theta * (-inv * inv).exp()) - u1;
        let deriv = norm * (1.0 - inv * tan_theta);
        if value.abs() < 1e-13 || (c - a) < 1e-15 {
            break;
        }
        if value > 0.0 {
            c = b;
        } else {
            a = b;
        }
        b -= value / deriv;
    }
    (erfinv(b), erfinv(2.0 * u2 - 1.0))
}

/// A small deterministic generator (SplitMix64) for tests and the chi-square harness.
#[derive(Clone, Debug)]
pub struct Rng(u64);

impl Rng {
    /// Seeded.
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }
    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// A number in [0, 1) with 53 random bits.
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
    /// Two of them.
    pub fn pair(&mut self) -> [f64; 2] {
        [self.uniform(), self.uniform()]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strategy_names_round_trip() {
        for s in Strategy::ALL {
            assert_eq!(Strategy::parse(s.name()), Some(s));
        }
        assert_eq!(Strategy::parse("fast"), None);
    }

    #[test]
    fn erfinv_inverts_erf() {
        for x in [-0.999999, -0.9, -0.3, 0.0, 0.1, 0.5, 0.99, 0.9999999] {
            let y = erfinv(x);
            assert!((libm::erf(y) - x).abs() < 1e-14, "{x}: {y}");
        }
    }

    #[test]
    fn cos_dists_invert_their_cdf() {
        for d in [
            CosDist::Pow { m: 20.0 },
            CosDist::Pow { m: -0.5 },
            CosDist::PowerG { s: 5.0, g: 4.0 },
            CosDist::PowerG { s: 0.5, g: 16.0 },
            CosDist::Exp { r: 30.0 },
            CosDist::Exp { r: 2000.0 },
        ] {
            // The density integrates to 1 and its CDF at sample(u) is u.
            let (total, _) = crate::quad::integrate(|c| d.pdf(c), 0.0, 1.0, &[], 1e-12);
            assert!((total - 1.0).abs() < 1e-9, "{d:?}: {total}");
            for u in [0.01, 0.3, 0.7, 0.99] {
                let c: f64 = d.sample(u);
                let (cdf, _) = crate::quad::integrate(|x| d.pdf(x), 0.0, c, &[], 1e-12);
                assert!((cdf - u).abs() < 1e-8, "{d:?} u={u}: {cdf}");
            }
        }
    }
}

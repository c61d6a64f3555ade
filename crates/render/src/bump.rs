//! Procedural micro-relief: a height field `depth * fbm(scale * p)` of 3-D value noise (three
//! octaves), turned into a normal perturbation by finite differences along the tangent plane.
//! It stands in for the offset structure of skin (seed 000). Written by hand: 40 lines, no
//! dependency, deterministic.

use glam::Vec3;

/// Micro-relief parameters.
#[derive(Clone, Copy, Debug)]
pub struct Bump {
    /// Features per unit length.
    pub scale: f32,
    /// Height amplitude, in units of the feature size.
    pub depth: f32,
}

fn hash(i: i32, j: i32, k: i32) -> f32 {
    let mut h = (i as u32).wrapping_mul(0x8da6_b343)
        ^ (j as u32).wrapping_mul(0xd816_3841)
        ^ (k as u32).wrapping_mul(0xcb1a_b31f);
    h ^= h >> 13;
    h = h.wrapping_mul(0x5bd1_e995);
    h ^= h >> 15;
    (h & 0x00ff_ffff) as f32 / 16_777_215.0
}

fn smooth(t: f32) -> f32 {
    t * t * (3.0 - 2.0 * t)
}

/// Value noise in [0, 1].
pub fn noise(p: Vec3) -> f32 {
    let f = p.floor();
    let (i, j, k) = (f.x as i32, f.y as i32, f.z as i32);
    let t = p - f;
    let (u, v, w) = (smooth(t.x), smooth(t.y), smooth(t.z));
    let lerp = |a: f32, b: f32, t: f32| a + (b - a) * t;
    let x00 = lerp(hash(i, j, k), hash(i + 1, j, k), u);
    let x10 = lerp(hash(i, j + 1, k), hash(i + 1, j + 1, k), u);
    let x01 = lerp(hash(i, j, k + 1), hash(i + 1, j, k + 1), u);
    let x11 = lerp(hash(i, j + 1, k + 1), hash(i + 1, j + 1, k + 1), u);
    lerp(lerp(x00, x10, v), lerp(x01, x11, v), w)
}

impl Bump {
    /// The height at `p` (three octaves).
    pub fn height(&self, p: Vec3) -> f32 {
        let q = p * self.scale;
        (noise(q) + 0.5 * noise(q * 2.03 + 17.0) + 0.25 * noise(q * 4.07 + 31.0)) / 1.75
            * self.depth
            / self.scale
    }

    /// The perturbed unit normal at `p` with unit normal `n`.
    pub fn perturb(&self, p: Vec3, n: Vec3) -> Vec3 {
        let (t, b) = n.any_orthonormal_pair();
        let eps = 0.25 / self.scale;
        let dt = (self.height(p + eps * t) - self.height(p - eps * t)) / (2.0 * eps);
        let db = (self.height(p + eps * b) - self.height(p - eps * b)) / (2.0 * eps);
        (n - dt * t - db * b).normalize_or(n)
    }
}

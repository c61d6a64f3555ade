//! The PCG hash the renderer seeds its samples and procedural textures with: a leaf module,
//! so that `env` (sample seeds) and `texture` (the procedural skin) share it without
//! importing each other.

/// The PCG hash of `x` (Jarzynski and Olano 2020).
pub fn pcg(x: u32) -> u32 {
    let s = x.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
    let w = ((s >> ((s >> 28) + 4)) ^ s).wrapping_mul(277_803_737);
    (w >> 22) ^ w
}

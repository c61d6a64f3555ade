//! A glTF material's textures other than its base colour, for the CPU renderer: metallic and
//! roughness (`metallicRoughnessTexture`), the tangent-space normal (`normalTexture`), ambient
//! occlusion (`occlusionTexture`) and emission (`emissiveFactor`, `emissiveTexture`,
//! `KHR_materials_emissive_strength`).
//!
//! # How a textured parameter is shaded
//!
//! - Metallic: `gltf-pbr` mixes its dielectric and metal layers by `metallic`, so it is affine
//!   in it: the value at a hit is `(1 - m) f(metallic 0) + m f(metallic 1)`, exact (as the base
//!   colour texture's `Specular::tint`, which each of the two models carries).
//! - Roughness is not affine: the models are built per roughness level, `k / LEVELS` for `k` in
//!   `0..=LEVELS` ([`LEVELS`] = 256), each when first needed (at most `2 (LEVELS + 1)` models
//!   per material, each its channels' kernels and the tint's: tens of kilobytes, so a few
//!   megabytes per material at worst), and a hit takes the level nearest its roughness
//!   `roughnessFactor x texel`: the roughness shaded differs from the texture's by at most
//!   `1 / 512`, half an 8-bit texel's own step (`1 / 255`).
//! - BRDF sampling under the environment light keeps the material's own model (its factors):
//!   the estimate stays unbiased (each draw is weighted by that sampler's own density), only
//!   its variance grows where the texture moves the roughness far from the factor.
//! - Normal: `n = normalize(T x s + B y s + N z)` with `(x, y, z) = 2 texel - 1`, `s` the
//!   `scale`, `B = (N x T) w`, the specification's rule; on a back face T, B and N are all
//!   reversed (as the Khronos sample viewer does). A perturbed normal facing away from the
//!   viewer falls back to the smooth one, as the micro-relief does.
//! - Occlusion: `1 + strength (texel - 1)` scales the light that is not punctual (the
//!   environment and the ambient term), as the specification asks.
//! - Emission: `emissiveFactor x strength x texel` (sRGB texels made linear) is added once per
//!   primary sample.
//!
//! Texels are read with the albedo texture's bilinear rule (`Texture::sample`); the data
//! textures (metallic-roughness, normal, occlusion) are stored linear, not sRGB-decoded.

use crate::error::Result;
use crate::specular::{Specular, Tint};
use crate::texture::Texture;
use fastbrdf::{Given, ModelSpec};
use glam::{Vec2, Vec3, Vec4};
use std::sync::{Arc, OnceLock};

/// Roughness levels per unit of roughness (see the module's documentation).
pub const LEVELS: u32 = 256;

/// The textures of a material beyond its base colour; each optional.
#[derive(Default)]
pub struct SurfaceMaps {
    pub metallic_roughness: Option<MetallicRoughness>,
    pub normal: Option<NormalMap>,
    pub occlusion: Option<Occlusion>,
    pub emissive: Option<Emissive>,
}

/// A metallic-roughness texture (G roughness, B metallic, linear) and the models it selects.
pub struct MetallicRoughness {
    pub texture: Arc<Texture>,
    /// `metallicFactor` and `roughnessFactor`, which the texels scale.
    pub metallic: f32,
    pub roughness: f32,
    /// The material's spec (the factors, the shortcut choices).
    spec: ModelSpec,
    /// The base colour texture, which every level's models carry as their tint.
    tint: Option<Arc<Texture>>,
    /// Per level, the models at metallic 0 and 1, built when first needed.
    levels: Vec<OnceLock<[Arc<Specular>; 2]>>,
}

/// A tangent-space normal texture (linear) and its `scale`.
pub struct NormalMap {
    pub texture: Arc<Texture>,
    pub scale: f32,
}

/// An occlusion texture (R, linear) and its `strength`.
pub struct Occlusion {
    pub texture: Arc<Texture>,
    pub strength: f32,
}

/// Emission: `factor` (emissiveFactor x emissive strength) times the texture's linear texel.
pub struct Emissive {
    pub factor: Vec3,
    pub texture: Option<Arc<Texture>>,
}

/// The specular term of `spec`, tinted by the base colour texture `tint` when there is one
/// (the model at base colour 0 beside it, `Specular::tint`).
pub fn tinted_specular(spec: &ModelSpec, tint: Option<&Arc<Texture>>) -> Result<Specular> {
    let mut sp = Specular::new(spec)?;
    if let Some(texture) = tint {
        let zero = spec.with("base_color", Given::Num(0.0))?;
        sp.tint = Some(Tint {
            texture: texture.clone(),
            zero: Arc::new(Specular::new(&zero)?),
        });
    }
    Ok(sp)
}

impl MetallicRoughness {
    /// The texture with the material's spec `spec` (its `metallic` and `roughness` are the
    /// factors) and base colour texture `tint`. The models of the lowest and highest levels
    /// are built here, so that a spec the model refuses fails now, not while rendering.
    pub fn new(
        texture: Arc<Texture>,
        spec: &ModelSpec,
        tint: Option<Arc<Texture>>,
    ) -> Result<Self> {
        let factor = |name: &str| spec.channels()[0].num(name) as f32;
        let mr = Self {
            texture,
            metallic: factor("metallic"),
            roughness: factor("roughness"),
            spec: spec.clone(),
            tint,
            levels: (0..=LEVELS).map(|_| OnceLock::new()).collect(),
        };
        mr.build(0)?;
        mr.build(LEVELS)?;
        Ok(mr)
    }

    /// The (metallic, roughness level) at texture coordinates `uv`.
    pub fn at(&self, uv: Vec2) -> (f32, u32) {
        let t = self.texture.sample(uv);
        let m = (self.metallic * t.z).clamp(0.0, 1.0);
        let r = (self.roughness * t.y).clamp(0.0, 1.0);
        (m, (r * LEVELS as f32).round() as u32)
    }

    /// The models at metallic 0 and 1 of roughness level `level`.
    pub fn models(&self, level: u32) -> &[Arc<Specular>; 2] {
        let slot = &self.levels[level.min(LEVELS) as usize];
        if let Some(m) = slot.get() {
            return m;
        }
        let built = self
            .build(level)
            .expect("the model accepts every roughness in [0, 1]: levels 0 and LEVELS were built");
        slot.get_or_init(|| built)
    }

    fn build(&self, level: u32) -> Result<[Arc<Specular>; 2]> {
        let r = f64::from(level) / f64::from(LEVELS);
        let at = |metallic: f64| -> Result<Arc<Specular>> {
            let s = self
                .spec
                .with("roughness", Given::Num(r))?
                .with("metallic", Given::Num(metallic))?;
            Ok(Arc::new(tinted_specular(&s, self.tint.as_ref())?))
        };
        let built = [at(0.0)?, at(1.0)?];
        let _ = self.levels[level as usize].set(built.clone());
        Ok(built)
    }
}

/// The shading normal and frame at a hit, from the smooth normal `n` (facing the viewer), the
/// mesh's interpolated `tangent` (zero where the mesh has none), whether the hit is on the
/// back face (`n` reversed), the view direction `v` and the material's normal texture at
/// `uv`: `(normal, t, b)`, an orthonormal frame with `b` along the bitangent. Without a usable
/// tangent: `n` and `any_orthonormal_pair` (the renderer's frame for every other surface).
#[inline]
pub fn frame(
    n: Vec3,
    tangent: Vec4,
    back: bool,
    v: Vec3,
    normal: Option<&NormalMap>,
    uv: Vec2,
) -> (Vec3, Vec3, Vec3) {
    if tangent == Vec4::ZERO && normal.is_none() {
        // No tangent frame and no normal texture (every built-in scene): the frame below
        // would come to this after a normalisation of the zero vector. Inlined into the
        // renderer's loop; the tangent frame's code is not.
        let (t, b) = n.any_orthonormal_pair();
        return (n, t, b);
    }
    let sign = if back { -1.0 } else { 1.0 };
    tangent_frame(
        n,
        (sign * tangent.truncate(), tangent.w),
        v,
        normal.map(|m| (m, uv)),
    )
}

/// [`frame`] where the mesh has a tangent or the material a normal texture: `(t, w)` the
/// tangent turned with the face and its bitangent sign, and the normal texture with the hit's
/// texture coordinates.
#[inline(never)]
fn tangent_frame(
    n: Vec3,
    (t, tw): (Vec3, f32),
    v: Vec3,
    normal: Option<(&NormalMap, Vec2)>,
) -> (Vec3, Vec3, Vec3) {
    let t = (t - n * n.dot(t)).normalize_or_zero();
    if t == Vec3::ZERO {
        let (t, b) = n.any_orthonormal_pair();
        return (n, t, b);
    }
    let w = if tw < 0.0 { -1.0 } else { 1.0 };
    // On a back face N and T are reversed, so B = (N x T) w is too.
    let b = n.cross(t) * w;
    let mut shading = n;
    if let Some((nm, uv)) = normal {
        let x = nm.texture.sample(uv) * 2.0 - Vec3::ONE;
        let p = (t * (x.x * nm.scale) + b * (x.y * nm.scale) + n * x.z).normalize_or_zero();
        if p.dot(v) > 0.0 {
            shading = p;
        }
    }
    // The frame about the shading normal: T made orthogonal to it, B on the bitangent's side.
    let t2 = (t - shading * shading.dot(t)).normalize_or_zero();
    if t2 == Vec3::ZERO {
        let (t, b) = shading.any_orthonormal_pair();
        return (shading, t, b);
    }
    let b2 = shading.cross(t2);
    (shading, t2, if b2.dot(b) < 0.0 { -b2 } else { b2 })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flat(rgb: Vec3) -> Arc<Texture> {
        Arc::new(Texture::from_linear(1, 1, vec![rgb]))
    }

    #[test]
    fn a_flat_normal_texel_keeps_the_normal_and_the_tangent_frame() {
        let nm = NormalMap {
            texture: flat(Vec3::new(0.5, 0.5, 1.0)),
            scale: 1.0,
        };
        let n = Vec3::Z;
        let (s, t, b) = frame(
            n,
            Vec4::new(1.0, 0.0, 0.0, 1.0),
            false,
            n,
            Some(&nm),
            Vec2::ZERO,
        );
        assert!((s - n).length() < 1e-6 && (t - Vec3::X).length() < 1e-6);
        assert!((b - Vec3::Y).length() < 1e-6, "{b}");
        // w = -1: the bitangent reverses.
        let (_, _, b) = frame(
            n,
            Vec4::new(1.0, 0.0, 0.0, -1.0),
            false,
            n,
            None,
            Vec2::ZERO,
        );
        assert!((b + Vec3::Y).length() < 1e-6, "{b}");
    }

    #[test]
    fn a_tilted_texel_tilts_the_normal_towards_the_tangent() {
        // (x, y, z) = (0.6, 0, 0.8): the normal leans 36.87 degrees towards +T; scale 0.5
        // halves the tangential part before normalising.
        let nm = |scale| NormalMap {
            texture: flat(Vec3::new(0.8, 0.5, 0.9)),
            scale,
        };
        let n = Vec3::Z;
        let tan = Vec4::new(1.0, 0.0, 0.0, 1.0);
        let (s, t, b) = frame(n, tan, false, n, Some(&nm(1.0)), Vec2::ZERO);
        let want = Vec3::new(0.6, 0.0, 0.8);
        assert!((s - want).length() < 1e-5, "{s}");
        assert!(t.dot(s).abs() < 1e-6 && b.dot(s).abs() < 1e-6 && t.dot(b).abs() < 1e-6);
        let (s, ..) = frame(n, tan, false, n, Some(&nm(0.5)), Vec2::ZERO);
        let want = Vec3::new(0.3, 0.0, 0.8).normalize();
        assert!((s - want).length() < 1e-5, "{s}");
        // The back face: everything reversed.
        let (s, ..) = frame(-n, tan, true, -n, Some(&nm(1.0)), Vec2::ZERO);
        assert!((s + Vec3::new(0.6, 0.0, 0.8)).length() < 1e-5, "{s}");
    }

    #[test]
    fn without_a_tangent_the_frame_is_the_renderers_usual_one() {
        let n = Vec3::new(0.0, 0.6, 0.8);
        let (s, t, b) = frame(n, Vec4::ZERO, false, n, None, Vec2::ZERO);
        assert_eq!((s, (t, b)), (n, n.any_orthonormal_pair()));
    }

    #[test]
    fn metallic_and_roughness_come_from_the_texel_times_the_factors() {
        let spec =
            ModelSpec::parse("gltf-pbr", &[("metallic", "0.5"), ("roughness", "0.8")]).unwrap();
        let tex = flat(Vec3::new(0.0, 0.5, 1.0));
        let mr = MetallicRoughness::new(tex, &spec, None).unwrap();
        let (m, level) = mr.at(Vec2::ZERO);
        assert_eq!(m, 0.5);
        assert_eq!(level, (0.4 * LEVELS as f32).round() as u32);
        let [m0, m1] = mr.models(level);
        let num = |s: &Specular, k: &str| s.brdf.as_ref().unwrap().channels()[0].num(k);
        assert!((num(m0, "roughness") - f64::from(level) / f64::from(LEVELS)).abs() < 1e-12);
        assert_eq!((num(m0, "metallic"), num(m1, "metallic")), (0.0, 1.0));
    }
}

//! Textures: a material's images decoded (PNG or JPEG, from a buffer view, a data URI or a
//! file beside the scene), bounded as `--texture` files are
//! ([`crate::texture::MAX_TEXTURE_SIDE`], [`crate::texture::MAX_TEXTURE_PIXELS`]); colour
//! (base colour, emissive) texels made linear from sRGB, data (metallic-roughness, normal,
//! occlusion) texels as stored, `byte / 255`. Each image is decoded once per use.

use super::Ctx;
use crate::error::Result;
use crate::texture::{
    MAX_TEXTURE_PIXELS, MAX_TEXTURE_SIDE, Texture, check_texture_size, srgb_to_linear,
};
use glam::Vec3;
use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

/// The decoded images of a scene, by image index.
#[derive(Default)]
pub(super) struct Images {
    /// By (image index, whether sRGB-decoded).
    done: HashMap<(usize, bool), Arc<Texture>>,
}

impl Images {
    /// The texture `texture` (an index into `textures`) as linear texels, sRGB-decoded when
    /// `srgb` (a colour, not data); `warnings` gets what is not used (the sampler's wrap modes).
    pub(super) fn get(
        &mut self,
        ctx: &Ctx,
        doc: &gltf::Document,
        buffers: &[Vec<u8>],
        dir: &Path,
        (texture, srgb): (usize, bool),
        warnings: &mut Vec<String>,
    ) -> Result<Arc<Texture>> {
        let t = doc
            .textures()
            .nth(texture)
            .expect("validated: the texture exists");
        let s = t.sampler();
        use gltf::texture::WrappingMode::Repeat;
        if s.wrap_s() != Repeat || s.wrap_t() != Repeat {
            warnings.push(format!(
                "texture /textures/{texture}: its sampler's wrap modes are not used (sampled with REPEAT)"
            ));
        }
        let img = t.source();
        if let Some(done) = self.done.get(&(img.index(), srgb)) {
            return Ok(done.clone());
        }
        let ptr = format!("/images/{}", img.index());
        let bytes: Vec<u8> = match img.source() {
            gltf::image::Source::View { view, .. } => {
                let data = &buffers[view.buffer().index()];
                data.get(view.offset()..view.offset().saturating_add(view.length()))
                    .ok_or_else(|| {
                        ctx.err(
                            &format!("/bufferViews/{}", view.index()),
                            format!(
                                "bytes {}..{} of buffer {}, which has {}",
                                view.offset(),
                                view.offset().saturating_add(view.length()),
                                view.buffer().index(),
                                data.len()
                            ),
                        )
                    })?
                    .to_vec()
            }
            gltf::image::Source::Uri { uri, .. } => {
                super::buffers::read_uri(ctx, &format!("{ptr}/uri"), uri, dir)?
            }
        };
        let tex = Arc::new(decode(ctx, &ptr, &bytes, srgb)?);
        self.done.insert((img.index(), srgb), tex.clone());
        Ok(tex)
    }
}

/// Decodes PNG or JPEG bytes: the format and the declared size checked first, the decoder's
/// allocations capped.
fn decode(ctx: &Ctx, ptr: &str, bytes: &[u8], srgb: bool) -> Result<Texture> {
    let bad = |m: String| ctx.err(ptr, m);
    let reader = || {
        image::ImageReader::new(std::io::Cursor::new(bytes))
            .with_guessed_format()
            .map_err(|e| bad(format!("cannot read the image: {e}")))
    };
    match reader()?.format() {
        Some(image::ImageFormat::Png | image::ImageFormat::Jpeg) => {}
        f => {
            return Err(bad(format!(
                "an image of format {f:?}: glTF images are PNG or JPEG"
            )));
        }
    }
    let (w, h) = reader()?
        .into_dimensions()
        .map_err(|e| bad(format!("cannot read the image: {e}")))?;
    check_texture_size(w, h).map_err(bad)?;
    let mut r = reader()?;
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(MAX_TEXTURE_SIDE);
    limits.max_image_height = Some(MAX_TEXTURE_SIDE);
    limits.max_alloc = Some(MAX_TEXTURE_PIXELS * 16);
    r.limits(limits);
    let rgb = r
        .decode()
        .map_err(|e| bad(format!("cannot read the image: {e}")))?
        .to_rgb8();
    let lut: Vec<f32> = (0..256)
        .map(|i| {
            let x = i as f32 / 255.0;
            if srgb { srgb_to_linear(x) } else { x }
        })
        .collect();
    let texels = rgb
        .pixels()
        .map(|p| Vec3::new(lut[p[0] as usize], lut[p[1] as usize], lut[p[2] as usize]))
        .collect();
    Ok(Texture::from_linear(w, h, texels))
}

//! Reading image files (textures, environment maps) with bounds: a leaf module, used by both
//! `texture` and `env`.

use crate::error::{RenderError, Result};
use std::path::Path;

/// The front of every image file the renderer reads (textures, environment maps): the file
/// read once, at most `max_bytes` (`what` names it in that error: "a texture"); its format
/// passed to `accept` and its declared size to `check` before anything is decoded; then
/// decoded with the decoder's limits `(max width, max height, max allocation)`. Errors are
/// input errors naming the file, "cannot read `noun`: ..." where the decoder fails.
pub(crate) fn decode_limited(
    path: &Path,
    max_bytes: u64,
    what: &str,
    noun: &str,
    accept: impl Fn(Option<image::ImageFormat>) -> std::result::Result<(), String>,
    check: impl Fn(u32, u32) -> std::result::Result<(), String>,
    (max_w, max_h, max_alloc): (u32, u32, u64),
) -> Result<image::DynamicImage> {
    let file = path.display().to_string();
    let bad = |m: String| RenderError::Input {
        file: file.clone(),
        line: None,
        message: m,
    };
    let f = std::fs::File::open(path).map_err(|e| bad(format!("cannot read {noun}: {e}")))?;
    let bytes = fastbrdf_io::read_reader_bounded(f, path, max_bytes, what)?;
    let reader = || {
        image::ImageReader::new(std::io::Cursor::new(&bytes[..]))
            .with_guessed_format()
            .map_err(|e| bad(format!("cannot read {noun}: {e}")))
    };
    accept(reader()?.format()).map_err(bad)?;
    let (w, h) = reader()?
        .into_dimensions()
        .map_err(|e| bad(format!("cannot read {noun}: {e}")))?;
    check(w, h).map_err(bad)?;
    let mut r = reader()?;
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(max_w);
    limits.max_image_height = Some(max_h);
    limits.max_alloc = Some(max_alloc);
    r.limits(limits);
    r.decode()
        .map_err(|e| bad(format!("cannot read {noun}: {e}")))
}

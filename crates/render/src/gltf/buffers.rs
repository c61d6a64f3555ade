//! The bytes of a glTF file: the container (a `.glb` split by hand, so a malformed header is
//! an error, never a panic), its buffers (the GLB's BIN chunk, base64 data URIs, files beside
//! the scene, each read once and bounded) and the accessors the renderer reads, every range
//! checked against the bytes it names before anything is read.

use super::{Ctx, MAX_BUFFER_BYTES, MAX_TOTAL_BUFFER_BYTES};
use crate::error::Result;
use base64::Engine;
use gltf::accessor::{DataType, Dimensions};
use std::path::{Component, Path};

/// A `.glb` container split into its JSON chunk and its optional BIN chunk.
pub(super) fn split_glb<'a>(ctx: &Ctx, bytes: &'a [u8]) -> Result<(&'a [u8], Option<&'a [u8]>)> {
    let u32_at = |at: usize| -> Option<u32> {
        bytes
            .get(at..at + 4)
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    };
    let version = u32_at(4).unwrap_or(0);
    if version != 2 {
        return Err(ctx.err(
            "",
            format!("a binary glTF (.glb) of version {version}: only version 2 is read"),
        ));
    }
    let length = u32_at(8).unwrap_or(0) as usize;
    if length < 20 || length > bytes.len() {
        return Err(ctx.err(
            "",
            format!(
                "the .glb header says {length} bytes, the file has {}: truncated or not a .glb",
                bytes.len()
            ),
        ));
    }
    let mut at = 12;
    let mut json = None;
    let mut bin = None;
    while at + 8 <= length {
        let (len, kind) = (
            u32_at(at).unwrap_or(0) as usize,
            u32_at(at + 4).unwrap_or(0),
        );
        let start = at + 8;
        let Some(end) = start.checked_add(len).filter(|&e| e <= length) else {
            return Err(ctx.err(
                "",
                format!("a .glb chunk at byte {at} of {len} bytes runs past the end of the file"),
            ));
        };
        match kind {
            0x4E4F_534A if json.is_none() => json = Some(&bytes[start..end]),
            0x004E_4942 if bin.is_none() && json.is_some() => bin = Some(&bytes[start..end]),
            _ => {} // unknown chunks are skipped, as the specification says
        }
        at = end;
    }
    let json = json.ok_or_else(|| ctx.err("", "a .glb without its JSON chunk"))?;
    Ok((json, bin))
}

/// Decodes a URI's percent escapes (`%20`); a URI is a relative reference.
fn percent_decode(s: &str) -> Option<String> {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%' {
            let hex = std::str::from_utf8(b.get(i + 1..i + 3)?).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(b[i]);
            i += 1;
        }
    }
    String::from_utf8(out).ok()
}

/// The bytes of every buffer, in order: the GLB's BIN chunk, a base64 data URI or a file
/// beside the scene (a relative path inside the scene's folder: no `..`, no absolute path, no
/// other scheme), each at most [`MAX_BUFFER_BYTES`] and all together at most
/// [`MAX_TOTAL_BUFFER_BYTES`]; a buffer shorter than its `byteLength` is an error.
pub(super) fn load_buffers(
    ctx: &Ctx,
    doc: &gltf::Document,
    bin: Option<&[u8]>,
    dir: &Path,
) -> Result<Vec<Vec<u8>>> {
    let mut total = 0u64;
    let mut out = Vec::new();
    for b in doc.buffers() {
        let ptr = format!("/buffers/{}", b.index());
        let declared = b.length();
        if declared as u64 > MAX_BUFFER_BYTES {
            return Err(ctx.err(
                &format!("{ptr}/byteLength"),
                format!(
                    "{declared} bytes: at most {} per buffer",
                    fastbrdf_io::human_size(MAX_BUFFER_BYTES)
                ),
            ));
        }
        total += declared as u64;
        if total > MAX_TOTAL_BUFFER_BYTES {
            return Err(ctx.err(
                &format!("{ptr}/byteLength"),
                format!(
                    "the buffers add up to more than {}",
                    fastbrdf_io::human_size(MAX_TOTAL_BUFFER_BYTES)
                ),
            ));
        }
        let data: Vec<u8> = match b.source() {
            gltf::buffer::Source::Bin => match bin {
                Some(bin) => bin.to_vec(),
                None => {
                    return Err(ctx.err(
                        &ptr,
                        "a buffer without a uri needs the BIN chunk of a .glb, and there is none",
                    ));
                }
            },
            gltf::buffer::Source::Uri(uri) => read_uri(ctx, &format!("{ptr}/uri"), uri, dir)?,
        };
        if data.len() < declared {
            return Err(ctx.err(
                &format!("{ptr}/byteLength"),
                format!("{declared} bytes declared, the data holds {}", data.len()),
            ));
        }
        out.push(data);
    }
    Ok(out)
}

pub(super) fn read_uri(ctx: &Ctx, ptr: &str, uri: &str, dir: &Path) -> Result<Vec<u8>> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let Some((_, payload)) = rest.split_once(";base64,") else {
            return Err(ctx.err(ptr, "a data URI must be base64 (data:...;base64,...)"));
        };
        if payload.len() as u64 / 4 * 3 > MAX_BUFFER_BYTES {
            return Err(ctx.err(
                ptr,
                format!(
                    "a data URI of more than {}",
                    fastbrdf_io::human_size(MAX_BUFFER_BYTES)
                ),
            ));
        }
        return base64::engine::general_purpose::STANDARD
            .decode(payload)
            .map_err(|e| ctx.err(ptr, format!("the data URI is not valid base64: {e}")));
    }
    let short = fastbrdf_io::shorten_middle(uri, 60);
    if uri.contains(':') {
        return Err(ctx.err(
            ptr,
            format!("'{short}': only data URIs and files beside the scene are read"),
        ));
    }
    let rel = percent_decode(uri)
        .ok_or_else(|| ctx.err(ptr, format!("'{short}': a malformed percent escape")))?;
    let rel_path = Path::new(&rel);
    if rel.is_empty()
        || rel_path
            .components()
            .any(|c| !matches!(c, Component::Normal(_)))
    {
        return Err(ctx.err(
            ptr,
            format!(
                "'{short}': a buffer file must be a relative path inside the scene's folder (no '..', no absolute path)"
            ),
        ));
    }
    let path = dir.join(rel_path);
    // A link inside the folder may still lead out of it: the file itself must be inside.
    if let (Ok(real), Ok(real_dir)) = (path.canonicalize(), dir.canonicalize())
        && !real.starts_with(&real_dir)
    {
        return Err(ctx.err(
            ptr,
            format!("'{short}' leads outside the scene's folder (a link): not read"),
        ));
    }
    let f = std::fs::File::open(&path)
        .map_err(|e| ctx.err(ptr, format!("cannot read {}: {e}", path.display())))?;
    Ok(fastbrdf_io::read_reader_bounded(
        f,
        &path,
        MAX_BUFFER_BYTES,
        "a glTF buffer",
    )?)
}

/// One accessor's elements as f32 rows of `want` components, checked: its type, its byte
/// range inside its buffer view and the view's inside its buffer. Floats, and for
/// `normalized_ok` the normalized unsigned bytes and shorts texture coordinates may use.
pub(super) fn read_floats(
    ctx: &Ctx,
    ptr: &str,
    a: &gltf::Accessor,
    buffers: &[Vec<u8>],
    want: Dimensions,
    normalized_ok: bool,
) -> Result<Vec<f32>> {
    let n = dims(want);
    if a.dimensions() != want {
        return Err(ctx.err(
            ptr,
            format!(
                "accessor {} is {:?}, {:?} expected",
                a.index(),
                a.dimensions(),
                want
            ),
        ));
    }
    let ty = a.data_type();
    let ok = ty == DataType::F32
        || (normalized_ok && a.normalized() && matches!(ty, DataType::U8 | DataType::U16));
    if !ok {
        return Err(ctx.err(
            ptr,
            format!(
                "accessor {} holds {:?}{}: float{} expected",
                a.index(),
                ty,
                if a.normalized() { " (normalized)" } else { "" },
                if normalized_ok {
                    " or normalized unsigned byte/short"
                } else {
                    ""
                }
            ),
        ));
    }
    let (bytes, stride) = elements(ctx, ptr, a, buffers, ty.size() * n)?;
    let mut out = Vec::with_capacity(a.count() * n);
    for i in 0..a.count() {
        let at = i * stride;
        for c in 0..n {
            let o = at + c * ty.size();
            let x = match ty {
                DataType::F32 => {
                    f32::from_le_bytes([bytes[o], bytes[o + 1], bytes[o + 2], bytes[o + 3]])
                }
                DataType::U8 => bytes[o] as f32 / 255.0,
                _ => u16::from_le_bytes([bytes[o], bytes[o + 1]]) as f32 / 65535.0,
            };
            out.push(x);
        }
    }
    Ok(out)
}

/// A primitive's indices (unsigned byte, short or int scalars), checked.
pub(super) fn read_indices(
    ctx: &Ctx,
    ptr: &str,
    a: &gltf::Accessor,
    buffers: &[Vec<u8>],
) -> Result<Vec<u32>> {
    let ty = a.data_type();
    if a.dimensions() != Dimensions::Scalar
        || !matches!(ty, DataType::U8 | DataType::U16 | DataType::U32)
    {
        return Err(ctx.err(
            ptr,
            format!(
                "accessor {} is {:?} of {:?}: indices are unsigned byte, short or int scalars",
                a.index(),
                a.dimensions(),
                ty
            ),
        ));
    }
    let (bytes, stride) = elements(ctx, ptr, a, buffers, ty.size())?;
    Ok((0..a.count())
        .map(|i| {
            let o = i * stride;
            match ty {
                DataType::U8 => u32::from(bytes[o]),
                DataType::U16 => u32::from(u16::from_le_bytes([bytes[o], bytes[o + 1]])),
                _ => u32::from_le_bytes([bytes[o], bytes[o + 1], bytes[o + 2], bytes[o + 3]]),
            }
        })
        .collect())
}

fn dims(d: Dimensions) -> usize {
    d.multiplicity()
}

/// The bytes from the accessor's first element on and its stride, after checking that
/// `count` elements of `elem` bytes fit in its view and the view in its buffer.
fn elements<'b>(
    ctx: &Ctx,
    ptr: &str,
    a: &gltf::Accessor,
    buffers: &'b [Vec<u8>],
    elem: usize,
) -> Result<(&'b [u8], usize)> {
    let acc = format!("/accessors/{}", a.index());
    if a.sparse().is_some() {
        return Err(ctx.err(
            &format!("{acc}/sparse"),
            "sparse accessors are not read (yet): write the values densely",
        ));
    }
    let Some(view) = a.view() else {
        return Err(ctx.err(
            &acc,
            "an accessor without a bufferView (all zeros) is not read: nothing to render",
        ));
    };
    if a.count() == 0 {
        return Err(ctx.err(&format!("{acc}/count"), "an accessor of no elements"));
    }
    let vptr = format!("/bufferViews/{}", view.index());
    let data = &buffers[view.buffer().index()];
    let vend = view.offset().checked_add(view.length());
    if vend.is_none_or(|e| e > data.len()) {
        return Err(ctx.err(
            &vptr,
            format!(
                "bytes {}..{} of buffer {}, which has {}",
                view.offset(),
                view.offset().saturating_add(view.length()),
                view.buffer().index(),
                data.len()
            ),
        ));
    }
    let vbytes = &data[view.offset()..view.offset() + view.length()];
    let stride = view.stride().unwrap_or(elem);
    if stride < elem {
        return Err(ctx.err(
            &format!("{vptr}/byteStride"),
            format!(
                "{stride} bytes, less than an element of accessor {} ({elem} bytes)",
                a.index()
            ),
        ));
    }
    let need = (a.count() - 1)
        .checked_mul(stride)
        .and_then(|x| x.checked_add(elem))
        .and_then(|x| x.checked_add(a.offset()));
    match need {
        Some(need) if need <= vbytes.len() => Ok((&vbytes[a.offset()..], stride)),
        _ => Err(ctx.err(
            &acc,
            format!(
                "{} elements of {elem} bytes from byte {} run past its bufferView {} ({} bytes){}",
                a.count(),
                a.offset(),
                view.index(),
                vbytes.len(),
                if ptr.is_empty() {
                    String::new()
                } else {
                    format!(", read for {ptr}")
                }
            ),
        )),
    }
}

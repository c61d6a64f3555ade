//! OBJ meshes: one hand-written parser that both validates and builds the mesh, so that what
//! it accepts it can load, and every rejection names the file, line and column. Smooth vertex
//! normals, area- and angle-weighted, when the file has none.
//!
//! Written by hand rather than with `tobj` because tobj's errors carry no line numbers, it
//! reads the file itself (a pipe cannot be read twice) and follows `mtllib` into unbounded
//! reads. Accepted (Wavefront OBJ, polygonal subset):
//! - `v x y z [w]` or `v x y z [w] r g b` (weights and colours are checked, then ignored),
//!   `vt u [v [w]]`, `vn x y z`: every number must be finite and of magnitude at most
//!   [`MAX_COORD`];
//! - `f` with 3 or more vertices in one form per face: `v`, `v/vt`, `v//vn` or `v/vt/vn`;
//!   indices 1-based, negative ones count back from the last element defined; polygons are
//!   triangulated as a fan (convex polygons, like tobj);
//! - comments (`#` to the end of the line), blank lines, a `\` at the end of a line continues
//!   the statement on the next one;
//! - the other OBJ statements (`o`, `g`, `s`, `usemtl`, `mtllib`, `l`, `p`, free-form
//!   geometry...) are skipped: materials are not used (the renderer's material comes from the
//!   options), so `mtllib` files are never opened.
//!
//! Memory: the file is read once, bounded by [`MAX_OBJ_BYTES`]; the mesh is at most a small
//! multiple of the file's size.

use crate::error::{RenderError, Result};
use crate::geometry::TriMesh;
use glam::{Vec2, Vec3};
use std::collections::HashMap;
use std::path::Path;

/// MediaPipe's canonical face mesh (468 vertices, 898 triangles, texture coordinates, no
/// normals), embedded unmodified; Apache-2.0, see `data/NOTICE.md` beside the crate's sources.
pub const FACE_OBJ: &str = include_str!("../data/canonical_face_model.obj");

/// The embedded face ([`FACE_OBJ`]) as a mesh, normals computed (`--mesh face`).
pub fn face() -> TriMesh {
    parse_obj(Path::new("<built-in face>"), FACE_OBJ).expect("the embedded face mesh parses")
}

/// Largest OBJ file read: 256 MiB (the face mesh is 40 KiB; 256 MiB is millions of faces).
pub const MAX_OBJ_BYTES: u64 = 256 << 20;

/// Most triangles in a mesh (after triangulation): 2^23, about 1.6 GiB with the BVHs (the
/// binary tree the GPU shares and the CPU's 4-wide one, 72 bytes a triangle).
pub const MAX_TRIANGLES: usize = 1 << 23;

/// Largest magnitude of a coordinate: products of coordinates in the camera and intersection
/// code stay finite in f32 (1e9^3 < 3.4e38).
pub const MAX_COORD: f32 = 1e9;

fn err(file: &Path, line: Option<usize>, message: impl Into<String>) -> RenderError {
    RenderError::Input {
        file: file.display().to_string(),
        line,
        message: message.into(),
    }
}

/// OBJ statements that are valid but not rendered (skipped).
const SKIPPED: &[&str] = &[
    "o",
    "g",
    "s",
    "usemtl",
    "mtllib",
    "l",
    "p",
    "vp",
    "maplib",
    "usemap",
    "lod",
    "shadow_obj",
    "trace_obj",
    "bevel",
    "c_interp",
    "d_interp",
    "cstype",
    "deg",
    "bmat",
    "step",
    "curv",
    "curv2",
    "surf",
    "parm",
    "trim",
    "hole",
    "scrv",
    "sp",
    "end",
    "con",
    "mg",
    "ctech",
    "stech",
    "call",
    "csh",
];

/// A parsed OBJ: triangles over unique (position, uv, normal) corners, like tobj with
/// `single_index` and `triangulate`.
struct Parsed {
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    uvs: Vec<Vec2>,
    triangles: Vec<[u32; 3]>,
    all_uvs: bool,
    faces: usize,
}

/// The tokens of a statement with their 1-based byte columns, lazily (a statement may be
/// millions of tokens long; nothing per token is held beyond what the mesh keeps).
fn tokens(s: &str) -> impl Iterator<Item = (usize, &str)> + Clone {
    s.split(|c: char| c.is_whitespace())
        .filter(|t| !t.is_empty())
        .map(move |t| (t.as_ptr() as usize - s.as_ptr() as usize + 1, t))
}

fn parse(file: &Path, text: &str) -> Result<Parsed> {
    // A UTF-8 byte-order mark (some Windows editors write one) is not part of the first line.
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let (mut vs, mut vts, mut vns) = (Vec::new(), Vec::new(), Vec::new());
    let mut corners: HashMap<(u32, Option<u32>, Option<u32>), u32> = HashMap::new();
    let mut p = Parsed {
        positions: Vec::new(),
        normals: Vec::new(),
        uvs: Vec::new(),
        triangles: Vec::new(),
        all_uvs: true,
        faces: 0,
    };
    let mut lines = text.lines().enumerate();
    while let Some((i, raw)) = lines.next() {
        let line = i + 1;
        // The statement: this line up to a comment, joined with continuation lines. Columns
        // are those of the first line (continued statements are rare).
        let mut stmt = raw.split('#').next().unwrap_or("").to_string();
        while stmt.trim_end().ends_with('\\') {
            let t = stmt.trim_end();
            stmt = format!("{} ", &t[..t.len() - 1]);
            match lines.next() {
                Some((_, next)) => stmt.push_str(next.split('#').next().unwrap_or("")),
                None => break,
            }
        }
        let mut toks = tokens(&stmt);
        let Some((_, kind)) = toks.next() else {
            continue;
        };
        let at = |col: usize, m: String| err(file, Some(line), format!("{m} (column {col})"));
        let numbers = |what: &str, counts: &[usize]| -> Result<Vec<f32>> {
            // At most 8 numbers are held; a longer record is counted, not collected.
            let rest: Vec<(usize, &str)> = toks.clone().take(8).collect();
            if !counts.contains(&rest.len()) {
                let found = toks.clone().count();
                let want = match counts {
                    [n] => format!("{n}"),
                    _ => {
                        let s: Vec<String> = counts.iter().map(|c| c.to_string()).collect();
                        format!("{} or {}", s[..s.len() - 1].join(", "), s[s.len() - 1])
                    }
                };
                return Err(err(
                    file,
                    Some(line),
                    format!("{what} needs {want} numbers, found {found}"),
                ));
            }
            rest.iter()
                .map(|&(col, t)| {
                    let x: f32 = t.parse().map_err(|_| {
                        at(
                            col,
                            format!("{what}: '{}' is not a number", fastbrdf_io::shorten(t, 40)),
                        )
                    })?;
                    if !x.is_finite() || x.abs() > MAX_COORD {
                        return Err(at(
                            col,
                            format!(
                                "{what}: '{}' is not a finite number of magnitude at most {MAX_COORD:e}",
                                fastbrdf_io::shorten(t, 40)
                            ),
                        ));
                    }
                    Ok(x)
                })
                .collect()
        };
        match kind {
            "v" => {
                let x = numbers("vertex", &[3, 4, 6, 7])?;
                vs.push(Vec3::new(x[0], x[1], x[2]));
            }
            "vt" => {
                let x = numbers("texture coordinate", &[1, 2, 3])?;
                vts.push(Vec2::new(x[0], x.get(1).copied().unwrap_or(0.0)));
            }
            "vn" => {
                let x = numbers("normal", &[3])?;
                vns.push(Vec3::new(x[0], x[1], x[2]));
            }
            "f" => {
                let refs = toks.clone();
                let n = refs.clone().take(3).count();
                if n < 3 {
                    return Err(err(
                        file,
                        Some(line),
                        format!("a face needs at least 3 vertices, found {n}"),
                    ));
                }
                let mut form = None;
                let mut face = Vec::new();
                for (col, r) in refs {
                    if p.triangles.len() + face.len() > MAX_TRIANGLES + 1 {
                        return Err(at(
                            col,
                            format!("more than {MAX_TRIANGLES} triangles: the mesh is too large"),
                        ));
                    }
                    let parts: Vec<&str> = r.split('/').collect();
                    if parts.len() > 3 || parts[0].is_empty() {
                        return Err(at(
                            col,
                            format!(
                                "face: '{}' is not v, v/vt, v//vn or v/vt/vn",
                                fastbrdf_io::shorten(r, 40)
                            ),
                        ));
                    }
                    let this = (parts.len(), parts.get(1).is_some_and(|s| !s.is_empty()));
                    match form {
                        None => form = Some(this),
                        Some(f) if f != this => {
                            return Err(at(
                                col,
                                format!(
                                    "face: '{}' mixes forms (every vertex of a face must be v, v/vt, v//vn or v/vt/vn alike)",
                                    fastbrdf_io::shorten(r, 40)
                                ),
                            ));
                        }
                        _ => {}
                    }
                    let index = |idx: &str, count: usize, what: &str| -> Result<u32> {
                        if idx.is_empty() {
                            return Err(at(
                                col,
                                format!(
                                    "face: '{}' has an empty {what} index",
                                    fastbrdf_io::shorten(r, 40)
                                ),
                            ));
                        }
                        let k: i64 = idx.parse().map_err(|_| {
                            at(
                                col,
                                format!(
                                    "face: '{}' has a non-integer {what} index",
                                    fastbrdf_io::shorten(r, 40)
                                ),
                            )
                        })?;
                        let resolved = if k < 0 { count as i64 + k + 1 } else { k };
                        if k == 0 || resolved < 1 || resolved > count as i64 {
                            return Err(at(
                                col,
                                format!(
                                    "face: {what} index {k} is out of range ({count} defined so far{})",
                                    if k == 0 { "; indices start at 1" } else { "" }
                                ),
                            ));
                        }
                        Ok((resolved - 1) as u32)
                    };
                    let v = index(parts[0], vs.len(), "vertex")?;
                    let t = match parts.get(1) {
                        Some(s) if !s.is_empty() || parts.len() == 2 => {
                            Some(index(s, vts.len(), "texture coordinate")?)
                        }
                        _ => None, // v//vn
                    };
                    let n = match parts.get(2) {
                        Some(s) => Some(index(s, vns.len(), "normal")?),
                        None => None,
                    };
                    let next = p.positions.len() as u32;
                    let id = *corners.entry((v, t, n)).or_insert(next);
                    if id == next {
                        p.positions.push(vs[v as usize]);
                        match n {
                            Some(n) => p.normals.push(vns[n as usize].normalize_or_zero()),
                            // A corner without a normal: computed normals are used (see parse_obj).
                            None => p.normals.push(Vec3::ZERO),
                        }
                        match t {
                            Some(t) => p.uvs.push(vts[t as usize]),
                            None => {
                                p.all_uvs = false;
                                p.uvs.push(Vec2::ZERO);
                            }
                        }
                    }
                    face.push(id);
                }
                for k in 1..face.len() - 1 {
                    p.triangles.push([face[0], face[k], face[k + 1]]);
                }
                p.faces += 1;
            }
            k if SKIPPED.contains(&k) => {}
            k => {
                return Err(at(
                    1 + stmt.len() - stmt.trim_start().len(),
                    format!(
                        "'{}' is not an OBJ statement (expected v, vt, vn, f, o, g, s, usemtl, mtllib, ...)",
                        fastbrdf_io::shorten(k, 40)
                    ),
                ));
            }
        }
    }
    if p.faces == 0 {
        return Err(err(
            file,
            None,
            format!("no faces ({} vertices): nothing to render", vs.len()),
        ));
    }
    let (lo, hi) = p.positions.iter().fold(
        (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
        |(lo, hi), q| (lo.min(*q), hi.max(*q)),
    );
    if (hi - lo).max_element() <= 0.0 {
        return Err(err(
            file,
            None,
            "every face's vertices are at one point: nothing to frame or render",
        ));
    }
    Ok(p)
}

/// Checks an OBJ text (every number of every record, every index, the face forms); returns
/// the number of faces. The error names the file, line and column.
pub fn validate_obj(file: &Path, text: &str) -> Result<usize> {
    parse(file, text).map(|p| p.faces)
}

/// Builds one triangle mesh from an OBJ text (`file` names it in errors).
pub fn parse_obj(file: &Path, text: &str) -> Result<TriMesh> {
    let p = parse(file, text)?;
    // A corner without a normal, or a zero one, cannot shade: fall back to computed normals.
    let normals = if !p.normals.contains(&Vec3::ZERO) {
        p.normals
    } else {
        smooth_normals(&p.positions, &p.triangles)
    };
    let uvs = if p.all_uvs { p.uvs } else { Vec::new() };
    Ok(TriMesh::new(p.positions, normals, uvs, p.triangles))
}

/// Loads an OBJ file: read once (bounded by [`MAX_OBJ_BYTES`]; pipes work), validated and
/// built by the same parser.
pub fn load_obj(path: &Path) -> Result<TriMesh> {
    let f = std::fs::File::open(path).map_err(|e| err(path, None, format!("cannot read: {e}")))?;
    let bytes = fastbrdf_io::read_reader_bounded(f, path, MAX_OBJ_BYTES, "an OBJ mesh")?;
    parse_obj(path, &fastbrdf_io::utf8_text(bytes, path)?)
}

/// Smooth vertex normals: each triangle adds its normal weighted by its area and by its angle
/// at the vertex. Vertices at the same position (split by texture seams) share one normal.
pub fn smooth_normals(positions: &[Vec3], triangles: &[[u32; 3]]) -> Vec<Vec3> {
    let key = |p: Vec3| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()];
    let mut group: HashMap<[u32; 3], usize> = HashMap::new();
    let ids: Vec<usize> = positions
        .iter()
        .map(|&p| {
            let n = group.len();
            *group.entry(key(p)).or_insert(n)
        })
        .collect();
    let mut acc = vec![Vec3::ZERO; group.len()];
    for t in triangles {
        let p = t.map(|i| positions[i as usize]);
        let cross = (p[1] - p[0]).cross(p[2] - p[0]); // length = 2 area
        for k in 0..3 {
            let e1 = (p[(k + 1) % 3] - p[k]).normalize_or_zero();
            let e2 = (p[(k + 2) % 3] - p[k]).normalize_or_zero();
            let angle = e1.dot(e2).clamp(-1.0, 1.0).acos();
            acc[ids[t[k] as usize]] += cross * angle;
        }
    }
    ids.iter().map(|&g| acc[g].normalize_or_zero()).collect()
}

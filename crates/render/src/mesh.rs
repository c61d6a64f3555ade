//! OBJ meshes: a line-by-line validation that names the file and line of every problem
//! (tobj's errors carry no line numbers), loading with tobj, and smooth vertex normals,
//! area- and angle-weighted, when the file has none.

use crate::error::{RenderError, Result};
use crate::geometry::TriMesh;
use glam::{Vec2, Vec3};
use std::collections::HashMap;
use std::path::Path;

fn err(file: &Path, line: Option<usize>, message: impl Into<String>) -> RenderError {
    RenderError::Input {
        file: file.display().to_string(),
        line,
        message: message.into(),
    }
}

/// Checks an OBJ text: vertices with finite coordinates, faces with at least three valid
/// references to elements defined before them (negative indices count back), at least one
/// face. Returns the number of faces.
pub fn validate_obj(file: &Path, text: &str) -> Result<usize> {
    let (mut nv, mut nt, mut nn, mut faces) = (0usize, 0usize, 0usize, 0usize);
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let content = raw.split('#').next().unwrap_or("").trim();
        let mut tok = content.split_whitespace();
        let Some(kind) = tok.next() else { continue };
        let rest: Vec<&str> = tok.collect();
        let floats = |need: usize, what: &str| -> Result<()> {
            if rest.len() < need {
                return Err(err(
                    file,
                    Some(line),
                    format!("{what} needs {need} numbers, found {}", rest.len()),
                ));
            }
            for t in &rest[..need] {
                let x: f32 = t
                    .parse()
                    .map_err(|_| err(file, Some(line), format!("{what}: '{t}' is not a number")))?;
                if !x.is_finite() {
                    return Err(err(
                        file,
                        Some(line),
                        format!("{what}: '{t}' is not a finite number"),
                    ));
                }
            }
            Ok(())
        };
        match kind {
            "v" => {
                floats(3, "vertex")?;
                nv += 1;
            }
            "vt" => {
                floats(1, "texture coordinate")?;
                nt += 1;
            }
            "vn" => {
                floats(3, "normal")?;
                nn += 1;
            }
            "f" => {
                if rest.len() < 3 {
                    return Err(err(
                        file,
                        Some(line),
                        format!("a face needs at least 3 vertices, found {}", rest.len()),
                    ));
                }
                for r in &rest {
                    let parts: Vec<&str> = r.split('/').collect();
                    let check = |idx: &str, count: usize, what: &str| -> Result<()> {
                        if idx.is_empty() {
                            return Ok(());
                        }
                        let k: i64 = idx.parse().map_err(|_| {
                            err(
                                file,
                                Some(line),
                                format!("face: '{r}' has a non-integer {what} index"),
                            )
                        })?;
                        let resolved = if k < 0 { count as i64 + k + 1 } else { k };
                        if k == 0 || resolved < 1 || resolved > count as i64 {
                            return Err(err(
                                file,
                                Some(line),
                                format!(
                                    "face: {what} index {k} is out of range ({count} {what}s defined so far)"
                                ),
                            ));
                        }
                        Ok(())
                    };
                    if parts.is_empty() || parts[0].is_empty() {
                        return Err(err(
                            file,
                            Some(line),
                            format!("face: '{r}' has no vertex index"),
                        ));
                    }
                    check(parts[0], nv, "vertex")?;
                    if let Some(t) = parts.get(1) {
                        check(t, nt, "texture coordinate")?;
                    }
                    if let Some(n) = parts.get(2) {
                        check(n, nn, "normal")?;
                    }
                }
                faces += 1;
            }
            _ => {}
        }
    }
    if faces == 0 {
        return Err(err(
            file,
            None,
            format!("no faces ({nv} vertices): nothing to render"),
        ));
    }
    Ok(faces)
}

/// Loads an OBJ file into one triangle mesh, validating it first.
pub fn load_obj(path: &Path) -> Result<TriMesh> {
    let text =
        std::fs::read_to_string(path).map_err(|e| err(path, None, format!("cannot read: {e}")))?;
    validate_obj(path, &text)?;
    let opts = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ..Default::default()
    };
    let (models, _materials) =
        tobj::load_obj(path, &opts).map_err(|e| err(path, None, format!("cannot load: {e}")))?;
    let (mut positions, mut normals, mut uvs, mut triangles) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let mut all_have_normals = true;
    let mut all_have_uvs = true;
    for m in &models {
        let mesh = &m.mesh;
        let base = positions.len() as u32;
        let n = mesh.positions.len() / 3;
        positions.extend(
            mesh.positions
                .chunks_exact(3)
                .map(|p| Vec3::new(p[0], p[1], p[2])),
        );
        if mesh.normals.len() == mesh.positions.len() {
            normals.extend(
                mesh.normals
                    .chunks_exact(3)
                    .map(|v| Vec3::new(v[0], v[1], v[2]).normalize_or_zero()),
            );
        } else {
            all_have_normals = false;
            normals.extend(std::iter::repeat_n(Vec3::ZERO, n));
        }
        if mesh.texcoords.len() == 2 * n {
            uvs.extend(
                mesh.texcoords
                    .chunks_exact(2)
                    .map(|t| Vec2::new(t[0], t[1])),
            );
        } else {
            all_have_uvs = false;
            uvs.extend(std::iter::repeat_n(Vec2::ZERO, n));
        }
        triangles.extend(
            mesh.indices
                .chunks_exact(3)
                .map(|t| [base + t[0], base + t[1], base + t[2]]),
        );
    }
    if triangles.is_empty() {
        return Err(err(path, None, "no faces after triangulation"));
    }
    if !all_have_normals {
        normals = smooth_normals(&positions, &triangles);
    }
    if !all_have_uvs {
        uvs.clear();
    }
    Ok(TriMesh::new(positions, normals, uvs, triangles))
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

//! The default scene's node hierarchy: each mesh primitive's triangles moved to world space
//! by its node's transform, gathered into one mesh per material; the first camera and the
//! punctual lights; what is not drawn named.

use super::buffers::{read_floats, read_indices};
use super::material::GltfMaterial;
use super::{Ctx, GltfObject, MAX_NODE_VISITS, view};
use crate::error::Result;
use crate::geometry::TriMesh;
use crate::mesh::{MAX_COORD, MAX_TRIANGLES};
use crate::scene::{Camera, Light};
use glam::{Mat3, Mat4, Vec2, Vec3};
use gltf::accessor::Dimensions;
use gltf::mesh::{Mode, Semantic};
use std::collections::BTreeMap;
use std::sync::Arc;

/// What the walk found.
pub(super) struct Walked {
    pub objects: Vec<GltfObject>,
    pub camera: Option<Camera>,
    pub lights: Vec<Light>,
    pub bounds: (Vec3, Vec3),
}

/// The triangles of one material so far, in world space.
#[derive(Default)]
struct Group {
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    uvs: Vec<Vec2>,
    all_uvs: bool,
    tangents: Vec<[f32; 4]>,
    all_tangents: bool,
    triangles: Vec<[u32; 3]>,
}

/// One primitive in its own space.
struct Prim {
    positions: Vec<Vec3>,
    normals: Option<Vec<Vec3>>,
    uvs: Option<Vec<Vec2>>,
    tangents: Option<Vec<[f32; 4]>>,
    triangles: Vec<[u32; 3]>,
}

/// Walks the default scene (or the first, when none is named).
pub(super) fn walk(
    ctx: &Ctx,
    doc: &gltf::Document,
    raw: &serde_json::Value,
    buffers: &[Vec<u8>],
    materials: &mut Vec<GltfMaterial>,
    warnings: &mut Vec<String>,
) -> Result<Walked> {
    let scene = doc
        .default_scene()
        .or_else(|| doc.scenes().next())
        .ok_or_else(|| ctx.err("/scenes", "no scene: nothing to render"))?;
    check_forest(ctx, doc, raw)?;
    let mut groups: BTreeMap<usize, Group> = BTreeMap::new();
    let mut default_material = None;
    let mut camera = None;
    let mut lights = Vec::new();
    let mut skipped: BTreeMap<String, usize> = BTreeMap::new();
    let mut morphs = 0;
    let mut skinned = 0;
    let mut triangles = 0usize;
    let mut visits = 0usize;
    let mut stack: Vec<(gltf::Node, Mat4)> = scene.nodes().map(|n| (n, Mat4::IDENTITY)).collect();
    stack.reverse();
    while let Some((node, parent)) = stack.pop() {
        visits += 1;
        if visits > MAX_NODE_VISITS {
            return Err(ctx.err(
                &format!("/scenes/{}", scene.index()),
                format!("more than {MAX_NODE_VISITS} node visits"),
            ));
        }
        let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        if !world.is_finite() {
            return Err(ctx.err(
                &format!("/nodes/{}", node.index()),
                "its transform (with its parents') is not finite",
            ));
        }
        if camera.is_none() {
            camera = view::camera(&node, world, warnings);
        }
        lights.extend(view::light(ctx, &node, world, warnings)?);
        skinned += usize::from(node.skin().is_some());
        if let Some(mesh) = node.mesh() {
            for p in mesh.primitives() {
                let ptr = format!("/meshes/{}/primitives/{}", mesh.index(), p.index());
                if !matches!(
                    p.mode(),
                    Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
                ) {
                    *skipped.entry(format!("{:?}", p.mode())).or_default() += 1;
                    continue;
                }
                morphs += usize::from(p.morph_targets().len() > 0);
                let m = match p.material().index() {
                    Some(i) => i,
                    None => *default_material.get_or_insert_with(|| {
                        materials.push(GltfMaterial::default_material());
                        materials.len() - 1
                    }),
                };
                let prim = read_primitive(ctx, &ptr, &p, buffers)?;
                triangles += prim.triangles.len();
                if triangles > MAX_TRIANGLES {
                    return Err(ctx.err(
                        &ptr,
                        format!("more than {MAX_TRIANGLES} triangles in the scene: too large"),
                    ));
                }
                let g = groups.entry(m).or_insert_with(|| Group {
                    all_uvs: true,
                    all_tangents: true,
                    ..Default::default()
                });
                let need = materials[m].needs_tangents;
                add(g, prim, world, need, &ptr, warnings);
            }
        }
        let mut kids: Vec<_> = node.children().map(|c| (c, world)).collect();
        kids.reverse();
        stack.extend(kids);
    }
    for (mode, n) in &skipped {
        warnings.push(format!(
            "{n} primitive(s) of mode {mode}: only triangles are drawn"
        ));
    }
    if morphs > 0 {
        warnings.push(format!(
            "{morphs} primitive(s) with morph targets: drawn without them (base geometry)"
        ));
    }
    if skinned > 0 {
        warnings.push(format!(
            "{skinned} skinned node(s): skins are not applied (meshes drawn with their node transform)"
        ));
    }
    if triangles == 0 {
        return Err(ctx.err(
            &format!("/scenes/{}", scene.index()),
            "no triangles in the scene: nothing to render",
        ));
    }
    let mut lo = Vec3::splat(f32::MAX);
    let mut hi = Vec3::splat(f32::MIN);
    let mut objects = Vec::new();
    for (m, g) in groups {
        for q in &g.positions {
            (lo, hi) = (lo.min(*q), hi.max(*q));
        }
        let tangents = (materials[m].needs_tangents && g.all_tangents).then_some(g.tangents);
        let uvs = if g.all_uvs { g.uvs } else { Vec::new() };
        let mut mesh = TriMesh::new(g.positions, g.normals, uvs, g.triangles);
        if let Some(t) = &tangents {
            mesh.tangents = t.iter().map(|&a| glam::Vec4::from_array(a)).collect();
        }
        objects.push(GltfObject {
            mesh: Arc::new(mesh),
            tangents,
            material: m,
        });
    }
    if (hi - lo).max_element() <= 0.0 {
        return Err(ctx.err(
            "",
            "every triangle's vertices are at one point: nothing to frame or render",
        ));
    }
    Ok(Walked {
        objects,
        camera,
        lights,
        bounds: (lo, hi),
    })
}

/// Each node has at most one parent and the scenes list only roots, so that the walk ends.
fn check_forest(ctx: &Ctx, doc: &gltf::Document, _raw: &serde_json::Value) -> Result<()> {
    let mut parent: Vec<Option<usize>> = vec![None; doc.nodes().len()];
    for n in doc.nodes() {
        for (k, c) in n.children().enumerate() {
            if let Some(p) = parent[c.index()] {
                return Err(ctx.err(
                    &format!("/nodes/{}/children/{k}", n.index()),
                    format!(
                        "node {} is already a child of node {p}: the nodes must form trees",
                        c.index()
                    ),
                ));
            }
            parent[c.index()] = Some(n.index());
        }
    }
    // A cycle leaves every node on it with a parent; walking up from each node finds it.
    for start in 0..parent.len() {
        let (mut at, mut steps) = (start, 0);
        while let Some(p) = parent[at] {
            (at, steps) = (p, steps + 1);
            if steps > parent.len() {
                return Err(ctx.err(
                    &format!("/nodes/{start}"),
                    "its parents form a cycle: the nodes must form trees",
                ));
            }
        }
    }
    for s in doc.scenes() {
        for (k, n) in s.nodes().enumerate() {
            if let Some(p) = parent[n.index()] {
                return Err(ctx.err(
                    &format!("/scenes/{}/nodes/{k}", s.index()),
                    format!(
                        "node {} is a child of node {p}: a scene lists root nodes",
                        n.index()
                    ),
                ));
            }
        }
    }
    Ok(())
}

fn vec3s(x: Vec<f32>) -> Vec<Vec3> {
    x.chunks_exact(3)
        .map(|c| Vec3::new(c[0], c[1], c[2]))
        .collect()
}

/// Reads one triangle primitive, checked.
fn read_primitive(ctx: &Ctx, ptr: &str, p: &gltf::Primitive, buffers: &[Vec<u8>]) -> Result<Prim> {
    let attr = |name: &str| format!("{ptr}/attributes/{name}");
    let pos_acc = p
        .get(&Semantic::Positions)
        .ok_or_else(|| ctx.err(&format!("{ptr}/attributes"), "no POSITION: nothing to draw"))?;
    let positions = vec3s(read_floats(
        ctx,
        &attr("POSITION"),
        &pos_acc,
        buffers,
        Dimensions::Vec3,
        false,
    )?);
    if let Some(i) = positions
        .iter()
        .position(|q| !q.is_finite() || q.abs().max_element() > MAX_COORD)
    {
        return Err(ctx.err(
            &attr("POSITION"),
            format!(
                "vertex {i} of accessor {} is not finite or beyond {MAX_COORD:e}",
                pos_acc.index()
            ),
        ));
    }
    let n = positions.len();
    let same_count = |name: &str, a: &gltf::Accessor| {
        if a.count() == n {
            Ok(())
        } else {
            Err(ctx.err(
                &attr(name),
                format!(
                    "accessor {} has {} elements, POSITION {n}",
                    a.index(),
                    a.count()
                ),
            ))
        }
    };
    let normals = match p.get(&Semantic::Normals) {
        Some(a) => {
            same_count("NORMAL", &a)?;
            let v = vec3s(read_floats(
                ctx,
                &attr("NORMAL"),
                &a,
                buffers,
                Dimensions::Vec3,
                false,
            )?);
            Some(v.into_iter().map(|v| v.normalize_or_zero()).collect())
        }
        None => None,
    };
    let uvs = match p.get(&Semantic::TexCoords(0)) {
        Some(a) => {
            same_count("TEXCOORD_0", &a)?;
            let v = read_floats(
                ctx,
                &attr("TEXCOORD_0"),
                &a,
                buffers,
                Dimensions::Vec2,
                true,
            )?;
            Some(v.chunks_exact(2).map(|c| Vec2::new(c[0], c[1])).collect())
        }
        None => None,
    };
    let tangents = match p.get(&Semantic::Tangents) {
        Some(a) => {
            same_count("TANGENT", &a)?;
            let v = read_floats(ctx, &attr("TANGENT"), &a, buffers, Dimensions::Vec4, false)?;
            Some(
                v.chunks_exact(4)
                    .map(|c| [c[0], c[1], c[2], c[3]])
                    .collect(),
            )
        }
        None => None,
    };
    let indices: Vec<u32> = match p.indices() {
        Some(a) => {
            let ix = read_indices(ctx, &format!("{ptr}/indices"), &a, buffers)?;
            if let Some(k) = ix.iter().position(|&i| i as usize >= n) {
                return Err(ctx.err(
                    &format!("{ptr}/indices"),
                    format!(
                        "index {k} of accessor {} is {}: POSITION has {n} vertices",
                        a.index(),
                        ix[k]
                    ),
                ));
            }
            ix
        }
        None => (0..n as u32).collect(),
    };
    if indices.len() > 3 * (MAX_TRIANGLES + 2) {
        return Err(ctx.err(
            ptr,
            format!("more than {MAX_TRIANGLES} triangles: too large"),
        ));
    }
    let triangles: Vec<[u32; 3]> = match p.mode() {
        Mode::TriangleStrip => (2..indices.len())
            .map(|i| {
                let (a, b, c) = (indices[i - 2], indices[i - 1], indices[i]);
                if i % 2 == 0 { [a, b, c] } else { [b, a, c] }
            })
            .collect(),
        Mode::TriangleFan => (2..indices.len())
            .map(|i| [indices[i - 1], indices[i], indices[0]])
            .collect(),
        _ => {
            if !indices.len().is_multiple_of(3) {
                return Err(ctx.err(
                    ptr,
                    format!(
                        "{} indices (or vertices): not a whole number of triangles",
                        indices.len()
                    ),
                ));
            }
            indices
                .chunks_exact(3)
                .map(|c| [c[0], c[1], c[2]])
                .collect()
        }
    };
    Ok(Prim {
        positions,
        normals,
        uvs,
        tangents,
        triangles,
    })
}

/// Adds a primitive to its material's group, moved by `world`: normals by the inverse
/// transpose, the winding reversed where `world` mirrors; flat normals when the file has none
/// (each triangle its own three vertices, as the specification asks); MikkTSpace tangents
/// when the material `need`s them and the file has none.
fn add(g: &mut Group, mut p: Prim, world: Mat4, need: bool, ptr: &str, warnings: &mut Vec<String>) {
    if p.normals.is_none() {
        p = flat(p);
    }
    if need && p.tangents.is_none() {
        match &p.uvs {
            Some(_) => {
                p.tangents = Some(super::tangents::mikktspace(
                    &p.positions,
                    p.normals.as_deref().unwrap_or(&[]),
                    p.uvs.as_deref().unwrap_or(&[]),
                    &p.triangles,
                ))
            }
            None => warnings.push(format!(
                "{ptr}: an anisotropic material and neither TANGENT nor TEXCOORD_0: no tangents"
            )),
        }
    }
    let m3 = Mat3::from_mat4(world);
    let nm = m3.inverse().transpose();
    let mirror = m3.determinant() < 0.0;
    let base = g.positions.len() as u32;
    g.positions
        .extend(p.positions.iter().map(|&q| world.transform_point3(q)));
    let normals = p.normals.unwrap_or_default();
    g.normals
        .extend(normals.iter().map(|&v| (nm * v).normalize_or_zero()));
    match p.uvs {
        // glTF puts v = 0 at the top of an image, the renderer's textures at the bottom.
        Some(uv) => g.uvs.extend(uv.iter().map(|t| Vec2::new(t.x, 1.0 - t.y))),
        None => {
            g.all_uvs = false;
            g.uvs
                .extend(std::iter::repeat_n(Vec2::ZERO, p.positions.len()));
        }
    }
    match p.tangents {
        Some(t) => g.tangents.extend(t.iter().map(|t| {
            let v = (m3 * Vec3::new(t[0], t[1], t[2])).normalize_or_zero();
            [v.x, v.y, v.z, if mirror { -t[3] } else { t[3] }]
        })),
        None => {
            g.all_tangents = false;
            g.tangents
                .extend(std::iter::repeat_n([0.0; 4], p.positions.len()));
        }
    }
    g.triangles.extend(p.triangles.iter().map(|t| {
        let t = t.map(|i| i + base);
        if mirror { [t[0], t[2], t[1]] } else { t }
    }));
}

/// The primitive with one vertex per triangle corner and each triangle's normal.
fn flat(p: Prim) -> Prim {
    let mut out = Prim {
        positions: Vec::with_capacity(p.triangles.len() * 3),
        normals: Some(Vec::with_capacity(p.triangles.len() * 3)),
        uvs: p.uvs.as_ref().map(|_| Vec::new()),
        tangents: p.tangents.as_ref().map(|_| Vec::new()),
        triangles: Vec::with_capacity(p.triangles.len()),
    };
    for t in &p.triangles {
        let q = t.map(|i| p.positions[i as usize]);
        let n = (q[1] - q[0]).cross(q[2] - q[0]).normalize_or_zero();
        let base = out.positions.len() as u32;
        for &i in t {
            out.positions.push(p.positions[i as usize]);
            if let Some(ns) = out.normals.as_mut() {
                ns.push(n);
            }
            if let (Some(o), Some(s)) = (out.uvs.as_mut(), p.uvs.as_ref()) {
                o.push(s[i as usize]);
            }
            if let (Some(o), Some(s)) = (out.tangents.as_mut(), p.tangents.as_ref()) {
                o.push(s[i as usize]);
            }
        }
        out.triangles.push([base, base + 1, base + 2]);
    }
    out
}

/// Features of the file that the renderer does not use, named.
pub(super) fn unused_features(doc: &gltf::Document, warnings: &mut Vec<String>) {
    let n = doc.animations().len();
    if n > 0 {
        warnings.push(format!(
            "{n} animation(s): not played (the scene is drawn at rest)"
        ));
    }
    let cams = doc.cameras().len();
    if cams > 1 {
        warnings.push(format!(
            "{cams} cameras: the first one the scene uses is the view"
        ));
    }
    if doc.scenes().len() > 1 {
        warnings.push(format!(
            "{} scenes: only the default one is drawn",
            doc.scenes().len()
        ));
    }
}

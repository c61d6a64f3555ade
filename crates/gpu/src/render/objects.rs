//! One scene object on the GPU: its uniform, albedo texture, mesh buffers (corners dilated at
//! boundary edges for the rasteriser), model coefficients and a user's parameters, bound
//! together.

use super::layouts::{Layouts, USER_PARAMS_BINDING};
use super::scene_data::{check_binding, storage};
use crate::context::GpuError;
use fastbrdf_render::scene::{Object, Shape};
use fastbrdf_render::texture::Texture;
use glam::{Vec2, Vec3};
use std::collections::HashMap;
use wgpu::util::DeviceExt;

/// What one object needs on the GPU.
pub(super) struct GpuObject {
    pub(super) bind: wgpu::BindGroup,
    /// The key of its model's pipelines.
    pub(super) model: String,
    /// Mesh corners (three per triangle) and their count; none for spheres and planes.
    pub(super) corners: Option<(wgpu::Buffer, u32)>,
}

/// What one object puts on the GPU, as plain data: its uniform (`struct Object`), its linear
/// texels (RGBA f32, at least 1 x 1: the albedo texture's rows, then the specular tint's,
/// [`stacked_texels`]), its mesh buffers (`mesh_v`, `mesh_t`) and, for a
/// mesh, the rasteriser's triangle corners (dilated at boundary edges) with their count. The
/// native renderer uploads it ([`upload_object`]); `render::web` sends it to a browser.
pub(super) struct ObjectData {
    pub(super) uniform: Vec<u32>,
    pub(super) texture: (u32, u32, Vec<f32>),
    pub(super) vertices: Vec<f32>,
    pub(super) triangles: Vec<u32>,
    pub(super) corners: Option<(Vec<f32>, u32)>,
}

/// Index of kd (`albedo.w`) and ks (`mat.x`) in [`ObjectData::uniform`].
pub(super) const KD_WORD: usize = 19;
pub(super) const KS_WORD: usize = 20;
/// Index of the metallic-roughness table's words (`mr`) in [`ObjectData::uniform`].
pub(super) const MR_WORD: usize = 64;

/// The object's data (see [`ObjectData`]), checked against `limits`.
pub(super) fn object_data(
    limits: &wgpu::Limits,
    obj: &Object,
    index: usize,
    reach: &Reach,
) -> Result<ObjectData, GpuError> {
    let m = &obj.material;
    let zero4 = [0.0f32; 4];
    let (mut a, mut normal, mut tu, mut tv) = (zero4, zero4, zero4, zero4);
    let mut vertices: Vec<f32> = Vec::new();
    let mut triangles: Vec<u32> = Vec::new();
    let mut corners = None;
    let mut has_uvs = 0;
    let mut has_tangents = 0;
    let kind = match &obj.shape {
        Shape::Sphere(s) => {
            a = [s.center.x, s.center.y, s.center.z, s.radius];
            0
        }
        Shape::Plane(p) => {
            let (t, b) = p.normal.any_orthonormal_pair();
            a = [p.point.x, p.point.y, p.point.z, 0.0];
            normal = [p.normal.x, p.normal.y, p.normal.z, 0.0];
            tu = [t.x, t.y, t.z, 0.0];
            tv = [b.x, b.y, b.z, 0.0];
            1
        }
        Shape::Mesh(mesh) => {
            let nv = mesh.positions.len();
            if mesh.normals.len() != nv || !(mesh.uvs.is_empty() || mesh.uvs.len() == nv) {
                return Err(GpuError::Input(format!(
                    "object {index}: the mesh has {nv} positions, {} normals and {} uvs \
                     (normals must match the positions; uvs too, or be absent)",
                    mesh.normals.len(),
                    mesh.uvs.len()
                )));
            }
            if let Some(bad) = mesh.triangles.iter().flatten().find(|&&i| i as usize >= nv) {
                return Err(GpuError::Input(format!(
                    "object {index}: triangle vertex index {bad} is out of range ({nv} vertices)"
                )));
            }
            if !(mesh.tangents.is_empty() || mesh.tangents.len() == nv) {
                return Err(GpuError::Input(format!(
                    "object {index}: the mesh has {nv} positions and {} tangents",
                    mesh.tangents.len()
                )));
            }
            has_uvs = u32::from(!mesh.uvs.is_empty());
            has_tangents = u32::from(!mesh.tangents.is_empty());
            // 8 floats per vertex, 12 with a tangent (the shader's `rd_vertex`).
            vertices.reserve(if has_tangents != 0 { 12 } else { 8 } * nv);
            for i in 0..nv {
                let (p, nn) = (mesh.positions[i], mesh.normals[i]);
                let uv = mesh.uvs.get(i).copied().unwrap_or(Vec2::ZERO);
                vertices.extend([p.x, p.y, p.z, nn.x, nn.y, nn.z, uv.x, uv.y]);
                if let Some(t) = mesh.tangents.get(i) {
                    vertices.extend(t.to_array());
                }
            }
            triangles = with_boundary_edges(&mesh.positions, &mesh.triangles);
            let count = u32::try_from(3 * mesh.triangles.len())
                .map_err(|_| GpuError::Input(format!("object {index}: too many triangles")))?;
            let pos = dilate_boundaries(&mesh.positions, &triangles, reach);
            check_binding(limits, vertices.len() * 4, "the mesh's vertices")?;
            check_binding(limits, pos.len() * 4, "the mesh's triangle corners")?;
            corners = Some((pos, count));
            2
        }
    };
    let tint = m.specular.tint.as_ref().map(|t| &*t.texture);
    let maps = m.maps.as_deref();
    let normal_map = maps.and_then(|x| x.normal.as_ref());
    let occlusion = maps.and_then(|x| x.occlusion.as_ref());
    let emissive = maps.and_then(|x| x.emissive.as_ref());
    let mr = maps.and_then(|x| x.metallic_roughness.as_ref());
    let (tex_w, tex_h) = m.texture.as_ref().map_or((1, 1), |t| (t.width, t.height));
    // The albedo texture's rows, then the tint's, the normal, occlusion and emissive textures'.
    let parts = [
        m.texture.as_deref(),
        tint,
        normal_map.map(|x| &*x.texture),
        occlusion.map(|x| &*x.texture),
        emissive.and_then(|x| x.texture.as_deref()),
        mr.map(|x| &*x.texture),
    ];
    let (texture, rows) = stacked_texels(&parts);
    let max = limits.max_texture_dimension_2d;
    if texture.0 > max || texture.1 > max {
        let size = |t: &Texture| format!("{}x{}", t.width, t.height);
        let what = match (&m.texture, parts[1..].iter().all(Option::is_none)) {
            (Some(t), true) => format!("the texture is {}", size(t)),
            _ => format!(
                "object {index}'s textures ({}) stacked are {}x{}",
                parts
                    .iter()
                    .flatten()
                    .map(|t| size(t))
                    .collect::<Vec<_>>()
                    .join(", "),
                texture.0,
                texture.1
            ),
        };
        return Err(GpuError::Input(format!(
            "{what}, larger than the GPU's largest texture side ({max})"
        )));
    }
    // Per part: width, height, first row, and 1 when there is one.
    let part = |k: usize| parts[k].map_or([0, 0, 0, 0], |t| [t.width, t.height, rows[k], 1]);
    let (bump_scale, bump_depth) = m.bump.map_or((0.0, 0.0), |b| (b.scale, b.depth));
    let mut uniform: Vec<u32> = Vec::with_capacity(72);
    for v in [
        a,
        normal,
        tu,
        tv,
        [m.albedo.x, m.albedo.y, m.albedo.z, m.kd],
        [m.ks, bump_scale, bump_depth, 0.0],
        [tex_w as f32, tex_h as f32, 0.0, 0.0],
    ] {
        uniform.extend(v.map(f32::to_bits));
    }
    uniform.extend([
        kind,
        u32::from(m.texture.is_some()),
        u32::from(m.bump.is_some()),
        has_uvs,
    ]);
    // The object's id in the visibility pass: its index plus one (0 is no hit).
    let id = u32::try_from(index + 1)
        .map_err(|_| GpuError::Input(format!("object {index}: too many objects")))?;
    uniform.extend([tex_w, tex_h, id, has_tangents]);
    for k in 1..6 {
        uniform.extend(part(k));
    }
    // The normal texture's scale, the occlusion's strength; the emission (its factor: zero
    // without one).
    let scale = normal_map.map_or(1.0, |x| x.scale);
    let strength = occlusion.map_or(0.0, |x| x.strength);
    let e = emissive.map_or(Vec3::ZERO, |x| x.factor);
    for v in [[scale, strength, 0.0, 0.0], [e.x, e.y, e.z, 0.0]] {
        uniform.extend(v.map(f32::to_bits));
    }
    // The metallic-roughness table (`models::ModelShader::mr`, set by `upload_object`), the
    // factors and the number of levels.
    debug_assert_eq!(uniform.len(), MR_WORD);
    uniform.extend([0u32; 4]);
    let (metallic, roughness) = mr.map_or((0.0, 0.0), |x| (x.metallic, x.roughness));
    let levels = fastbrdf_render::maps::LEVELS as f32;
    uniform.extend([metallic, roughness, levels, 0.0].map(f32::to_bits));
    debug_assert_eq!(uniform[KD_WORD], m.kd.to_bits());
    debug_assert_eq!(uniform[KS_WORD], m.ks.to_bits());
    Ok(ObjectData {
        uniform,
        texture: (texture.0, texture.1, texture.2),
        vertices,
        triangles,
        corners,
    })
}

/// An object's data (`object_data`, its metallic-roughness words set), its model
/// coefficients (`coefs`, the model instance's `fb_k`; empty for a user's shader) and a
/// user's parameter block (`params`, [`crate::user::UserShader::param_block`]; empty for a
/// model) uploaded and bound together; `model` is its pipelines' key.
pub(super) fn upload_object(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    layouts: &Layouts,
    data: ObjectData,
    (coefs, params): (&[f32], &[f32]),
    model: String,
) -> Result<GpuObject, GpuError> {
    let corners = data.corners.map(|(pos, count)| {
        let buf = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("fastbrdf render corners"),
            contents: bytemuck::cast_slice(&pos),
            usage: wgpu::BufferUsages::VERTEX,
        });
        (buf, count)
    });
    let (tex_w, tex_h, texels) = &data.texture;
    let texture = device.create_texture_with_data(
        queue,
        &wgpu::TextureDescriptor {
            label: Some("fastbrdf render albedo"),
            size: wgpu::Extent3d {
                width: *tex_w,
                height: *tex_h,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba32Float,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        bytemuck::cast_slice(texels),
    );
    let uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("fastbrdf render object"),
        contents: bytemuck::cast_slice(&data.uniform),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let view = texture.create_view(&Default::default());
    let vertices = storage(device, "fastbrdf render vertices", &data.vertices);
    let triangles = storage(device, "fastbrdf render triangles", &data.triangles);
    let coefs = storage(device, "fastbrdf render coefficients", coefs);
    // At least one vec4 (a uniform binding is never empty; `FbUserParams` has K >= 1).
    let params = if params.is_empty() {
        &[0.0; 4][..]
    } else {
        params
    };
    let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("fastbrdf render user parameters"),
        contents: bytemuck::cast_slice(params),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("fastbrdf render object"),
        layout: &layouts.object,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: uniform.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::TextureView(&view),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: vertices.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 3,
                resource: triangles.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 4,
                resource: coefs.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: USER_PARAMS_BINDING,
                resource: params.as_entire_binding(),
            },
        ],
    });
    Ok(GpuObject {
        bind,
        model,
        corners,
    })
}

/// Where the camera is and how long one sample is at unit distance from it (world units).
pub(super) struct Reach {
    pub(super) eye: Vec3,
    pub(super) sample_per_distance: f32,
}

/// The triangle corners the rasteriser draws (three per triangle, world positions), with every
/// boundary edge pushed outward in its triangle's plane by a quarter of a sample.
///
/// Why: a sample exactly on a boundary edge (an axis-aligned triangle with corners on the
/// sample grid) is a hit for the CPU's inclusive ray-triangle test, but the rasteriser's
/// top-left rule may give no fragment there, and the GPU showed the background (up to 188/255
/// at 1 sample per pixel). Dilated, the rasteriser proposes those samples too; the fragment
/// shader's exact test (`rd_triangle`) still discards every sample outside a boundary edge, so
/// only the CPU's hits are drawn. Shared edges are not moved: across them the neighbour covers
/// the sample, as before. Each corner moves to the meeting point of its two (shifted or not)
/// edge lines, at most 8 shifts away (a needle's corner is not pushed to infinity).
fn dilate_boundaries(positions: &[Vec3], triangles: &[u32], reach: &Reach) -> Vec<f32> {
    let mut out = Vec::with_capacity(9 * triangles.len() / 4);
    for t in triangles.chunks_exact(4) {
        let p = [0, 1, 2].map(|k| positions[t[k] as usize]);
        let mask = t[3];
        let normal = (p[1] - p[0]).cross(p[2] - p[0]);
        let area2 = normal.length_squared();
        let corners = if mask == 0 || area2.is_nan() || area2 <= 0.0 {
            p
        } else {
            // Edge k runs from p[k] to p[k + 1]; bit 1 << k marks it as a boundary edge.
            let far = p
                .iter()
                .map(|q| q.distance(reach.eye))
                .fold(0.0f32, f32::max);
            let shift = 0.25 * reach.sample_per_distance * far;
            let edge = |k: usize| {
                let (a, b, c) = (p[k], p[(k + 1) % 3], p[(k + 2) % 3]);
                let mut o = (b - a).cross(normal).normalize_or_zero();
                if o.dot(c - a) > 0.0 {
                    o = -o;
                }
                let s = if mask & (1 << k) != 0 { shift } else { 0.0 };
                (o, s)
            };
            let e = [edge(0), edge(1), edge(2)];
            [0, 1, 2].map(|j| {
                // Corner j joins edge j - 1 (ending at p[j]) and edge j (starting there).
                let ((o1, s1), (o2, s2)) = (e[(j + 2) % 3], e[j]);
                let c = o1.dot(o2);
                let det = 1.0 - c * c;
                let d = if det > 1e-6 {
                    o1 * ((s1 - c * s2) / det) + o2 * ((s2 - c * s1) / det)
                } else {
                    o1 * s1 + o2 * s2
                };
                let cap = 8.0 * shift;
                let d = if d.length() > cap {
                    d * (cap / d.length())
                } else {
                    d
                };
                if d.is_finite() { p[j] + d } else { p[j] }
            })
        };
        out.extend(corners.iter().flat_map(|q| q.to_array()));
    }
    out
}

/// The triangles as `[a, b, c, mask]`, where the mask marks the edges no other triangle
/// shares (1: a-b, 2: b-c, 4: c-a). Edges are compared by their end points' positions, so
/// vertices duplicated at texture seams still join.
fn with_boundary_edges(positions: &[Vec3], triangles: &[[u32; 3]]) -> Vec<u32> {
    let key = |i: u32, j: u32| {
        let (p, q) = (
            positions[i as usize].to_array().map(f32::to_bits),
            positions[j as usize].to_array().map(f32::to_bits),
        );
        if p <= q { (p, q) } else { (q, p) }
    };
    let mut count: HashMap<([u32; 3], [u32; 3]), u32> = HashMap::new();
    for &[a, b, c] in triangles {
        for (i, j) in [(a, b), (b, c), (c, a)] {
            *count.entry(key(i, j)).or_default() += 1;
        }
    }
    let mut out = Vec::with_capacity(4 * triangles.len());
    for &[a, b, c] in triangles {
        let mut mask = 0;
        for (bit, (i, j)) in [(1, (a, b)), (2, (b, c)), (4, (c, a))] {
            if count[&key(i, j)] == 1 {
                mask |= bit;
            }
        }
        out.extend([a, b, c, mask]);
    }
    out
}

/// `t`'s linear texels as RGBA rows, top row first (the CPU's storage order).
fn linear_texels(t: &Texture) -> Vec<f32> {
    t.texels()
        .iter()
        .flat_map(|c| [c.x, c.y, c.z, 1.0])
        .collect()
}

/// One object's texture: the rows of each of `parts` that is there, in order (the albedo
/// texture's [`linear_texels`], the specular tint's, the glTF maps'), each row padded with
/// zeros to the widest; 1 x 1 zero without any. As ((width, height, texels), the first row of
/// each part: 0 for one that is absent).
#[allow(clippy::type_complexity)]
fn stacked_texels(parts: &[Option<&Texture>]) -> ((u32, u32, Vec<f32>), Vec<u32>) {
    let present: Vec<&Texture> = parts.iter().flatten().copied().collect();
    let mut rows = Vec::with_capacity(parts.len());
    let mut h = 0;
    for p in parts {
        rows.push(if p.is_some() { h } else { 0 });
        h += p.map_or(0, |t| t.height);
    }
    if present.is_empty() {
        return ((1, 1, vec![0.0; 4]), rows);
    }
    let w = present.iter().map(|t| t.width).max().unwrap_or(1);
    let mut out = Vec::with_capacity(4 * (w * h) as usize);
    for t in present {
        let texels = linear_texels(t);
        for row in texels.chunks_exact(4 * t.width as usize) {
            out.extend_from_slice(row);
            out.resize(out.len() + 4 * (w - t.width) as usize, 0.0);
        }
    }
    ((w, h, out), rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Texels go up in the CPU's order, as RGBA.
    #[test]
    fn texels_are_uploaded_in_order() {
        let texels: Vec<Vec3> = (0..6).map(|i| Vec3::new(i as f32, 0.5, 0.25)).collect();
        let got = linear_texels(&Texture::from_linear(3, 2, texels));
        assert_eq!(&got[..8], &[0.0, 0.5, 0.25, 1.0, 1.0, 0.5, 0.25, 1.0]);
        assert_eq!(got.len(), 24);
    }

    /// The tint's rows follow the albedo texture's, each row padded to the wider.
    #[test]
    fn textures_stack_albedo_then_tint() {
        let a = Texture::from_linear(1, 2, vec![Vec3::splat(0.5), Vec3::splat(0.25)]);
        let t = Texture::from_linear(2, 1, vec![Vec3::X, Vec3::Y]);
        let ((w, h, texels), rows) = stacked_texels(&[Some(&a), Some(&t)]);
        assert_eq!(rows, [0, 2]);
        assert_eq!((w, h), (2, 3));
        assert_eq!(
            texels,
            [
                [0.5, 0.5, 0.5, 1.0, 0.0, 0.0, 0.0, 0.0],
                [0.25, 0.25, 0.25, 1.0, 0.0, 0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0, 1.0, 0.0, 1.0, 0.0, 1.0]
            ]
            .concat()
        );
        assert_eq!(stacked_texels(&[None, Some(&t)]).0.0, 2);
        assert_eq!(stacked_texels(&[None, Some(&t)]).1, [0, 0]);
        assert_eq!(stacked_texels(&[Some(&t), None, Some(&a)]).1, [0, 0, 1]);
        assert_eq!(stacked_texels(&[None, None]).0, (1, 1, vec![0.0; 4]));
    }

    /// Boundary edges: a quad of two triangles has four, its diagonal is shared.
    #[test]
    fn boundary_edges_of_a_quad() {
        let p = vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y];
        let t = with_boundary_edges(&p, &[[0, 1, 2], [0, 2, 3]]);
        // a-b and b-c of the first, b-c and c-a of the second; c-a / a-b (0-2) shared.
        assert_eq!(t, vec![0, 1, 2, 1 | 2, 0, 2, 3, 2 | 4]);
    }
}

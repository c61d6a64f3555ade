//! What every pipeline reads besides the object: the frame uniform of a tile (camera, sample
//! grid, clip rows, shadow constants), the lights, and the occluders of the shadow rays;
//! storage buffers checked against the device's limits.

use super::{NEAR, Tile};
use crate::context::GpuError;
use fastbrdf_render::render::Options;
use fastbrdf_render::scene::{LightKind, SHADOW_EPS, Scene, Shape};
use glam::{DVec3, Vec3};
use wgpu::util::DeviceExt;

/// The camera frame exactly as `Camera::ray` computes it: (f, r, u, tan(fov/2), aspect).
fn camera_frame(scene: &Scene, w: u32, h: u32) -> (Vec3, Vec3, Vec3, f32, f32) {
    let (f, r, u, th) = scene.camera.frame();
    (f, r, u, th, w as f32 / h as f32)
}

/// The frame uniform of one tile (layout: `struct Frame` in the shader).
pub(super) fn frame_data(scene: &Scene, opts: &Options, tile: &Tile) -> Vec<u32> {
    let (w, h, n) = (opts.width, opts.height, opts.spp);
    let (f, r, u, th, aspect) = camera_frame(scene, w, h);
    let eye = scene.camera.eye;
    let v4 = |v: Vec3, w: f32| [v.x, v.y, v.z, w].map(f32::to_bits);
    // Clip coordinates of world point p, as linear forms in p - eye (f64, then f32): the
    // sample-grid position X = x N of `Camera::project`'s x (and Y likewise), local to the tile.
    let (fd, rd, ud) = (f.as_dvec3(), r.as_dvec3(), u.as_dvec3());
    let (thd, ad) = (f64::from(th), f64::from(aspect));
    let (sw, sh) = (f64::from(w * n), f64::from(h * n));
    let (x0, y0) = (f64::from(tile.x0), f64::from(tile.y0));
    let (tw, tht) = (f64::from(tile.w), f64::from(tile.h));
    // X z = (0.5 sw / (th aspect)) (r . d) + 0.5 sw z; clip_x = 2 (X - x0) z / tw - z.
    let xz = rd * (0.5 * sw / (thd * ad)) + fd * (0.5 * sw - x0);
    let clip_x = xz * (2.0 / tw) - fd;
    // Y z = 0.5 sh z - (0.5 sh / th) (u . d); clip_y = z - 2 (Y - y0) z / th.
    let yz = fd * (0.5 * sh - y0) - ud * (0.5 * sh / thd);
    let clip_y = fd - yz * (2.0 / tht);
    let eyed = eye.as_dvec3();
    let row = |a: DVec3, c: f64| [a.x, a.y, a.z, c - a.dot(eyed)].map(|x| (x as f32).to_bits());
    let mut out = Vec::with_capacity(48);
    out.extend(v4(eye, 0.0));
    out.extend(v4(f, 0.0));
    out.extend(v4(r, 0.0));
    out.extend(v4(u, 0.0));
    out.extend([th, aspect, w as f32, h as f32].map(f32::to_bits));
    out.extend(v4(scene.ambient, 0.0));
    out.extend([w, h, n, scene.lights.len() as u32]);
    out.extend([tile.x0, tile.y0, tile.w, tile.h]);
    out.extend(row(clip_x, 0.0));
    out.extend(row(clip_y, 0.0));
    out.extend(row(fd, -NEAR));
    out.extend(row(fd, 0.0));
    out.extend(
        [
            if scene.shadows { 1.0 } else { 0.0 },
            SHADOW_EPS,
            1.0 - 1e-5,
            f32::MAX,
        ]
        .map(f32::to_bits),
    );
    out
}

/// The lights as `struct Light` records (one zero record when there are none).
pub(super) fn lights_buffer(device: &wgpu::Device, scene: &Scene) -> wgpu::Buffer {
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("fastbrdf render lights"),
        contents: bytemuck::cast_slice(&lights_data(scene)),
        usage: wgpu::BufferUsages::STORAGE,
    })
}

/// The lights' records as data (8 f32 each; one zero record when there are none).
pub(super) fn lights_data(scene: &Scene) -> Vec<f32> {
    let mut data: Vec<f32> = Vec::with_capacity(8 * scene.lights.len().max(1));
    for l in &scene.lights {
        let (p, kind) = match l.kind {
            LightKind::Directional { to_light } => (to_light, 0.0),
            LightKind::Point { position } => (position, 1.0),
        };
        data.extend([
            p.x,
            p.y,
            p.z,
            kind,
            l.color.x,
            l.color.y,
            l.color.z,
            l.intensity,
        ]);
    }
    if data.is_empty() {
        data.resize(8, 0.0);
    }
    data
}

/// The scene's objects for the shadow rays (`struct Occluder`, `BvhNode` and `sh_tris` in
/// the shader): every object in scene order; every mesh's BVH nodes, rebased into one array
/// (inner nodes' children by the mesh's first node, leaves' triangles by its first
/// triangle); every mesh's triangle corners in its BVH's leaf order, so a leaf's triangles
/// are consecutive. With shadows off, only the (small) object records go up.
pub(super) struct Occluders {
    pub(super) objects: wgpu::Buffer,
    pub(super) nodes: wgpu::Buffer,
    pub(super) triangles: wgpu::Buffer,
}

impl Occluders {
    pub(super) fn new(device: &wgpu::Device, d: &OccluderData) -> Self {
        Self {
            objects: storage(device, "fastbrdf render occluders", &d.objects),
            nodes: storage(device, "fastbrdf render bvh nodes", &d.nodes),
            triangles: storage(device, "fastbrdf render shadow triangles", &d.triangles),
        }
    }
}

/// [`Occluders`] as data: the records, BVH nodes and triangle corners.
pub(super) struct OccluderData {
    pub(super) objects: Vec<[u32; 12]>,
    pub(super) nodes: Vec<[u32; 8]>,
    pub(super) triangles: Vec<f32>,
}

impl OccluderData {
    pub(super) fn new(limits: &wgpu::Limits, scene: &Scene) -> Result<Self, GpuError> {
        let mut objects: Vec<[u32; 12]> = Vec::with_capacity(scene.objects.len());
        let mut nodes: Vec<[u32; 8]> = Vec::new();
        let mut triangles: Vec<f32> = Vec::new();
        let bits = |v: [f32; 4]| v.map(f32::to_bits);
        for obj in &scene.objects {
            let (a, b, kind) = match &obj.shape {
                Shape::Sphere(s) => (
                    [s.center.x, s.center.y, s.center.z, s.radius],
                    [0.0; 4],
                    [0, 0, 0, 0],
                ),
                Shape::Plane(p) => (
                    [p.point.x, p.point.y, p.point.z, 0.0],
                    [p.normal.x, p.normal.y, p.normal.z, 0.0],
                    [1, 0, 0, 0],
                ),
                Shape::Mesh(m) if scene.shadows && !m.triangles.is_empty() => {
                    let (tree, order) = m.bvh();
                    let root = u32::try_from(nodes.len()).map_err(|_| too_many())?;
                    let first = u32::try_from(triangles.len() / 9).map_err(|_| too_many())?;
                    for node in tree {
                        let start = if node.count > 0 {
                            node.start.checked_add(first)
                        } else {
                            node.start.checked_add(root)
                        }
                        .ok_or_else(too_many)?;
                        let (lo, hi) = (node.lo, node.hi);
                        nodes.push([
                            lo.x.to_bits(),
                            lo.y.to_bits(),
                            lo.z.to_bits(),
                            start,
                            hi.x.to_bits(),
                            hi.y.to_bits(),
                            hi.z.to_bits(),
                            node.count,
                        ]);
                    }
                    check_binding(
                        limits,
                        nodes.len() * 32,
                        "the meshes' BVH nodes for the shadow rays (--shadows off needs none)",
                    )?;
                    check_binding(
                        limits,
                        (triangles.len() + 9 * order.len()) * 4,
                        "the meshes' triangles for the shadow rays (--shadows off needs none)",
                    )?;
                    triangles.reserve(9 * order.len());
                    for &t in order {
                        let tri = m.triangles.get(t as usize).ok_or_else(too_many)?;
                        for &i in tri {
                            let p = m.positions.get(i as usize).ok_or_else(|| {
                                GpuError::Input(format!(
                                    "a triangle vertex index {i} is out of range ({} vertices)",
                                    m.positions.len()
                                ))
                            })?;
                            triangles.extend(p.to_array());
                        }
                    }
                    ([0.0; 4], [0.0; 4], [2, root, 0, 0])
                }
                // No shadow rays, or no triangles: nothing to hit.
                Shape::Mesh(_) => ([0.0; 4], [0.0; 4], [3, 0, 0, 0]),
            };
            let mut rec = [0u32; 12];
            rec[..4].copy_from_slice(&bits(a));
            rec[4..8].copy_from_slice(&bits(b));
            rec[8..].copy_from_slice(&kind);
            objects.push(rec);
        }
        if objects.is_empty() {
            // No objects: one record that hits nothing (a zeroed one would be a sphere).
            objects.push([0, 0, 0, 0, 0, 0, 0, 0, 3, 0, 0, 0]);
        }
        Ok(Self {
            objects,
            nodes,
            triangles,
        })
    }
}

fn too_many() -> GpuError {
    GpuError::Input("the meshes have too many triangles for the GPU's shadow rays".into())
}

/// A storage buffer of `data`, or of one zero when `data` is empty.
pub(super) fn storage<T: bytemuck::Pod + bytemuck::Zeroable>(
    device: &wgpu::Device,
    label: &str,
    data: &[T],
) -> wgpu::Buffer {
    let one = [T::zeroed()];
    let data = if data.is_empty() { &one[..] } else { data };
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: bytemuck::cast_slice(data),
        usage: wgpu::BufferUsages::STORAGE,
    })
}

/// Checks a storage binding's size against the device's limit.
pub(super) fn check_binding(
    limits: &wgpu::Limits,
    bytes: usize,
    what: &str,
) -> Result<(), GpuError> {
    let cap = limits
        .max_storage_buffer_binding_size
        .min(limits.max_buffer_size);
    if bytes as u64 > cap {
        return Err(GpuError::Input(format!(
            "{what} takes {} MiB, more than the GPU's largest storage binding ({} MiB)",
            bytes >> 20,
            cap >> 20
        )));
    }
    Ok(())
}

//! MikkTSpace tangents (the `mikktspace` crate, the algorithm glTF names) for primitives
//! without a TANGENT attribute whose material needs one.
//!
//! The texture coordinates go in with v flipped (`1 - v`, v pointing up the image, as in
//! Blender, whose exporter writes the TANGENTs of most files): so the bitangent
//! `(N x T) w` points up the image, the +Y of a glTF normal texture ("+X is right and +Y is
//! up"), as the Khronos sample viewer's fallback frame (`b = N x T`) has it. With v as glTF
//! stores it (down the image) the sign `w` would reverse and a normal texture's green channel
//! would tilt normals the wrong way.

use glam::{Vec2, Vec3};

struct Geometry<'a> {
    positions: &'a [Vec3],
    normals: &'a [Vec3],
    uvs: &'a [Vec2],
    triangles: &'a [[u32; 3]],
    out: Vec<[f32; 4]>,
}

impl mikktspace::Geometry for Geometry<'_> {
    fn num_faces(&self) -> usize {
        self.triangles.len()
    }
    fn num_vertices_of_face(&self, _face: usize) -> usize {
        3
    }
    fn position(&self, face: usize, vert: usize) -> [f32; 3] {
        self.positions[self.triangles[face][vert] as usize].to_array()
    }
    fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
        self.normals[self.triangles[face][vert] as usize].to_array()
    }
    fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
        let uv = self.uvs[self.triangles[face][vert] as usize];
        [uv.x, 1.0 - uv.y]
    }
    fn set_tangent_encoded(&mut self, tangent: [f32; 4], face: usize, vert: usize) {
        self.out[self.triangles[face][vert] as usize] = tangent;
    }
}

/// Per-vertex tangents (xyz, w the bitangent's sign); a vertex shared by corners whose
/// tangents differ takes the last one (glTF files split vertices at UV seams). Zero where
/// MikkTSpace finds none (degenerate texture coordinates).
pub(crate) fn mikktspace(
    positions: &[Vec3],
    normals: &[Vec3],
    uvs: &[Vec2],
    triangles: &[[u32; 3]],
) -> Vec<[f32; 4]> {
    let mut g = Geometry {
        positions,
        normals,
        uvs,
        triangles,
        out: vec![[0.0; 4]; positions.len()],
    };
    mikktspace::generate_tangents(&mut g);
    g.out
}

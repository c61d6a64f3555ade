//! A small glTF 2.0 writer for tests: JSON built with serde_json, one binary buffer written as
//! a base64 data URI, a `.bin` file beside the scene or a `.glb`'s BIN chunk. Shared by the
//! render crate's tests and the CLI's (`#[path]`).
#![allow(dead_code)]

use serde_json::{Value, json};

/// A glTF document being built.
pub struct Doc {
    pub json: Value,
    pub bin: Vec<u8>,
}

/// Base64 (standard alphabet, padded).
pub fn base64(bytes: &[u8]) -> String {
    const A: &[u8] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for c in bytes.chunks(3) {
        let n = (u32::from(c[0]) << 16)
            | (u32::from(*c.get(1).unwrap_or(&0)) << 8)
            | u32::from(*c.get(2).unwrap_or(&0));
        for k in 0..4 {
            if k <= c.len() {
                out.push(A[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

impl Default for Doc {
    fn default() -> Self {
        Self::new()
    }
}

impl Doc {
    pub fn new() -> Self {
        Self {
            json: json!({"asset": {"version": "2.0"}}),
            bin: Vec::new(),
        }
    }

    /// Appends `v` to the top-level array `key`; returns its index.
    pub fn push(&mut self, key: &str, v: Value) -> usize {
        let a = self
            .json
            .as_object_mut()
            .unwrap()
            .entry(key)
            .or_insert(json!([]));
        let a = a.as_array_mut().unwrap();
        a.push(v);
        a.len() - 1
    }

    fn view(&mut self, bytes: &[u8]) -> usize {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let offset = self.bin.len();
        self.bin.extend_from_slice(bytes);
        self.push(
            "bufferViews",
            json!({"buffer": 0, "byteOffset": offset, "byteLength": bytes.len()}),
        )
    }

    /// A float accessor of type `ty` (`VEC3`...), with min and max.
    pub fn floats(&mut self, data: &[f32], ty: &str) -> usize {
        let n = match ty {
            "SCALAR" => 1,
            "VEC2" => 2,
            "VEC3" => 3,
            _ => 4,
        };
        let bytes: Vec<u8> = data.iter().flat_map(|x| x.to_le_bytes()).collect();
        let view = self.view(&bytes);
        let mut lo = vec![f32::MAX; n];
        let mut hi = vec![f32::MIN; n];
        for row in data.chunks(n) {
            for k in 0..n {
                lo[k] = lo[k].min(row[k]);
                hi[k] = hi[k].max(row[k]);
            }
        }
        self.push(
            "accessors",
            json!({"bufferView": view, "componentType": 5126, "count": data.len() / n,
                   "type": ty, "min": lo, "max": hi}),
        )
    }

    /// An unsigned-short index accessor.
    pub fn indices(&mut self, data: &[u16]) -> usize {
        let bytes: Vec<u8> = data.iter().flat_map(|x| x.to_le_bytes()).collect();
        let view = self.view(&bytes);
        self.push(
            "accessors",
            json!({"bufferView": view, "componentType": 5123, "count": data.len(), "type": "SCALAR"}),
        )
    }

    /// A mesh of one primitive with these attributes (name -> accessor), indices and material.
    pub fn mesh(
        &mut self,
        attributes: Value,
        indices: Option<usize>,
        material: Option<usize>,
    ) -> usize {
        let mut p = json!({"attributes": attributes});
        if let Some(i) = indices {
            p["indices"] = json!(i);
        }
        if let Some(m) = material {
            p["material"] = json!(m);
        }
        self.push("meshes", json!({"primitives": [p]}))
    }

    /// The default scene with these root nodes.
    pub fn scene(&mut self, nodes: &[usize]) {
        let s = self.push("scenes", json!({"nodes": nodes}));
        self.json["scene"] = json!(s);
    }

    /// Declares an extension used (and `required`).
    pub fn uses(&mut self, ext: &str, required: bool) {
        self.push("extensionsUsed", json!(ext));
        if required {
            self.push("extensionsRequired", json!(ext));
        }
    }

    fn with_buffer(&self, buffer: Value) -> Value {
        let mut j = self.json.clone();
        if !self.bin.is_empty() {
            j["buffers"] = json!([buffer]);
        }
        j
    }

    /// The `.gltf` text with the buffer as a data URI.
    pub fn gltf(&self) -> Vec<u8> {
        let uri = format!("data:application/octet-stream;base64,{}", base64(&self.bin));
        serde_json::to_vec_pretty(
            &self.with_buffer(json!({"byteLength": self.bin.len(), "uri": uri})),
        )
        .unwrap()
    }

    /// The `.gltf` text whose buffer is the file `uri` (write [`Doc::bin`] there).
    pub fn gltf_external(&self, uri: &str) -> Vec<u8> {
        serde_json::to_vec_pretty(
            &self.with_buffer(json!({"byteLength": self.bin.len(), "uri": uri})),
        )
        .unwrap()
    }

    /// The `.glb` bytes (JSON chunk, BIN chunk).
    pub fn glb(&self) -> Vec<u8> {
        let mut j =
            serde_json::to_vec(&self.with_buffer(json!({"byteLength": self.bin.len()}))).unwrap();
        while !j.len().is_multiple_of(4) {
            j.push(b' ');
        }
        let mut b = self.bin.clone();
        while !b.len().is_multiple_of(4) {
            b.push(0);
        }
        let total = 12 + 8 + j.len() + if b.is_empty() { 0 } else { 8 + b.len() };
        let mut out = Vec::new();
        out.extend_from_slice(b"glTF");
        out.extend_from_slice(&2u32.to_le_bytes());
        out.extend_from_slice(&(total as u32).to_le_bytes());
        out.extend_from_slice(&(j.len() as u32).to_le_bytes());
        out.extend_from_slice(&0x4E4F_534Au32.to_le_bytes());
        out.extend_from_slice(&j);
        if !b.is_empty() {
            out.extend_from_slice(&(b.len() as u32).to_le_bytes());
            out.extend_from_slice(&0x004E_4942u32.to_le_bytes());
            out.extend_from_slice(&b);
        }
        out
    }

    /// A unit quad in the xy plane (z = 0, facing +z), texture coordinates u along x, v along
    /// -y; `normals` adds +z normals. Returns the mesh.
    pub fn quad(&mut self, normals: bool, material: Option<usize>) -> usize {
        let pos = self.floats(
            &[
                -0.5, -0.5, 0.0, 0.5, -0.5, 0.0, 0.5, 0.5, 0.0, -0.5, 0.5, 0.0,
            ],
            "VEC3",
        );
        let uv = self.floats(&[0.0, 1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0], "VEC2");
        let idx = self.indices(&[0, 1, 2, 0, 2, 3]);
        let mut attrs = json!({"POSITION": pos, "TEXCOORD_0": uv});
        if normals {
            attrs["NORMAL"] = json!(self.floats(&[0.0, 0.0, 1.0].repeat(4), "VEC3"));
        }
        self.mesh(attrs, Some(idx), material)
    }

    /// A UV sphere of radius 1 at the origin with normals (`n` segments around).
    pub fn sphere(&mut self, n: usize, material: Option<usize>) -> usize {
        let (mut pos, mut nor, mut idx) = (Vec::new(), Vec::new(), Vec::new());
        let rings = n / 2;
        for i in 0..=rings {
            let th = std::f32::consts::PI * i as f32 / rings as f32;
            for j in 0..=n {
                let ph = 2.0 * std::f32::consts::PI * j as f32 / n as f32;
                let p = [th.sin() * ph.cos(), th.cos(), th.sin() * ph.sin()];
                pos.extend(p);
                nor.extend(p);
            }
        }
        let w = (n + 1) as u16;
        for i in 0..rings as u16 {
            for j in 0..n as u16 {
                let (a, b) = (i * w + j, (i + 1) * w + j);
                idx.extend([a, a + 1, b, a + 1, b + 1, b]);
            }
        }
        let p = self.floats(&pos, "VEC3");
        let q = self.floats(&nor, "VEC3");
        let i = self.indices(&idx);
        self.mesh(json!({"POSITION": p, "NORMAL": q}), Some(i), material)
    }
}

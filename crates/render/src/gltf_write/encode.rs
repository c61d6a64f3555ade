//! The writer's checks and encodings: the document checked object by object, then turned into
//! glTF JSON plus one binary buffer, and the GLB container.

use super::{Document, Geometry, LightKind, Material, invalid};
use crate::error::Result;
use serde_json::{Map, Value, json};

/// glTF's component types and buffer view targets.
const FLOAT: u32 = 5126;
const UNSIGNED_SHORT: u32 = 5123;
const UNSIGNED_INT: u32 = 5125;
const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;

/// Largest deviation of a normal's, tangent's or rotation's length from 1 accepted (the
/// validator's `ACCESSOR_NON_UNIT` allows 0.0005; this is stricter).
const UNIT_TOLERANCE: f32 = 2e-4;

/// Whether a length is 1 within [`UNIT_TOLERANCE`] (false for NaN).
fn unit(length: f32) -> bool {
    (length - 1.0).abs() <= UNIT_TOLERANCE
}

/// A number for the JSON: the shortest decimal that reads back as the same `f32`.
fn num(x: f32) -> Value {
    let shortest: f64 = x.to_string().parse().expect("an f32 prints as a number");
    json!(shortest)
}

fn nums(x: &[f32]) -> Value {
    Value::Array(x.iter().map(|&v| num(v)).collect())
}

fn finite(what: &str, x: &[f32]) -> Result<()> {
    if x.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(invalid(format!("{what}: {x:?} is not finite")))
    }
}

fn in_range(what: &str, x: f32, lo: f32, hi: f32) -> Result<()> {
    if (lo..=hi).contains(&x) {
        Ok(())
    } else {
        Err(invalid(format!("{what} = {x}: must be in [{lo}, {hi}]")))
    }
}

fn index(what: &str, i: usize, len: usize, of: &str) -> Result<()> {
    if i < len {
        Ok(())
    } else {
        Err(invalid(format!(
            "{what} = {i}: the document has {len} {of}"
        )))
    }
}

fn check_geometry(k: usize, g: &Geometry) -> Result<()> {
    let what = format!("geometry {k}");
    let n = g.positions.len();
    if n == 0 || g.triangles.is_empty() {
        return Err(invalid(format!("{what}: no vertices or no triangles")));
    }
    if n > u32::MAX as usize {
        return Err(invalid(format!("{what}: {n} vertices (at most 2^32 - 1)")));
    }
    for (name, len) in [
        ("normals", g.normals.len()),
        ("uvs", g.uvs.len()),
        ("tangents", g.tangents.len()),
    ] {
        if len != n && !(len == 0 && name != "normals") {
            return Err(invalid(format!("{what}: {len} {name} for {n} positions")));
        }
    }
    for (i, p) in g.positions.iter().enumerate() {
        finite(&format!("{what} position {i}"), &p.to_array())?;
    }
    for (i, v) in g.normals.iter().enumerate() {
        if !unit(v.length()) {
            return Err(invalid(format!(
                "{what} normal {i}: {v} is not a unit vector"
            )));
        }
    }
    for (i, t) in g.uvs.iter().enumerate() {
        finite(&format!("{what} uv {i}"), &t.to_array())?;
    }
    for (i, t) in g.tangents.iter().enumerate() {
        if !unit(t.truncate().length()) || t.w.abs() != 1.0 {
            return Err(invalid(format!(
                "{what} tangent {i}: {t} (xyz must be a unit vector, w = 1 or -1)"
            )));
        }
    }
    for (i, t) in g.triangles.iter().enumerate() {
        for &v in t {
            index(
                &format!("{what} triangle {i} vertex"),
                v as usize,
                n,
                "vertices",
            )?;
        }
    }
    Ok(())
}

fn check_material(k: usize, m: &Material) -> Result<()> {
    let what = |f: &str| format!("material {k} ({}) {f}", m.name);
    for (i, &c) in m.base_color.iter().enumerate() {
        in_range(&what(&format!("baseColorFactor[{i}]")), c, 0.0, 1.0)?;
    }
    in_range(&what("metallicFactor"), m.metallic, 0.0, 1.0)?;
    in_range(&what("roughnessFactor"), m.roughness, 0.0, 1.0)?;
    if let Some(ior) = m.ior
        && !(ior == 0.0 || (ior >= 1.0 && ior.is_finite()))
    {
        return Err(invalid(format!(
            "{} = {ior}: must be 0 or >= 1",
            what("ior")
        )));
    }
    if let Some(s) = m.specular {
        in_range(&what("specularFactor"), s.factor, 0.0, 1.0)?;
        for c in s.color {
            in_range(&what("specularColorFactor"), c, 0.0, f32::MAX)?;
        }
    }
    if let Some(c) = m.clearcoat {
        in_range(&what("clearcoatFactor"), c.factor, 0.0, 1.0)?;
        in_range(&what("clearcoatRoughnessFactor"), c.roughness, 0.0, 1.0)?;
    }
    if let Some(s) = m.sheen {
        for c in s.color {
            in_range(&what("sheenColorFactor"), c, 0.0, 1.0)?;
        }
        in_range(&what("sheenRoughnessFactor"), s.roughness, 0.0, 1.0)?;
    }
    if let Some(a) = m.anisotropy {
        in_range(&what("anisotropyStrength"), a.strength, 0.0, 1.0)?;
        finite(&what("anisotropyRotation"), &[a.rotation])?;
    }
    for c in m.emissive {
        in_range(&what("emissiveFactor"), c, 0.0, 1.0)?;
    }
    if let Some((_, scale)) = m.normal_texture {
        finite(&what("normalTexture.scale"), &[scale])?;
    }
    if let Some((_, strength)) = m.occlusion_texture {
        in_range(&what("occlusionTexture.strength"), strength, 0.0, 1.0)?;
    }
    Ok(())
}

/// Checks every object and every reference of `d`.
pub(super) fn check(d: &Document) -> Result<()> {
    for (k, g) in d.geometries.iter().enumerate() {
        check_geometry(k, g)?;
    }
    for (k, i) in d.images.iter().enumerate() {
        if !i.png.starts_with(b"\x89PNG\r\n\x1a\n") {
            return Err(invalid(format!("image {k} ({}): not a PNG file", i.name)));
        }
    }
    for (k, m) in d.materials.iter().enumerate() {
        check_material(k, m)?;
        for i in m.images() {
            index(
                &format!("material {k} ({}) texture", m.name),
                i,
                d.images.len(),
                "images",
            )?;
        }
    }
    for (k, m) in d.meshes.iter().enumerate() {
        if m.primitives.is_empty() {
            return Err(invalid(format!("mesh {k} ({}): no primitives", m.name)));
        }
        for p in &m.primitives {
            let what = format!("mesh {k} ({})", m.name);
            index(
                &format!("{what} geometry"),
                p.geometry,
                d.geometries.len(),
                "geometries",
            )?;
            if let Some(mat) = p.material {
                index(
                    &format!("{what} material"),
                    mat,
                    d.materials.len(),
                    "materials",
                )?;
                if !d.materials[mat].images().is_empty() && d.geometries[p.geometry].uvs.is_empty()
                {
                    return Err(invalid(format!(
                        "{what}: material {mat} has textures and geometry {} no texture coordinates",
                        p.geometry
                    )));
                }
            }
        }
    }
    for (k, c) in d.cameras.iter().enumerate() {
        let what = format!("camera {k} ({})", c.name);
        if !(c.yfov > 0.0 && c.yfov < std::f32::consts::PI) {
            return Err(invalid(format!(
                "{what} yfov = {}: must be in (0, pi)",
                c.yfov
            )));
        }
        if !(c.znear > 0.0 && c.znear.is_finite()) {
            return Err(invalid(format!("{what} znear = {}: must be > 0", c.znear)));
        }
        if let Some(f) = c.zfar
            && !(f > c.znear && f.is_finite())
        {
            return Err(invalid(format!("{what} zfar = {f}: must be > znear")));
        }
        if let Some(a) = c.aspect_ratio
            && !(a > 0.0 && a.is_finite())
        {
            return Err(invalid(format!("{what} aspectRatio = {a}: must be > 0")));
        }
    }
    for (k, l) in d.lights.iter().enumerate() {
        let what = |f: &str| format!("light {k} ({}) {f}", l.name);
        for c in l.color {
            in_range(&what("color"), c, 0.0, 1.0)?;
        }
        in_range(&what("intensity"), l.intensity, 0.0, f32::MAX)?;
        let range = match l.kind {
            LightKind::Directional => None,
            LightKind::Point { range } => range,
            LightKind::Spot {
                range,
                inner_cone,
                outer_cone,
            } => {
                let half = std::f32::consts::FRAC_PI_2;
                if !(0.0 <= inner_cone && inner_cone < outer_cone && outer_cone <= half) {
                    return Err(invalid(format!(
                        "{}: inner {inner_cone}, outer {outer_cone} (0 <= inner < outer <= pi/2)",
                        what("spot cone")
                    )));
                }
                range
            }
        };
        if let Some(r) = range
            && !(r > 0.0 && r.is_finite())
        {
            return Err(invalid(format!("{} = {r}: must be > 0", what("range"))));
        }
    }
    let mut parent = vec![None; d.nodes.len()];
    for (k, n) in d.nodes.iter().enumerate() {
        let what = format!("node {k} ({})", n.name);
        finite(&format!("{what} translation"), &n.translation.to_array())?;
        finite(&format!("{what} scale"), &n.scale.to_array())?;
        if !unit(n.rotation.length()) {
            return Err(invalid(format!(
                "{what} rotation {}: not a unit quaternion",
                n.rotation
            )));
        }
        if let Some(m) = n.mesh {
            index(&format!("{what} mesh"), m, d.meshes.len(), "meshes")?;
        }
        if let Some(c) = n.camera {
            index(&format!("{what} camera"), c, d.cameras.len(), "cameras")?;
        }
        if let Some(l) = n.light {
            index(&format!("{what} light"), l, d.lights.len(), "lights")?;
        }
        for &c in &n.children {
            index(&format!("{what} child"), c, d.nodes.len(), "nodes")?;
            if c == k || parent[c].is_some() {
                return Err(invalid(format!(
                    "{what} child {c}: already a child of a node"
                )));
            }
            parent[c] = Some(k);
        }
    }
    // A cycle through children would leave its nodes without a root: every node must reach one.
    for k in 0..d.nodes.len() {
        let (mut at, mut steps) = (k, 0);
        while let Some(p) = parent[at] {
            at = p;
            steps += 1;
            if steps > d.nodes.len() {
                return Err(invalid(format!("node {k}: its parents form a cycle")));
            }
        }
    }
    Ok(())
}

/// The buffer being filled and the buffer views and accessors that describe it.
struct Packer {
    bin: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl Packer {
    /// Appends `bytes` (4-byte aligned) as a buffer view; returns its index. `target` 0: none
    /// (an image's view).
    fn view(&mut self, bytes: &[u8], target: u32) -> usize {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let mut v = json!({
            "buffer": 0,
            "byteOffset": self.bin.len(),
            "byteLength": bytes.len(),
        });
        if target != 0 {
            v["target"] = target.into();
        }
        self.views.push(v);
        self.bin.extend_from_slice(bytes);
        self.views.len() - 1
    }

    /// A float vector attribute of `N` components (`VEC2`/`VEC3`/`VEC4`); `bounds` adds the
    /// exact per-component min and max (required for `POSITION`).
    fn floats<const N: usize>(&mut self, data: &[[f32; N]], bounds: bool) -> usize {
        let bytes: Vec<u8> = data
            .iter()
            .flatten()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        let view = self.view(&bytes, ARRAY_BUFFER);
        let mut a = json!({
            "bufferView": view,
            "componentType": FLOAT,
            "count": data.len(),
            "type": format!("VEC{N}"),
        });
        if bounds {
            let mut lo = [f32::INFINITY; N];
            let mut hi = [f32::NEG_INFINITY; N];
            for v in data {
                for c in 0..N {
                    lo[c] = lo[c].min(v[c]);
                    hi[c] = hi[c].max(v[c]);
                }
            }
            // Exact (f32 widened), not shortest: the validator compares them with the data.
            a["min"] = lo.iter().map(|&x| f64::from(x)).collect();
            a["max"] = hi.iter().map(|&x| f64::from(x)).collect();
        }
        self.accessors.push(a);
        self.accessors.len() - 1
    }

    /// The triangle indices as `SCALAR` u16 when every index fits (65535 is the primitive
    /// restart value, so u16 only below it), else u32.
    fn indices(&mut self, triangles: &[[u32; 3]], vertices: usize) -> usize {
        let small = vertices <= 65535;
        let bytes: Vec<u8> = if small {
            let to16 = |i: &u32| (*i as u16).to_le_bytes();
            triangles.iter().flatten().flat_map(to16).collect()
        } else {
            triangles
                .iter()
                .flatten()
                .flat_map(|i| i.to_le_bytes())
                .collect()
        };
        let view = self.view(&bytes, ELEMENT_ARRAY_BUFFER);
        self.accessors.push(json!({
            "bufferView": view,
            "componentType": if small { UNSIGNED_SHORT } else { UNSIGNED_INT },
            "count": triangles.len() * 3,
            "type": "SCALAR",
        }));
        self.accessors.len() - 1
    }
}

/// `name` when not empty.
fn named(mut v: Value, name: &str) -> Value {
    if !name.is_empty() {
        v["name"] = name.into();
    }
    v
}

fn material_json(m: &Material, used: &mut Vec<&'static str>) -> Value {
    let mut ext = Map::new();
    let mut add = |id: &'static str, v: Value| {
        if !used.contains(&id) {
            used.push(id);
        }
        ext.insert(id.into(), v);
    };
    if let Some(ior) = m.ior {
        add("KHR_materials_ior", json!({ "ior": num(ior) }));
    }
    if let Some(s) = m.specular {
        add(
            "KHR_materials_specular",
            json!({ "specularFactor": num(s.factor), "specularColorFactor": nums(&s.color) }),
        );
    }
    if let Some(c) = m.clearcoat {
        add(
            "KHR_materials_clearcoat",
            json!({ "clearcoatFactor": num(c.factor), "clearcoatRoughnessFactor": num(c.roughness) }),
        );
    }
    if let Some(s) = m.sheen {
        add(
            "KHR_materials_sheen",
            json!({ "sheenColorFactor": nums(&s.color), "sheenRoughnessFactor": num(s.roughness) }),
        );
    }
    if let Some(a) = m.anisotropy {
        add(
            "KHR_materials_anisotropy",
            json!({ "anisotropyStrength": num(a.strength), "anisotropyRotation": num(a.rotation) }),
        );
    }
    let mut v = json!({
        "pbrMetallicRoughness": {
            "baseColorFactor": nums(&m.base_color),
            "metallicFactor": num(m.metallic),
            "roughnessFactor": num(m.roughness),
        },
    });
    // Texture k is image k (one texture per image).
    if let Some(t) = m.base_color_texture {
        v["pbrMetallicRoughness"]["baseColorTexture"] = json!({ "index": t });
    }
    if let Some(t) = m.metallic_roughness_texture {
        v["pbrMetallicRoughness"]["metallicRoughnessTexture"] = json!({ "index": t });
    }
    if let Some((t, scale)) = m.normal_texture {
        v["normalTexture"] = json!({ "index": t, "scale": num(scale) });
    }
    if let Some((t, strength)) = m.occlusion_texture {
        v["occlusionTexture"] = json!({ "index": t, "strength": num(strength) });
    }
    if let Some(t) = m.emissive_texture {
        v["emissiveTexture"] = json!({ "index": t });
    }
    if m.emissive != [0.0; 3] {
        v["emissiveFactor"] = nums(&m.emissive);
    }
    if m.double_sided {
        v["doubleSided"] = true.into();
    }
    if !ext.is_empty() {
        v["extensions"] = Value::Object(ext);
    }
    named(v, &m.name)
}

/// The document as glTF JSON and its buffer (assumes [`check`] passed).
pub(super) fn json(d: &Document) -> (Value, Vec<u8>) {
    let mut p = Packer {
        bin: Vec::new(),
        views: Vec::new(),
        accessors: Vec::new(),
    };
    // Per geometry: its attributes object and its index accessor, shared by its primitives.
    let mut geometry = Vec::new();
    for g in &d.geometries {
        let mut attributes = Map::new();
        let arr3 = |v: &[glam::Vec3]| v.iter().map(|x| x.to_array()).collect::<Vec<_>>();
        let pos = p.floats(&arr3(&g.positions), true);
        attributes.insert("POSITION".into(), pos.into());
        let nrm = p.floats(&arr3(&g.normals), false);
        attributes.insert("NORMAL".into(), nrm.into());
        if !g.tangents.is_empty() {
            let t: Vec<[f32; 4]> = g.tangents.iter().map(|x| x.to_array()).collect();
            attributes.insert("TANGENT".into(), p.floats(&t, false).into());
        }
        if !g.uvs.is_empty() {
            let t: Vec<[f32; 2]> = g.uvs.iter().map(|x| x.to_array()).collect();
            attributes.insert("TEXCOORD_0".into(), p.floats(&t, false).into());
        }
        let indices = p.indices(&g.triangles, g.positions.len());
        geometry.push((Value::Object(attributes), indices));
    }
    // Images: PNG bytes in buffer views; texture k samples image k (linear, REPEAT).
    let images: Vec<Value> = d
        .images
        .iter()
        .map(|i| {
            let view = p.view(&i.png, 0);
            named(
                json!({ "bufferView": view, "mimeType": "image/png" }),
                &i.name,
            )
        })
        .collect();
    let textures: Vec<Value> = (0..d.images.len())
        .map(|k| json!({ "sampler": 0, "source": k }))
        .collect();
    let mut used = Vec::new();
    let materials: Vec<Value> = d
        .materials
        .iter()
        .map(|m| material_json(m, &mut used))
        .collect();
    let meshes: Vec<Value> = d
        .meshes
        .iter()
        .map(|m| {
            let prims: Vec<Value> = m
                .primitives
                .iter()
                .map(|q| {
                    let (attributes, indices) = &geometry[q.geometry];
                    let mut v = json!({ "attributes": attributes, "indices": indices, "mode": 4 });
                    if let Some(mat) = q.material {
                        v["material"] = mat.into();
                    }
                    v
                })
                .collect();
            named(json!({ "primitives": prims }), &m.name)
        })
        .collect();
    let cameras: Vec<Value> = d
        .cameras
        .iter()
        .map(|c| {
            let mut pers = json!({ "yfov": num(c.yfov), "znear": num(c.znear) });
            if let Some(f) = c.zfar {
                pers["zfar"] = num(f);
            }
            if let Some(a) = c.aspect_ratio {
                pers["aspectRatio"] = num(a);
            }
            named(
                json!({ "type": "perspective", "perspective": pers }),
                &c.name,
            )
        })
        .collect();
    let lights: Vec<Value> = d
        .lights
        .iter()
        .map(|l| {
            let mut v = json!({ "color": nums(&l.color), "intensity": num(l.intensity) });
            let range = match l.kind {
                LightKind::Directional => {
                    v["type"] = "directional".into();
                    None
                }
                LightKind::Point { range } => {
                    v["type"] = "point".into();
                    range
                }
                LightKind::Spot {
                    range,
                    inner_cone,
                    outer_cone,
                } => {
                    v["type"] = "spot".into();
                    v["spot"] = json!({
                        "innerConeAngle": num(inner_cone),
                        "outerConeAngle": num(outer_cone),
                    });
                    range
                }
            };
            if let Some(r) = range {
                v["range"] = num(r);
            }
            named(v, &l.name)
        })
        .collect();
    if !lights.is_empty() {
        used.push("KHR_lights_punctual");
    }
    let mut is_child = vec![false; d.nodes.len()];
    let nodes: Vec<Value> = d
        .nodes
        .iter()
        .map(|n| {
            let mut v = json!({});
            if n.translation != glam::Vec3::ZERO {
                v["translation"] = nums(&n.translation.to_array());
            }
            if n.rotation != glam::Quat::IDENTITY {
                v["rotation"] = nums(&n.rotation.normalize().to_array());
            }
            if n.scale != glam::Vec3::ONE {
                v["scale"] = nums(&n.scale.to_array());
            }
            if let Some(m) = n.mesh {
                v["mesh"] = m.into();
            }
            if let Some(c) = n.camera {
                v["camera"] = c.into();
            }
            if let Some(l) = n.light {
                v["extensions"] = json!({ "KHR_lights_punctual": { "light": l } });
            }
            if !n.children.is_empty() {
                for &c in &n.children {
                    is_child[c] = true;
                }
                v["children"] = json!(n.children);
            }
            named(v, &n.name)
        })
        .collect();
    let roots: Vec<usize> = (0..d.nodes.len()).filter(|&k| !is_child[k]).collect();
    let mut root = json!({
        "asset": { "version": "2.0", "generator": d.generator },
        "scene": 0,
        "scenes": [{ "nodes": roots }],
    });
    let mut put = |key: &str, v: Vec<Value>| {
        if !v.is_empty() {
            root[key] = Value::Array(v);
        }
    };
    put("nodes", nodes);
    put("meshes", meshes);
    put("materials", materials);
    let samplers = if images.is_empty() {
        vec![]
    } else {
        vec![json!({ "magFilter": 9729, "minFilter": 9729, "wrapS": 10497, "wrapT": 10497 })]
    };
    put("samplers", samplers);
    put("images", images);
    put("textures", textures);
    put("cameras", cameras);
    put("accessors", p.accessors);
    put("bufferViews", p.views);
    if !p.bin.is_empty() {
        root["buffers"] = json!([{ "byteLength": p.bin.len() }]);
    }
    if !lights.is_empty() {
        root["extensions"] = json!({ "KHR_lights_punctual": { "lights": lights } });
    }
    if !used.is_empty() {
        root["extensionsUsed"] = json!(used);
    }
    (root, p.bin)
}

/// The GLB container: header, JSON chunk (padded with spaces), binary chunk (padded with
/// zeros; left out when `bin` is empty).
pub(super) fn glb(text: &[u8], bin: &[u8]) -> Result<Vec<u8>> {
    let pad4 = |n: usize| n.next_multiple_of(4);
    let json_len = pad4(text.len());
    let bin_len = pad4(bin.len());
    let total = 12 + 8 + json_len + if bin.is_empty() { 0 } else { 8 + bin_len };
    if u32::try_from(total).is_err() {
        return Err(invalid(format!("{total} bytes: a GLB holds at most 4 GiB")));
    }
    let mut out = Vec::with_capacity(total);
    let u32le = |n: usize| (n as u32).to_le_bytes();
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&u32le(total));
    out.extend_from_slice(&u32le(json_len));
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(text);
    out.resize(20 + json_len, b' ');
    if !bin.is_empty() {
        out.extend_from_slice(&u32le(bin_len));
        out.extend_from_slice(b"BIN\0");
        out.extend_from_slice(bin);
        out.resize(total, 0);
    }
    Ok(out)
}

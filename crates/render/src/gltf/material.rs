//! glTF materials as the `gltf-pbr` model: the metallic-roughness factors and the
//! `KHR_materials_*` extensions' factors become the model's parameters (the mapping below),
//! read from the raw JSON so that every value is checked at its JSON pointer. The base colour,
//! metallic-roughness, normal, occlusion and emissive textures on `TEXCOORD_0` without
//! `KHR_texture_transform` are rendered (see `GltfScene::scene` and `crate::maps`), and the
//! emission; the extensions' textures, other texture coordinates and transforms, alpha modes
//! other than OPAQUE and the material extensions not read are named in a warning.
//!
//! | glTF | `gltf-pbr` |
//! |---|---|
//! | `pbrMetallicRoughness.baseColorFactor` (R, G, B; alpha not used) | `base_color` |
//! | `pbrMetallicRoughness.metallicFactor` | `metallic` |
//! | `pbrMetallicRoughness.roughnessFactor` | `roughness` |
//! | `KHR_materials_ior.ior` | `ior` |
//! | `KHR_materials_specular.specularFactor` | `specular` |
//! | `KHR_materials_specular.specularColorFactor` | `specular_color` |
//! | `KHR_materials_clearcoat.clearcoatFactor` | `clearcoat` |
//! | `KHR_materials_clearcoat.clearcoatRoughnessFactor` | `clearcoat_roughness` |
//! | `KHR_materials_sheen.sheenColorFactor` | `sheen_color` |
//! | `KHR_materials_sheen.sheenRoughnessFactor` | `sheen_roughness` |
//! | `KHR_materials_anisotropy.anisotropyStrength` | `anisotropy` |
//! | `KHR_materials_anisotropy.anisotropyRotation` | `anisotropy_rotation` |

use super::Ctx;
use crate::error::{RenderError, Result};
use fastbrdf::ModelSpec;
use serde_json::Value;

/// The model every glTF material is rendered with.
pub const MODEL_ID: &str = "gltf-pbr";

/// Material extensions whose factors are read.
const READ: &[&str] = &[
    "KHR_materials_ior",
    "KHR_materials_specular",
    "KHR_materials_clearcoat",
    "KHR_materials_sheen",
    "KHR_materials_anisotropy",
    "KHR_materials_emissive_strength",
];

/// One glTF material as `gltf-pbr` parameters.
#[derive(Clone, Debug, PartialEq)]
pub struct GltfMaterial {
    /// Its name in the file, or "" when it has none.
    pub name: String,
    /// Its JSON pointer (`/materials/3`), or `(default material)` for primitives without one.
    pub pointer: String,
    /// The `gltf-pbr` parameters, `NAME=VALUE` text as `--param` takes them.
    pub pairs: Vec<(String, String)>,
    /// Whether it needs tangents (anisotropy).
    pub needs_tangents: bool,
    /// Its `baseColorTexture` (a texture index) when it is rendered: on `TEXCOORD_0`, without
    /// `KHR_texture_transform`. Likewise the textures below.
    pub base_color_texture: Option<usize>,
    /// `pbrMetallicRoughness.metallicRoughnessTexture` (G roughness, B metallic).
    pub metallic_roughness_texture: Option<usize>,
    /// `normalTexture` and its `scale`.
    pub normal_texture: Option<(usize, f64)>,
    /// `occlusionTexture` and its `strength`.
    pub occlusion_texture: Option<(usize, f64)>,
    /// `emissiveTexture`.
    pub emissive_texture: Option<usize>,
    /// `emissiveFactor` x `KHR_materials_emissive_strength` (linear RGB; zero: no emission).
    pub emission: [f64; 3],
}

impl GltfMaterial {
    /// The specification's default material (base colour 1, metallic 1, roughness 1), used by
    /// primitives without a material.
    pub fn default_material() -> Self {
        Self {
            name: String::new(),
            pointer: "(default material)".into(),
            pairs: vec![
                ("base_color".into(), "1".into()),
                ("metallic".into(), "1".into()),
                ("roughness".into(), "1".into()),
            ],
            needs_tangents: false,
            base_color_texture: None,
            metallic_roughness_texture: None,
            normal_texture: None,
            occlusion_texture: None,
            emissive_texture: None,
            emission: [0.0; 3],
        }
    }

    /// The pairs with `overrides` replacing values of the same name (or added).
    pub fn pairs_with(&self, overrides: &[(String, String)]) -> Vec<(String, String)> {
        let mut out: Vec<(String, String)> = self
            .pairs
            .iter()
            .filter(|(k, _)| !overrides.iter().any(|(o, _)| o == k))
            .cloned()
            .collect();
        out.extend(overrides.iter().cloned());
        out
    }

    /// The `gltf-pbr` spec with `overrides` (see [`GltfMaterial::pairs_with`]); `file` names
    /// the scene in errors.
    pub fn spec(&self, file: &str, overrides: &[(String, String)]) -> Result<ModelSpec> {
        let parse = |pairs: &[(String, String)]| {
            let refs: Vec<(&str, &str)> = pairs
                .iter()
                .map(|(k, v)| (k.as_str(), v.as_str()))
                .collect();
            ModelSpec::parse(MODEL_ID, &refs)
        };
        parse(&self.pairs_with(overrides)).map_err(|e| {
            if !overrides.is_empty() && parse(&self.pairs).is_ok() {
                let given: Vec<String> =
                    overrides.iter().map(|(k, v)| format!("{k}={v}")).collect();
                RenderError::Invalid(format!(
                    "{} (given to every material of {file}): {e}",
                    given.join(" ")
                ))
            } else {
                RenderError::Input {
                    file: file.into(),
                    line: None,
                    message: format!("{}: {e}", self.pointer),
                }
            }
        })
    }

    /// The label of the material in messages: its pointer and name.
    pub fn label(&self) -> String {
        if self.name.is_empty() {
            self.pointer.clone()
        } else {
            format!(
                "{} '{}'",
                self.pointer,
                fastbrdf_io::shorten(&self.name, 40)
            )
        }
    }
}

/// The texture index of texture info `key` of `o` when it is rendered: on TEXCOORD_0 and not
/// transformed; else it is named in `unused`.
fn texture(o: &Obj, key: &str, unused: &mut Vec<String>) -> Option<usize> {
    let t = o.v.and_then(|v| v.get(key))?;
    let coord = t.get("texCoord").and_then(|v| v.as_u64()).unwrap_or(0);
    if coord != 0 {
        unused.push(format!(
            "{key} (on TEXCOORD_{coord}: only TEXCOORD_0 is read)"
        ));
        None
    } else if t.pointer("/extensions/KHR_texture_transform").is_some() {
        unused.push(format!("{key} (with KHR_texture_transform)"));
        None
    } else {
        t.get("index").and_then(|v| v.as_u64()).map(|i| i as usize)
    }
}

/// A number as text: the shortest that reads back the same.
fn num(x: f64) -> String {
    format!("{x}")
}

/// A colour as one value when grey (one channel: a third of the cost), else `R,G,B`.
fn colour(c: [f64; 3]) -> String {
    if c[0] == c[1] && c[1] == c[2] {
        num(c[0])
    } else {
        format!("{},{},{}", num(c[0]), num(c[1]), num(c[2]))
    }
}

/// `x` clamped to `[lo, hi]`, a clamped value named in `unused`.
fn clamp(unused: &mut Vec<String>, name: &str, x: f64, lo: f64, hi: f64, why: &str) -> f64 {
    if (lo..=hi).contains(&x) {
        x
    } else {
        let c = x.clamp(lo, hi);
        unused.push(format!("{name} {x} taken as {c} ({why})"));
        c
    }
}

/// The reader of one JSON object's factors, each checked at its pointer.
struct Obj<'a> {
    ctx: &'a Ctx,
    v: Option<&'a Value>,
    ptr: String,
}

impl<'a> Obj<'a> {
    fn new(ctx: &'a Ctx, parent: &'a Value, ptr: &str, key: &str) -> Result<Self> {
        let ptr = format!("{ptr}/{key}");
        let v = parent.get(key);
        if v.is_some_and(|v| !v.is_object()) {
            return Err(ctx.err(&ptr, "must be an object"));
        }
        Ok(Self { ctx, v, ptr })
    }

    /// Number `key` (default `default`), which glTF requires in `[lo, hi]`.
    fn number(&self, key: &str, default: f64, lo: f64, hi: f64) -> Result<f64> {
        let Some(v) = self.v.and_then(|o| o.get(key)) else {
            return Ok(default);
        };
        match v.as_f64() {
            Some(x) if x.is_finite() && (lo..=hi).contains(&x) => Ok(x),
            _ => Err(self.ctx.err(
                &format!("{}/{key}", self.ptr),
                format!(
                    "{} is not a number from {lo} to {}",
                    fastbrdf_io::shorten(&v.to_string(), 40),
                    if hi.is_finite() {
                        hi.to_string()
                    } else {
                        "infinity".into()
                    }
                ),
            )),
        }
    }

    /// Array `key` of `n` numbers in `[lo, hi]` (the first 3 returned).
    fn colour(&self, key: &str, n: usize, default: [f64; 3], lo: f64, hi: f64) -> Result<[f64; 3]> {
        let Some(v) = self.v.and_then(|o| o.get(key)) else {
            return Ok(default);
        };
        let bad = || {
            self.ctx.err(
                &format!("{}/{key}", self.ptr),
                format!(
                    "{} is not {n} numbers from {lo} to {}",
                    fastbrdf_io::shorten(&v.to_string(), 60),
                    if hi.is_finite() {
                        hi.to_string()
                    } else {
                        "infinity".into()
                    }
                ),
            )
        };
        let a = v.as_array().filter(|a| a.len() == n).ok_or_else(bad)?;
        let x: Vec<f64> = a
            .iter()
            .map(|x| {
                x.as_f64()
                    .filter(|x| x.is_finite() && (lo..=hi).contains(x))
            })
            .collect::<Option<_>>()
            .ok_or_else(bad)?;
        Ok([x[0], x[1], x[2]])
    }

    /// The texture references of this object (keys ending in `Texture`) but `skip`, named.
    fn textures(&self, out: &mut Vec<String>, skip: &[&str]) {
        let Some(o) = self.v.and_then(|v| v.as_object()) else {
            return;
        };
        for (k, t) in o {
            if k.ends_with("Texture") && !skip.contains(&k.as_str()) {
                let transform = t.pointer("/extensions/KHR_texture_transform").is_some();
                out.push(format!(
                    "{k}{}",
                    if transform {
                        " (with KHR_texture_transform)"
                    } else {
                        ""
                    }
                ));
            }
        }
    }
}

/// Every material of the file (`raw` is its JSON), in order; what is not rendered is named
/// in `warnings`, one line per material.
pub(crate) fn read_all(
    ctx: &Ctx,
    raw: &Value,
    warnings: &mut Vec<String>,
) -> Result<Vec<GltfMaterial>> {
    let Some(list) = raw.get("materials") else {
        return Ok(Vec::new());
    };
    let list = list
        .as_array()
        .ok_or_else(|| ctx.err("/materials", "must be an array"))?;
    list.iter()
        .enumerate()
        .map(|(i, m)| read(ctx, m, &format!("/materials/{i}"), warnings))
        .collect()
}

/// One material at pointer `ptr`.
pub(crate) fn read(
    ctx: &Ctx,
    m: &Value,
    ptr: &str,
    warnings: &mut Vec<String>,
) -> Result<GltfMaterial> {
    if !m.is_object() {
        return Err(ctx.err(ptr, "a material must be an object"));
    }
    let inf = f64::INFINITY;
    let mut unused = Vec::new();
    let mut pairs: Vec<(String, String)> = Vec::new();
    let mut put = |k: &str, v: String| pairs.push((k.into(), v));
    let top = Obj {
        ctx,
        v: Some(m),
        ptr: ptr.into(),
    };
    let pbr = Obj::new(ctx, m, ptr, "pbrMetallicRoughness")?;
    let bc = pbr.colour("baseColorFactor", 4, [1.0; 3], 0.0, 1.0)?;
    put("base_color", colour(bc));
    put(
        "metallic",
        num(pbr.number("metallicFactor", 1.0, 0.0, 1.0)?),
    );
    put(
        "roughness",
        num(pbr.number("roughnessFactor", 1.0, 0.0, 1.0)?),
    );
    // The core textures are rendered (`Specular::tint`, `crate::maps`) when they are on
    // TEXCOORD_0 and not transformed.
    let base_color_texture = texture(&pbr, "baseColorTexture", &mut unused);
    let metallic_roughness_texture = texture(&pbr, "metallicRoughnessTexture", &mut unused);
    let scaled = |key: &str, factor: &str, lo: f64, hi: f64, unused: &mut Vec<String>| {
        let Some(i) = texture(&top, key, unused) else {
            return Ok(None);
        };
        let info = Obj::new(ctx, m, ptr, key)?;
        Ok::<_, RenderError>(Some((i, info.number(factor, 1.0, lo, hi)?)))
    };
    let normal_texture = scaled("normalTexture", "scale", -inf, inf, &mut unused)?;
    let occlusion_texture = scaled("occlusionTexture", "strength", 0.0, 1.0, &mut unused)?;
    let emissive_texture = texture(&top, "emissiveTexture", &mut unused);
    let core = [
        "baseColorTexture",
        "metallicRoughnessTexture",
        "normalTexture",
        "occlusionTexture",
        "emissiveTexture",
    ];
    pbr.textures(&mut unused, &core);
    top.textures(&mut unused, &core);
    let ext = Obj::new(ctx, m, ptr, "extensions")?;
    let e = |name: &str| -> Result<Option<Obj>> {
        Ok(match ext.v.and_then(|x| x.get(name)) {
            Some(_) => Some(Obj::new(
                ctx,
                ext.v.unwrap_or(&Value::Null),
                &ext.ptr,
                name,
            )?),
            None => None,
        })
    };
    let mut needs_tangents = false;
    if let Some(o) = e("KHR_materials_ior")? {
        let ior = o.number("ior", 1.5, 0.0, inf)?;
        let ior = if ior == 0.0 {
            // The extension's 0 stands for an infinite index (f0 = 1): the model's largest.
            unused.push("ior 0 (infinite) taken as 5 (the model's range is 1 to 5)".into());
            5.0
        } else if ior < 1.0 {
            return Err(ctx.err(
                &format!("{}/ior", o.ptr),
                format!("{ior} is neither 0 nor at least 1"),
            ));
        } else {
            clamp(
                &mut unused,
                "ior",
                ior,
                1.0,
                5.0,
                "the model's range is 1 to 5",
            )
        };
        put("ior", num(ior));
    }
    if let Some(o) = e("KHR_materials_specular")? {
        put("specular", num(o.number("specularFactor", 1.0, 0.0, 1.0)?));
        let c = o.colour("specularColorFactor", 3, [1.0; 3], 0.0, inf)?;
        let c = c.map(|x| {
            clamp(
                &mut unused,
                "specularColorFactor",
                x,
                0.0,
                10.0,
                "the model's range is 0 to 10",
            )
        });
        put("specular_color", colour(c));
        o.textures(&mut unused, &[]);
    }
    if let Some(o) = e("KHR_materials_clearcoat")? {
        put(
            "clearcoat",
            num(o.number("clearcoatFactor", 0.0, 0.0, 1.0)?),
        );
        put(
            "clearcoat_roughness",
            num(o.number("clearcoatRoughnessFactor", 0.0, 0.0, 1.0)?),
        );
        o.textures(&mut unused, &[]);
    }
    if let Some(o) = e("KHR_materials_sheen")? {
        put(
            "sheen_color",
            colour(o.colour("sheenColorFactor", 3, [0.0; 3], 0.0, 1.0)?),
        );
        put(
            "sheen_roughness",
            num(o.number("sheenRoughnessFactor", 0.0, 0.0, 1.0)?),
        );
        o.textures(&mut unused, &[]);
    }
    if let Some(o) = e("KHR_materials_anisotropy")? {
        let s = o.number("anisotropyStrength", 0.0, 0.0, 1.0)?;
        put("anisotropy", num(s));
        put(
            "anisotropy_rotation",
            num(o.number("anisotropyRotation", 0.0, -inf, inf)?),
        );
        o.textures(&mut unused, &[]);
        needs_tangents = s > 0.0;
    }
    // A normal texture is applied in the tangent frame.
    needs_tangents |= normal_texture.is_some();
    let emissive = top.colour("emissiveFactor", 3, [0.0; 3], 0.0, 1.0)?;
    let strength = match e("KHR_materials_emissive_strength")? {
        Some(o) => o.number("emissiveStrength", 1.0, 0.0, inf)?,
        None => 1.0,
    };
    let emission = emissive.map(|x| x * strength);
    match m.get("alphaMode").and_then(|v| v.as_str()) {
        None | Some("OPAQUE") => {}
        Some(mode) => unused.push(format!(
            "alphaMode {} (rendered OPAQUE)",
            fastbrdf_io::shorten(mode, 20)
        )),
    }
    if let Some(x) = ext.v.and_then(|v| v.as_object()) {
        for k in x.keys().filter(|k| !READ.contains(&k.as_str())) {
            unused.push(format!("extension {}", fastbrdf_io::shorten(k, 60)));
        }
    }
    let name = m
        .get("name")
        .and_then(|v| v.as_str())
        .unwrap_or("")
        .to_string();
    let material = GltfMaterial {
        name,
        pointer: ptr.into(),
        pairs,
        needs_tangents,
        base_color_texture,
        metallic_roughness_texture,
        normal_texture,
        occlusion_texture,
        emissive_texture,
        emission,
    };
    if !unused.is_empty() {
        warnings.push(format!(
            "material {}: not rendered: {}",
            material.label(),
            unused.join(", ")
        ));
    }
    Ok(material)
}

//! The WGSL of an object's specular term (issue 33): `rd_brdf(wi, wo, h) -> RdSpec`, the value of
//! its model per colour channel (`RdSpec::f`) and, for a tinted term (`Specular::tint`, a glTF
//! base colour texture), of the model with the textured parameter at 0 (`RdSpec::zero`).
//!
//! # Slots
//!
//! The CPU evaluates one model instance per channel (`Specular::channels`: one grey, or R, G
//! and B) and, with a tint, the zero model's channels too: up to six instances, each a grey
//! model. Here each is a slot: a WGSL function and the offset of its coefficients in the
//! object's `fb_k`. Instances whose functions are the same text but for their coefficients
//! (the usual case: the channels differ only in numbers) share one function, which takes the
//! offset as an argument (`fb_k[o + i]` for the instance's `fb_k[i]`). `fb_k` starts with a
//! header, `[channels of the model, channels of the zero model (0 without a tint), then per
//! slot: function index, offset]` (small integers as f32, exact), then the coefficients.
//!
//! A block (a header and its slots) per specular term: the material's own at 0 and, with a
//! metallic-roughness texture (`maps::MetallicRoughness`), one per roughness level its texels
//! can select ([`level_range`]) and metallic 0 and 1, found through a table of block offsets
//! (level, corner) whose place the object uniform's `mr` gives. `rd_brdf(wi, wo, h)` evaluates
//! the block at `h`.
//!
//! With more than one slot, `rd_brdf` loops over the slots with a count read from `fb_k`, so
//! the compiler cannot unroll it: every distinct function is inlined once, however many slots
//! call it, and a coloured or tinted model costs the compile time of a grey one (lavapipe
//! compiles `gltf-pbr` slowly; six inlined copies took six times as long). Each slot's value
//! is its instance's, computed by the same function text as the grey model's, so channel c of
//! a coloured render is the grey render of channel c's model, as on the CPU.
//!
//! The pipelines are keyed by the module's text without the coefficients ([`ModelShader::key`]):
//! objects whose models differ only in numbers share them.

use crate::context::GpuError;
use crate::spec::Instance;
use fastbrdf::ModelSpec;
use fastbrdf_render::maps::{LEVELS, MetallicRoughness};
use fastbrdf_render::scene::Specular;

/// An object's specular term as WGSL: its functions and `rd_brdf`, and its `fb_k`.
pub(super) struct ModelShader {
    /// The functions, `rd_brdf` and the library items they call (a module's model part).
    pub(super) source: String,
    /// The functions and `rd_brdf` (what decides the module): the pipelines' key.
    pub(super) key: String,
    /// The header and every slot's coefficients.
    pub(super) coefs: Vec<f32>,
    /// The model's id, for messages.
    pub(super) id: String,
    /// With a metallic-roughness texture: the first entry of the level table in `fb_k`, the
    /// lowest and highest level in it, 1 (the object uniform's `mr`); zeros without.
    pub(super) mr: [u32; 4],
}

/// The roughness levels a metallic-roughness texture can select: those of its texels'
/// roughness, one more on either side (a bilinear mix lies between its texels, rounding
/// aside), within `0..=LEVELS`.
pub(super) fn level_range(mr: &MetallicRoughness) -> (u32, u32) {
    let level = |g: f32| ((mr.roughness * g).clamp(0.0, 1.0) * LEVELS as f32).round() as u32;
    let (lo, hi) = mr
        .texture
        .texels()
        .iter()
        .map(|t| level(t.y))
        .fold((LEVELS, 0), |(lo, hi), l| (lo.min(l), hi.max(l)));
    (lo.saturating_sub(1), (hi + 1).min(LEVELS))
}

/// The model of `spec` as [`ModelShader`]; with `mr` (a glTF metallic-roughness texture) also
/// its models at metallic 0 and 1 per roughness level it can select, each a block of slots
/// like the material's own, found through a table (level, corner) -> block. Errors: an RGB
/// BRDF (as the term or its tint's zero model), a term without a model spec, a model that is
/// not a BRDF or that has no WGSL instance.
pub(super) fn model_shader(
    spec: &Specular,
    mr: Option<&MetallicRoughness>,
) -> Result<ModelShader, GpuError> {
    let mut coefs = Vec::new();
    let mut functions: Vec<String> = Vec::new();
    let mut most = block(spec, &mut coefs, &mut functions)?;
    let mut table = [0u32; 4];
    if let Some(mr) = mr {
        let (lo, hi) = level_range(mr);
        let at = coefs.len();
        table = [at as u32, lo, hi, 1];
        coefs.resize(at + 2 * (hi - lo + 1) as usize, 0.0);
        for level in lo..=hi {
            for (c, corner) in mr.models(level).iter().enumerate() {
                coefs[at + 2 * (level - lo) as usize + c] = coefs.len() as f32;
                most = most.max(block(corner, &mut coefs, &mut functions)?);
            }
        }
    }
    let named: Vec<String> = functions
        .iter()
        .enumerate()
        .map(|(f, t)| t.replacen("fn rd_model(", &format!("fn rd_model_{f}("), 1))
        .collect();
    let glue = if most == 1 && mr.is_none() {
        // One grey instance: a plain call, its coefficients after the 4-entry header.
        "fn rd_brdf(wi: vec3<f32>, wo: vec3<f32>, h: u32) -> RdSpec {\n    return RdSpec(vec3<f32>(rd_model_0(wi, wo, h + 4u)), vec3<f32>(0.0));\n}\n".to_string()
    } else {
        let cases: String = (0..named.len())
            .map(|f| format!("            case {f}u: {{ x = rd_model_{f}(wi, wo, o); }}\n"))
            .collect();
        format!(
            "/// The slots of the block at `h` (render/models.rs): the model's channels, then its zero model's.\n\
             fn rd_brdf(wi: vec3<f32>, wo: vec3<f32>, h: u32) -> RdSpec {{\n    \
             var v = array<f32, 6>();\n    \
             let c0 = u32(fb_k[h]);\n    \
             let c1 = u32(fb_k[h + 1u]);\n    \
             for (var k = 0u; k < c0 + c1; k++) {{\n        \
             let o = u32(fb_k[h + 3u + 2u * k]);\n        \
             var x = 0.0;\n        \
             switch u32(fb_k[h + 2u + 2u * k]) {{\n{cases}            default: {{}}\n        }}\n        \
             v[k] = x;\n    }}\n    \
             var s = RdSpec(vec3<f32>(v[0]), vec3<f32>(0.0));\n    \
             if c0 == 3u {{\n        s.f = vec3<f32>(v[0], v[1], v[2]);\n    }}\n    \
             if c1 == 3u {{\n        s.zero = vec3<f32>(v[c0], v[c0 + 1u], v[c0 + 2u]);\n    }} else if c1 == 1u {{\n        s.zero = vec3<f32>(v[c0]);\n    }}\n    \
             return s;\n}}\n"
        )
    };
    let key = format!("{}\n{glue}", named.join("\n"));
    let source = format!("{}\n{key}", crate::library::closure_source(&key));
    Ok(ModelShader {
        source,
        key,
        coefs,
        id: spec.id.clone(),
        mr: table,
    })
}

/// Appends to `coefs` the block of `spec` (its header `[channels, zero model's channels, (function,
/// offset) per slot]` and its slots' coefficients), its distinct functions to `functions`;
/// returns its number of slots.
fn block(
    spec: &Specular,
    coefs: &mut Vec<f32>,
    functions: &mut Vec<String>,
) -> Result<usize, GpuError> {
    if spec.brdf.is_none() || spec.channels.is_empty() {
        return Err(GpuError::Input(format!(
            "'{}' is not a model spec: the GPU renderer shades with model instances",
            spec.id
        )));
    }
    let mut sets: Vec<Vec<&ModelSpec>> = vec![spec.channels.iter().map(|c| &c.spec).collect()];
    if let Some(t) = &spec.tint {
        if t.zero.rgb.is_some() || t.zero.channels.is_empty() {
            return Err(GpuError::Input(format!(
                "'{}': its tint's zero model is not a model spec: CPU-only",
                spec.id
            )));
        }
        sets.push(t.zero.channels.iter().map(|c| &c.spec).collect());
    }
    for set in &sets {
        if !(set.len() == 1 || set.len() == 3) {
            return Err(GpuError::Input(format!(
                "'{}': {} channels (1 or 3 are shaded)",
                spec.id,
                set.len()
            )));
        }
    }
    let slots: Vec<&ModelSpec> = sets.iter().flatten().copied().collect();
    let h = coefs.len();
    coefs.resize(h + 2 + 2 * slots.len(), 0.0);
    coefs[h] = sets[0].len() as f32;
    coefs[h + 1] = sets.get(1).map_or(0, Vec::len) as f32;
    for (k, s) in slots.iter().enumerate() {
        let inst = Instance::with_storage(s)?;
        if inst.info.kind != fastbrdf::Kind::Brdf {
            return Err(GpuError::Input(format!(
                "'{}' is not a BRDF: the renderer shades with BRDF instances",
                inst.info.id
            )));
        }
        let text = offset_form(&inst)?;
        let f = match functions.iter().position(|t| *t == text) {
            Some(f) => f,
            None => {
                functions.push(text);
                functions.len() - 1
            }
        };
        coefs[h + 2 + 2 * k] = f as f32;
        coefs[h + 3 + 2 * k] = coefs.len() as f32;
        coefs.extend(&inst.coefs);
    }
    Ok(slots.len())
}

/// `inst`'s function as `rd_model(wi, wo, o: u32)`, reading its coefficient `i` at
/// `fb_k[o + i]`, its doc comment dropped (it names the instance's values, which are data).
fn offset_form(inst: &Instance) -> Result<String, GpuError> {
    let sig = format!("fn {}({})", inst.function, inst.info.kind.wgsl_signature());
    let body: String = inst
        .wrapper
        .lines()
        .filter(|l| !l.trim_start().starts_with("///"))
        .map(|l| format!("{l}\n"))
        .collect();
    if body.matches(&sig).count() != 1 {
        return Err(GpuError::Input(format!(
            "{}: its WGSL function has an unexpected signature",
            inst.info.id
        )));
    }
    let body = body.replacen(
        &sig,
        &format!("fn rd_model({}, o: u32)", inst.info.kind.wgsl_signature()),
        1,
    );
    // fb_k[N] -> fb_k[o + Nu].
    let mut out = String::with_capacity(body.len() + 64);
    let mut rest = body.as_str();
    while let Some(i) = rest.find("fb_k[") {
        out.push_str(&rest[..i + 5]);
        rest = &rest[i + 5..];
        let digits = rest.bytes().take_while(u8::is_ascii_digit).count();
        if digits == 0 || !rest[digits..].starts_with(']') {
            return Err(GpuError::Input(format!(
                "{}: its WGSL function indexes fb_k other than by a number",
                inst.info.id
            )));
        }
        out.push_str(&format!("o + {}u", &rest[..digits]));
        rest = &rest[digits..];
    }
    out.push_str(rest);
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn specular(id: &str, given: &[(&str, &str)]) -> Specular {
        Specular::new(&ModelSpec::parse(id, given).unwrap()).unwrap()
    }

    /// The render module with `m` validates (naga).
    fn validates(m: &ModelShader) {
        super::super::naga_module(&format!("{}\n{}", super::super::SHADER, m.source));
    }

    /// A grey model: one slot, a plain call; coefficients after the header.
    #[test]
    fn a_grey_model_is_one_slot() {
        let s = specular("cook-torrance", &[("alpha", "0.3")]);
        let m = model_shader(&s, None).unwrap();
        let inst = Instance::with_storage(s.brdf.as_ref().unwrap()).unwrap();
        assert_eq!(&m.coefs[..4], &[1.0, 0.0, 0.0, 4.0]);
        assert_eq!(&m.coefs[4..], &inst.coefs[..]);
        assert!(m.key.contains("rd_model_0(wi, wo, h + 4u)"), "{}", m.key);
        assert!(m.key.contains("fb_k[o + 0u]"), "{}", m.key);
        assert!(!m.key.contains("fb_k[0]"), "{}", m.key);
        validates(&m);
    }

    /// A coloured model whose channels differ only in numbers: one function, three slots;
    /// another value of the same structure has the same key.
    #[test]
    fn coloured_channels_share_a_function() {
        let s = specular("cook-torrance", &[("f0", "0.9,0.6,0.3"), ("alpha", "0.3")]);
        let m = model_shader(&s, None).unwrap();
        let n = Instance::with_storage(&s.channels[0].spec)
            .unwrap()
            .coefs
            .len() as f32;
        assert_eq!(
            &m.coefs[..8],
            &[3.0, 0.0, 0.0, 8.0, 0.0, 8.0 + n, 0.0, 8.0 + 2.0 * n]
        );
        assert!(m.key.contains("fn rd_model_0(") && !m.key.contains("rd_model_1"));
        let other = specular("cook-torrance", &[("f0", "0.2,0.6,0.3"), ("alpha", "0.5")]);
        assert_eq!(model_shader(&other, None).unwrap().key, m.key);
        validates(&m);
        let g = Instance::with_storage(&s.channels[1].spec).unwrap();
        assert_eq!(&m.coefs[8 + n as usize..8 + 2 * n as usize], &g.coefs[..]);
    }

    /// A tinted term: the model's channels, then its zero model's (here grey), one function.
    #[test]
    fn a_tint_adds_the_zero_models_slots() {
        let given = [("base_color", "0.8,0.5,0.2"), ("metallic", "0")];
        let mut s = specular("gltf-pbr", &given);
        let zero = ModelSpec::parse("gltf-pbr", &[("base_color", "0"), ("metallic", "0")]);
        s.tint = Some(fastbrdf_render::scene::Tint {
            texture: std::sync::Arc::new(fastbrdf_render::texture::Texture::from_linear(
                1,
                1,
                vec![glam::Vec3::ONE],
            )),
            zero: std::sync::Arc::new(Specular::new(&zero.unwrap()).unwrap()),
        });
        let m = model_shader(&s, None).unwrap();
        assert_eq!(&m.coefs[..2], &[3.0, 1.0]);
        assert!(!m.key.contains("rd_model_1"), "{}", m.key);
        // The zero model's slot reads its own coefficients.
        let z = Instance::with_storage(&s.tint.as_ref().unwrap().zero.channels[0].spec).unwrap();
        let at = m.coefs[2 + 2 * 3 + 1] as usize;
        assert_eq!(&m.coefs[at..at + z.coefs.len()], &z.coefs[..]);
        assert_eq!(m.coefs.len(), at + z.coefs.len());
        validates(&m);
    }

    /// Channels whose functions differ (one with a sheen, one without) get one function each.
    #[test]
    fn different_channels_get_their_own_functions() {
        let s = specular(
            "gltf-pbr",
            &[("sheen_color", "0.5,0,0"), ("sheen_albedo", "none")],
        );
        let m = model_shader(&s, None).unwrap();
        assert!(m.key.contains("fn rd_model_1("), "{}", m.key);
        assert_eq!(m.coefs[2], 0.0);
        assert_eq!(m.coefs[4], 1.0);
        validates(&m);
    }
}

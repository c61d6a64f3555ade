//! glTF base colour textures: `gltf-pbr` is affine in its base colour, so a texture is
//! rendered exactly by mixing the model at its factor and at 0 per texel (`Specular::tint`).

mod gltf_build;

use fastbrdf_render::gltf;
use glam::Vec3;
use gltf_build::Doc;
use serde_json::json;
use std::path::Path;

fn opts(w: u32, h: u32) -> fastbrdf_render::render::Options {
    fastbrdf_render::render::Options {
        width: w,
        height: h,
        spp: 1,
        shading: fastbrdf_render::render::Shading::Batch,
        sampler: fastbrdf_render::render::Sampler::Sobol,
        aa: fastbrdf_render::render::Antialias::Grid,
    }
}

/// A PNG of `w` x `h` sRGB texels, row-major from the top.
fn png(w: u32, h: u32, texels: &[[u8; 3]]) -> Vec<u8> {
    let img = image::RgbImage::from_fn(w, h, |x, y| image::Rgb(texels[(y * w + x) as usize]));
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png).unwrap();
    out.into_inner()
}

/// A quad facing the camera with material `mat`, lit from the camera's side.
fn quad_scene(d: &mut Doc, mat: serde_json::Value) {
    let m = d.push("materials", mat);
    let q = d.quad(true, Some(m));
    let n = d.push("nodes", json!({"mesh": q}));
    let c = d.push(
        "cameras",
        json!({"type": "perspective", "perspective": {"yfov": 0.3, "znear": 0.1}}),
    );
    let cam = d.push(
        "nodes",
        json!({"camera": c, "translation": [0.0, 0.0, 3.0]}),
    );
    d.scene(&[n, cam]);
}

fn render_doc(bytes: &[u8], w: u32, h: u32) -> Vec<Vec3> {
    let s = gltf::from_bytes("t.glb", bytes, Path::new(".")).unwrap();
    let mut spec = fastbrdf_render::setup::SceneSpec::new();
    spec.lights = vec![fastbrdf_render::scene::Light::parse("dir:0.3,0.2,1").unwrap()];
    let scene = s.scene(&spec, None, &s.specs(&[]).unwrap()).unwrap();
    fastbrdf_render::render::render(&scene, &opts(w, h), &|_, _| {})
        .unwrap()
        .pixels
}

#[test]
fn gltf_pbr_is_affine_in_the_base_colour() {
    // What the textured base colour rests on: f(b) = f(0) + b (f(1) - f(0)), for every
    // extension's layer on.
    if fastbrdf::registry::find(gltf::MODEL_ID).is_err() {
        return;
    }
    let at = |b: &str| {
        let spec = fastbrdf::ModelSpec::parse(
            gltf::MODEL_ID,
            &[
                ("base_color", b),
                ("metallic", "0.4"),
                ("roughness", "0.35"),
                ("clearcoat", "0.7"),
                ("sheen_color", "0.6"),
                ("sheen_roughness", "0.4"),
                ("specular", "0.8"),
                ("ior", "1.7"),
            ],
        )
        .unwrap();
        let fastbrdf::Model::Brdf(f) = spec.model::<f64>().unwrap() else {
            panic!()
        };
        f
    };
    let (f0, fh, f1) = (at("0"), at("0.3"), at("1"));
    for k in 0..50 {
        let t = k as f64 * 0.61;
        let wi = [0.5 * t.cos(), 0.5 * t.sin(), (1.0f64 - 0.25).sqrt()];
        let wo = [-0.7 * (1.3 * t).sin(), 0.2 * (0.7 * t).cos(), 0.0];
        let wo = [wo[0], wo[1], (1.0 - wo[0] * wo[0] - wo[1] * wo[1]).sqrt()];
        let (a, b, c) = (f0.eval(wi, wo), fh.eval(wi, wo), f1.eval(wi, wo));
        let lerp = a + 0.3 * (c - a);
        assert!(
            (b - lerp).abs() <= 1e-9 * (1.0 + c.abs()),
            "{wi:?} {wo:?}: {b} != {lerp}"
        );
    }
}

#[test]
fn a_base_colour_texture_is_rendered_exactly_as_its_factor_would_be() {
    if fastbrdf::registry::find(gltf::MODEL_ID).is_err() {
        return;
    }
    let pbr = |extra: serde_json::Value| {
        let mut m = json!({"pbrMetallicRoughness": {"metallicFactor": 0.3, "roughnessFactor": 0.4,
            "baseColorFactor": [1.0, 0.5, 1.0, 1.0]},
            "extensions": {"KHR_materials_sheen": {"sheenColorFactor": [0.5, 0.5, 0.5], "sheenRoughnessFactor": 0.5}}});
        for (k, v) in extra.as_object().unwrap() {
            m["pbrMetallicRoughness"][k] = v.clone();
        }
        m
    };
    // A uniform texture (sRGB 128, 64, 200) times the factor (1, 0.5, 1) against the factor
    // (linear texel x factor) alone.
    let lin = |c: u8| fastbrdf_render::texture::srgb_to_linear(c as f32 / 255.0);
    let mut a = Doc::new();
    let img = a.push("images", json!({"uri": format!("data:image/png;base64,{}", gltf_build::base64(&png(1, 1, &[[128, 64, 200]])))}));
    a.push("textures", json!({"source": img}));
    quad_scene(&mut a, pbr(json!({"baseColorTexture": {"index": 0}})));
    let mut b = Doc::new();
    quad_scene(
        &mut b,
        pbr(json!({"baseColorFactor": [lin(128), 0.5 * lin(64), lin(200), 1.0]})),
    );
    let sa = gltf::from_bytes("t.gltf", &a.gltf(), Path::new(".")).unwrap();
    assert!(sa.textures[0].is_some());
    assert!(
        !sa.warnings.iter().any(|w| w.contains("baseColorTexture")),
        "{:?}",
        sa.warnings
    );
    let (pa, pb) = (render_doc(&a.glb(), 16, 16), render_doc(&b.glb(), 16, 16));
    let mut lit = 0;
    for (x, y) in pa.iter().zip(&pb) {
        assert!(
            (*x - *y).abs().max_element() <= 1e-4 * (1.0 + y.max_element()),
            "{x} != {y}"
        );
        lit += usize::from(y.max_element() > 0.05);
    }
    assert!(lit > 100, "the quad fills the picture: {lit}");
    // A texture of two halves (red left, blue right), in the .glb's buffer: each half its own.
    let mut d = Doc::new();
    let bytes = png(
        4,
        1,
        &[[230, 20, 20], [230, 20, 20], [20, 20, 230], [20, 20, 230]],
    );
    let view = d.bin.len();
    d.bin.extend_from_slice(&bytes);
    let v = d.push(
        "bufferViews",
        json!({"buffer": 0, "byteOffset": view, "byteLength": bytes.len()}),
    );
    let img = d.push("images", json!({"bufferView": v, "mimeType": "image/png"}));
    d.push("textures", json!({"source": img, "sampler": 0}));
    d.push("samplers", json!({"magFilter": 9728}));
    quad_scene(
        &mut d,
        json!({"pbrMetallicRoughness": {"metallicFactor": 0.0, "roughnessFactor": 0.6,
        "baseColorTexture": {"index": 0}}}),
    );
    let px = render_doc(&d.glb(), 32, 16);
    let (l, r) = (px[8 * 32 + 9], px[8 * 32 + 22]);
    assert!(l.x > 2.0 * l.z, "left red: {l}");
    assert!(r.z > 2.0 * r.x, "right blue: {r}");
}

#[test]
fn an_unusable_base_colour_texture_is_named_and_a_broken_image_is_an_error() {
    let mut d = Doc::new();
    let img = d.push(
        "images",
        json!({"uri": format!("data:image/png;base64,{}", gltf_build::base64(&png(1, 1, &[[9, 9, 9]])))}),
    );
    d.push("textures", json!({"source": img}));
    quad_scene(
        &mut d,
        json!({"pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "texCoord": 1}}}),
    );
    let s = gltf::from_bytes("t.gltf", &d.gltf(), Path::new(".")).unwrap();
    assert!(s.textures[0].is_none());
    assert!(
        s.warnings
            .iter()
            .any(|w| w.contains("baseColorTexture (on TEXCOORD_1: only TEXCOORD_0 is read)")),
        "{:?}",
        s.warnings
    );
    let mut d = Doc::new();
    d.push("images", json!({"uri": "data:image/png;base64,AAAA"}));
    d.push("textures", json!({"source": 0}));
    quad_scene(
        &mut d,
        json!({"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}),
    );
    let e = gltf::from_bytes("t.gltf", &d.gltf(), Path::new("."))
        .err()
        .unwrap()
        .to_string();
    assert!(e.starts_with("t.gltf: /images/0: "), "{e}");
}

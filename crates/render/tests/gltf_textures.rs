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

/// The scene of mesh `q` and a camera 3 units up +z looking at it.
fn viewed(d: &mut Doc, q: usize) {
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

/// A quad facing the camera with material `mat`, lit from the camera's side.
fn quad_scene(d: &mut Doc, mat: serde_json::Value) {
    let m = d.push("materials", mat);
    let q = d.quad(true, Some(m));
    viewed(d, q);
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

// The textures beyond the base colour (`fastbrdf_render::maps`).

/// `doc` with `pngs` as data-URI images and textures 0, 1, ... in order.
fn with_images(pngs: &[Vec<u8>]) -> Doc {
    let mut d = Doc::new();
    for p in pngs {
        let img = d.push(
            "images",
            json!({"uri": format!("data:image/png;base64,{}", gltf_build::base64(p))}),
        );
        d.push("textures", json!({"source": img}));
    }
    d
}

/// A quad facing the camera (as [`quad_scene`]) with the given NORMAL and, if any, TANGENT of
/// all four corners.
fn quad_with(d: &mut Doc, mat: serde_json::Value, normal: [f32; 3], tangent: Option<[f32; 4]>) {
    let m = d.push("materials", mat);
    let pos = d.floats(
        &[
            -0.5, -0.5, 0.0, 0.5, -0.5, 0.0, 0.5, 0.5, 0.0, -0.5, 0.5, 0.0,
        ],
        "VEC3",
    );
    let uv = d.floats(&[0.0, 1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0], "VEC2");
    let nor = d.floats(&normal.repeat(4), "VEC3");
    let idx = d.indices(&[0, 1, 2, 0, 2, 3]);
    let mut attrs = json!({"POSITION": pos, "TEXCOORD_0": uv, "NORMAL": nor});
    if let Some(t) = tangent {
        attrs["TANGENT"] = json!(d.floats(&t.repeat(4), "VEC4"));
    }
    let q = d.mesh(attrs, Some(idx), Some(m));
    viewed(d, q);
}

/// Asserts two renders agree to `tol` relative, and that the quad is lit in most pixels.
fn same(a: &[Vec3], b: &[Vec3], tol: f32) {
    let mut lit = 0;
    for (x, y) in a.iter().zip(b) {
        assert!(
            (*x - *y).abs().max_element() <= tol * (1.0 + y.max_element()),
            "{x} != {y}"
        );
        lit += usize::from(y.max_element() > 0.02);
    }
    assert!(lit > a.len() / 3, "the quad is lit: {lit} of {}", a.len());
}

#[test]
fn a_metallic_roughness_texture_is_rendered_as_its_factors_would_be() {
    if fastbrdf::registry::find(gltf::MODEL_ID).is_err() {
        return;
    }
    // One texel: roughness 102/255 = 0.4 (level 102 of 256), metallic 191/255, times the
    // factors 1 and 0.8; against those values as factors (the level's roughness).
    let pbr = |m: f64, r: f64, tex: bool| {
        let mut p = json!({"baseColorFactor": [0.9, 0.6, 0.3, 1.0], "metallicFactor": m,
            "roughnessFactor": r});
        if tex {
            p["metallicRoughnessTexture"] = json!({"index": 0});
        }
        json!({"pbrMetallicRoughness": p,
            "extensions": {"KHR_materials_clearcoat": {"clearcoatFactor": 0.5, "clearcoatRoughnessFactor": 0.2}}})
    };
    let mut a = with_images(&[png(1, 1, &[[7, 102, 191]])]);
    quad_scene(&mut a, pbr(0.8, 1.0, true));
    let sa = gltf::from_bytes("t.gltf", &a.gltf(), Path::new(".")).unwrap();
    assert!(sa.maps[0].metallic_roughness.is_some(), "{:?}", sa.warnings);
    let levels = fastbrdf_render::maps::LEVELS as f32;
    let level = (102.0f32 / 255.0 * levels).round() as f64 / levels as f64;
    let mut b = Doc::new();
    quad_scene(&mut b, pbr(0.8 * 191.0 / 255.0, level, false));
    same(
        &render_doc(&a.glb(), 16, 16),
        &render_doc(&b.glb(), 16, 16),
        1e-4,
    );
    // A texture of two halves (rough left, smooth right): each half its own roughness.
    let mut d = with_images(&[png(
        4,
        1,
        &[[0, 255, 0], [0, 255, 0], [0, 40, 0], [0, 40, 0]],
    )]);
    quad_scene(&mut d, pbr(0.0, 1.0, true));
    let px = render_doc(&d.glb(), 32, 16);
    for (x, r) in [
        (9, 1.0),
        (
            22,
            (40.0f32 / 255.0 * levels).round() as f64 / levels as f64,
        ),
    ] {
        let mut e = Doc::new();
        quad_scene(&mut e, pbr(0.0, r, false));
        let want = render_doc(&e.glb(), 32, 16)[8 * 32 + x];
        let got = px[8 * 32 + x];
        assert!(
            (got - want).abs().max_element() <= 1e-4 * (1.0 + want.max_element()),
            "x {x}: {got} != {want}"
        );
    }
    assert!(
        (px[8 * 32 + 9] - px[8 * 32 + 22]).abs().max_element() > 1e-3,
        "the halves differ"
    );
}

#[test]
fn a_normal_texture_tilts_the_normal_in_the_tangent_frame() {
    if fastbrdf::registry::find(gltf::MODEL_ID).is_err() {
        return;
    }
    let mat = json!({"pbrMetallicRoughness": {"metallicFactor": 0.0, "roughnessFactor": 0.5},
        "normalTexture": {"index": 0}});
    let unit = |b: u8| b as f32 / 255.0 * 2.0 - 1.0;
    // Texels leaning right (+X) and up the image (+Y); the quad's u runs along +x and up the
    // image along +y, so MikkTSpace's frame is (x, y, z). With a TANGENT of +y instead
    // (B = z x y = -x), +X of the texture leans along +y and +Y along -x.
    for (texel, tangent, lean) in [
        ([204u8, 128, 230], None, 0),
        ([128, 204, 230], None, 0),
        ([204, 128, 230], Some([0.0, 1.0, 0.0, 1.0]), 1),
    ] {
        let mut a = with_images(&[png(1, 1, &[texel])]);
        quad_with(&mut a, mat.clone(), [0.0, 0.0, 1.0], tangent);
        let s = gltf::from_bytes("t.gltf", &a.gltf(), Path::new(".")).unwrap();
        assert!(s.maps[0].normal.is_some(), "{:?}", s.warnings);
        let (side, up) = (unit(texel[0]), unit(texel[1]));
        let tilt = if lean == 0 {
            [side, up, unit(texel[2])]
        } else {
            [-up, side, unit(texel[2])]
        };
        let n = Vec3::from_array(tilt).normalize().to_array();
        let mut b = Doc::new();
        quad_with(
            &mut b,
            json!({"pbrMetallicRoughness": {"metallicFactor": 0.0, "roughnessFactor": 0.5}}),
            n,
            None,
        );
        same(
            &render_doc(&a.glb(), 16, 16),
            &render_doc(&b.glb(), 16, 16),
            1e-4,
        );
    }
}

#[test]
fn emission_is_added_and_occlusion_scales_the_environment() {
    if fastbrdf::registry::find(gltf::MODEL_ID).is_err() {
        return;
    }
    let lin = |c: u8| fastbrdf_render::texture::srgb_to_linear(c as f32 / 255.0);
    let base = json!({"metallicFactor": 0.0, "roughnessFactor": 0.5});
    let mut a = with_images(&[png(1, 1, &[[200, 100, 50]])]);
    quad_scene(
        &mut a,
        json!({"pbrMetallicRoughness": base, "emissiveFactor": [1.0, 0.5, 0.25],
            "emissiveTexture": {"index": 0},
            "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 2.0}}}),
    );
    let mut b = Doc::new();
    quad_scene(&mut b, json!({"pbrMetallicRoughness": base}));
    let (pa, pb) = (render_doc(&a.glb(), 16, 16), render_doc(&b.glb(), 16, 16));
    let emit = Vec3::new(2.0 * lin(200), lin(100), 0.5 * lin(50));
    let mut on = 0;
    for (x, y) in pa.iter().zip(&pb) {
        if *y != Vec3::splat(0.015) {
            // On the quad (not the background).
            assert!(
                (*x - *y - emit).abs().max_element() < 1e-5,
                "{x} - {y} != {emit}"
            );
            on += 1;
        }
    }
    assert!(on > 100, "{on}");
    // Occlusion 102/255 at strength 0.5 scales the white environment by 1 + 0.5 (0.4 - 1).
    let env = |mat: serde_json::Value, pngs: &[Vec<u8>]| {
        let mut d = with_images(pngs);
        quad_scene(&mut d, mat);
        let s = gltf::from_bytes("t.glb", &d.glb(), Path::new(".")).unwrap();
        let sky = std::sync::Arc::new(fastbrdf_render::env::EnvMap::from_spec("white").unwrap());
        let mut spec = fastbrdf_render::setup::SceneSpec::new();
        spec.env_samples = 4;
        let scene = s.scene(&spec, Some(sky), &s.specs(&[]).unwrap()).unwrap();
        fastbrdf_render::render::render(&scene, &opts(12, 12), &|_, _| {})
            .unwrap()
            .pixels
    };
    let occluded = env(
        json!({"pbrMetallicRoughness": base, "occlusionTexture": {"index": 0, "strength": 0.5}}),
        &[png(1, 1, &[[102, 0, 0]])],
    );
    let open = env(json!({"pbrMetallicRoughness": base}), &[]);
    let k = 1.0 + 0.5 * (102.0 / 255.0 - 1.0);
    let scaled: Vec<Vec3> = open.iter().map(|p| *p * k).collect();
    // The background (white) is not occluded: only the quad's pixels are compared.
    let quad: Vec<(Vec3, Vec3)> = occluded
        .iter()
        .zip(&scaled)
        .zip(&open)
        .filter(|(_, o)| (**o - Vec3::ONE).abs().max_element() > 1e-6)
        .map(|((a, b), _)| (*a, *b))
        .collect();
    assert!(quad.len() > 40, "{}", quad.len());
    for (x, y) in quad {
        assert!(
            (x - y).abs().max_element() <= 1e-5 * (1.0 + y.max_element()),
            "{x} != {y}"
        );
    }
}

#[test]
fn anisotropy_follows_the_files_tangents() {
    if fastbrdf::registry::find(gltf::MODEL_ID).is_err() {
        return;
    }
    let mat = |rot: f64| {
        json!({"pbrMetallicRoughness": {"metallicFactor": 1.0, "roughnessFactor": 0.5},
            "extensions": {"KHR_materials_anisotropy": {"anisotropyStrength": 0.9, "anisotropyRotation": rot}}})
    };
    let draw = |rot: f64, tangent: [f32; 4]| {
        let mut d = Doc::new();
        d.uses("KHR_materials_anisotropy", false);
        quad_with(&mut d, mat(rot), [0.0, 0.0, 1.0], Some(tangent));
        render_doc(&d.glb(), 16, 16)
    };
    // Direction T cos + B sin: T = +x at 0 and T = +y, B = (z x y) = -x at pi/2 are both
    // along x (the lobe is symmetric under reversal); T = +y at 0 is along y.
    let along_x = draw(0.0, [1.0, 0.0, 0.0, 1.0]);
    same(
        &along_x,
        &draw(std::f64::consts::FRAC_PI_2, [0.0, 1.0, 0.0, 1.0]),
        1e-4,
    );
    let along_y = draw(0.0, [0.0, 1.0, 0.0, 1.0]);
    let diff = along_x
        .iter()
        .zip(&along_y)
        .map(|(a, b)| (*a - *b).abs().max_element())
        .fold(0.0f32, f32::max);
    assert!(diff > 1e-2, "the tangent turns the highlight: {diff}");
}

#[test]
fn bad_texture_scalars_are_errors_at_their_pointers() {
    for (mat, ptr) in [
        (
            json!({"occlusionTexture": {"index": 0, "strength": 2.0}}),
            "/materials/0/occlusionTexture/strength",
        ),
        // A wrong type fails in the gltf crate's parser, which names the line and column.
        (
            json!({"normalTexture": {"index": 0, "scale": "big"}}),
            "expected f32 at line",
        ),
    ] {
        let mut d = with_images(&[png(1, 1, &[[128, 128, 255]])]);
        quad_scene(&mut d, mat);
        let e = gltf::from_bytes("t.gltf", &d.gltf(), Path::new("."))
            .err()
            .expect("refused")
            .to_string();
        assert!(e.contains(ptr), "{e}");
    }
}

//! Renderer tests: the highlight where the mirror direction predicts it, the face mesh lit from
//! the camera, identical models giving a zero difference, batch and scalar shading agreeing,
//! golden images. Bad inputs: tests/inputs.rs.

use fastbrdf::ModelSpec;
use fastbrdf_render::bump::Bump;
use fastbrdf_render::compare;
use fastbrdf_render::film::Film;
use fastbrdf_render::mesh::load_obj;
use fastbrdf_render::render::{Options, Shading, render};
use fastbrdf_render::scene::{Light, LightKind, Specular};
use fastbrdf_render::setup::{self, SceneSpec};
use glam::Vec3;
use std::path::{Path, PathBuf};
use std::sync::Arc;

fn face() -> PathBuf {
    PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/data/canonical_face_model.obj"
    ))
}

fn shoot(
    spec: &SceneSpec,
    id: &str,
    params: &[(&str, &str)],
    opts: Options,
) -> (Film, fastbrdf_render::scene::Camera) {
    let loaded = setup::load(spec).unwrap();
    let scene = setup::scene(
        spec,
        &loaded,
        Arc::new(Specular::new(&ModelSpec::parse(id, params).unwrap()).unwrap()),
    );
    (render(&scene, &opts, &|_, _| {}).unwrap(), scene.camera)
}

fn opts(w: u32, h: u32, spp: u32) -> Options {
    Options {
        width: w,
        height: h,
        spp,
        shading: Shading::Batch,
        sampler: fastbrdf_render::render::Sampler::default(),
        aa: fastbrdf_render::render::Antialias::default(),
    }
}

fn lum(c: Vec3) -> f32 {
    0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
}

#[test]
fn the_highlight_sits_where_the_mirror_direction_predicts() {
    for to_light in [
        Vec3::Z,
        Vec3::new(0.5, 0.3, 1.0).normalize(),
        Vec3::new(-0.6, -0.2, 0.8).normalize(),
    ] {
        let mut spec = SceneSpec::new();
        spec.kd = 0.0;
        spec.ks = 1.0;
        spec.lights = vec![Light {
            kind: LightKind::Directional { to_light },
            color: Vec3::ONE,
            intensity: 1.0,
        }];
        let (w, h) = (201, 201);
        let (film, cam) = shoot(&spec, "pow", &[("n", "5000")], opts(w, h, 1));
        let (mut best, mut at) = (0.0, (0, 0));
        for y in 0..h {
            for x in 0..w {
                if lum(film.at(x, y)) > best {
                    best = lum(film.at(x, y));
                    at = (x, y);
                }
            }
        }
        // Prediction by geometry alone: the sphere point whose mirror reflection of the view
        // direction is the light direction.
        let (mut err_best, mut pred) = (f32::INFINITY, (0, 0));
        for y in 0..h {
            for x in 0..w {
                let ray = cam.ray(x as f32 + 0.5, y as f32 + 0.5, w, h);
                let oc = ray.o;
                let b = oc.dot(ray.d);
                let disc = b * b - (oc.length_squared() - 1.0);
                if disc < 0.0 {
                    continue;
                }
                let n = (ray.o + (-b - disc.sqrt()) * ray.d).normalize();
                let v = -ray.d;
                let r = 2.0 * n.dot(v) * n - v;
                let e = (r - to_light).length();
                if e < err_best {
                    err_best = e;
                    pred = (x, y);
                }
            }
        }
        let d =
            ((at.0 as f32 - pred.0 as f32).powi(2) + (at.1 as f32 - pred.1 as f32).powi(2)).sqrt();
        assert!(
            d <= 1.5,
            "light {to_light}: brightest pixel {at:?}, mirror prediction {pred:?}"
        );
    }
}

#[test]
fn face_mesh_lit_from_the_camera_has_a_bright_nose_and_dark_cheek_edge() {
    let mut spec = SceneSpec::new();
    spec.mesh = Some(face());
    spec.lights = vec![Light {
        kind: LightKind::Directional { to_light: Vec3::Z },
        color: Vec3::ONE,
        intensity: 2.0,
    }];
    let (w, h) = (256, 256);
    let (film, cam) = shoot(&spec, "cook-torrance", &[("alpha", "0.4")], opts(w, h, 2));
    let covered = film.pixels.iter().filter(|p| lum(**p) > 0.05).count();
    assert!(
        covered > (w * h) as usize / 5,
        "the face covers only {covered} pixels"
    );
    let nose = cam.project(Vec3::new(0.0, -0.463, 7.587), w, h);
    // A vertex near the right cheek's silhouette (large |x|, small z).
    let cheek = cam.project(Vec3::new(7.2, -1.0, 1.0), w, h);
    let around = |(x, y): (f32, f32)| {
        let mut s = 0.0;
        for dy in -1..=1 {
            for dx in -1..=1 {
                s += lum(film.at((x as i32 + dx) as u32, (y as i32 + dy) as u32));
            }
        }
        s / 9.0
    };
    let (ln, lc) = (around(nose), around(cheek));
    assert!(ln > 2.0 * lc && lc > 0.0, "nose {ln} vs cheek edge {lc}");
    // Normals were computed (the file has none), smooth and facing out at the nose tip.
    let mesh = load_obj(&face()).unwrap();
    assert_eq!(mesh.triangles.len(), 898);
    let tip = mesh
        .positions
        .iter()
        .position(|p| (*p - Vec3::new(0.0, -0.463_17, 7.586_58)).length() < 1e-4)
        .unwrap();
    assert!(
        mesh.normals[tip].z.abs() > 0.9,
        "nose tip normal {}",
        mesh.normals[tip]
    );
}

#[test]
fn identical_models_give_zero_difference_and_infinite_psnr() {
    let spec = SceneSpec::new();
    let (a, _) = shoot(&spec, "ward", &[("alpha", "0.3")], opts(64, 64, 1));
    let (b, _) = shoot(&spec, "ward", &[("alpha", "0.3")], opts(64, 64, 1));
    let (ra, rb) = (a.to_srgb8(1.0), b.to_srgb8(1.0));
    let m = compare::metrics("ward", &ra, &rb, 64, 64);
    assert_eq!(m.rmse, 0.0);
    assert!(m.psnr.is_infinite() && m.flip == 0.0);
    assert!(compare::difference(&ra, &rb).iter().all(|d| *d == 0.0));
    // And a different model does differ.
    let (c, _) = shoot(&spec, "ward-power16", &[("alpha", "0.3")], opts(64, 64, 1));
    let m = compare::metrics("ward-power16", &ra, &c.to_srgb8(1.0), 64, 64);
    assert!(m.rmse > 0.0 && m.psnr.is_finite() && m.flip > 0.0);
}

#[test]
fn batch_and_scalar_shading_agree() {
    let mut spec = SceneSpec::new();
    spec.bump = Some(Bump {
        scale: 30.0,
        depth: 0.5,
    });
    for (id, p) in [
        ("flog", ("n", "80")),
        ("cook-torrance", ("alpha", "0.2")),
        ("beckmann-power16", ("alpha", "0.3")),
    ] {
        let (a, _) = shoot(&spec, id, &[p], opts(96, 96, 1));
        let (b, _) = shoot(
            &spec,
            id,
            &[p],
            Options {
                shading: Shading::Scalar,
                sampler: fastbrdf_render::render::Sampler::default(),
                aa: fastbrdf_render::render::Antialias::default(),
                ..opts(96, 96, 1)
            },
        );
        let worst = a
            .pixels
            .iter()
            .zip(&b.pixels)
            .map(|(x, y)| (*x - *y).abs().max_element() / y.max_element().max(1.0))
            .fold(0.0, f32::max);
        assert!(worst < 1e-4, "{id}: batch and scalar differ by {worst}");
    }
}

/// Golden images: small scenes rendered and compared with checked-in PNGs. Tolerance: at most
/// 2/255 per channel and PSNR >= 45 dB, because the batch kernels' results can differ in the
/// last bits between CPUs (libm's sin/cos/sqrt used by the camera and bump are not
/// bit-reproducible across platforms). Set FASTBRDF_BLESS=1 to rewrite them.
#[test]
fn golden_images() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden");
    let mut bumpy = SceneSpec::new();
    bumpy.bump = Some(Bump {
        scale: 25.0,
        depth: 0.5,
    });
    bumpy.albedo = Vec3::new(0.8, 0.5, 0.4);
    let mut floor = SceneSpec::new();
    floor.floor = true;
    // Checked in before shadows: the golden keeps the unshadowed picture (--shadows off).
    floor.shadows = false;
    floor.lights = vec![Light {
        kind: LightKind::Point {
            position: Vec3::new(2.0, 3.0, 3.0),
        },
        color: Vec3::new(1.0, 0.9, 0.8),
        intensity: 20.0,
    }];
    type Case<'a> = (&'a str, &'a SceneSpec, &'a str, &'a [(&'a str, &'a str)]);
    let cases: [Case; 4] = [
        ("sphere-pow-n50", &SceneSpec::new(), "pow", &[("n", "50")]),
        (
            "sphere-cubic-rational-n100",
            &SceneSpec::new(),
            "cubic-rational",
            &[("n", "100")],
        ),
        (
            "bumpy-cook-torrance",
            &bumpy,
            "cook-torrance",
            &[("alpha", "0.3"), ("f", "schlick")],
        ),
        (
            "floor-point-light-ward",
            &floor,
            "ward",
            &[("alpha", "0.2")],
        ),
    ];
    for (name, spec, id, params) in cases {
        let (film, _) = shoot(spec, id, params, opts(64, 64, 2));
        let got = film.to_srgb8(1.0);
        let path = dir.join(format!("{name}.png"));
        if std::env::var_os("FASTBRDF_BLESS").is_some() {
            std::fs::write(
                &path,
                fastbrdf_render::film::png_bytes(&got, 64, 64).unwrap(),
            )
            .unwrap();
            continue;
        }
        let want = image::open(&path)
            .unwrap_or_else(|e| panic!("{}: {e} (FASTBRDF_BLESS=1 creates it)", path.display()))
            .to_rgb8()
            .into_raw();
        let max = got
            .iter()
            .zip(&want)
            .map(|(a, b)| (*a as i32 - *b as i32).abs())
            .max()
            .unwrap();
        let m = compare::metrics(name, &want, &got, 64, 64);
        assert!(
            max <= 2 && m.psnr >= 45.0,
            "{name}: max difference {max}/255, PSNR {:.1} dB",
            m.psnr
        );
    }
}

/// A coloured model (per-channel parameters, issue 14): channel c of the picture is exactly
/// channel c of the grey picture of channel c's model, in batch and scalar shading, with a
/// coloured light and diffuse term (so a mixed-up channel or weight shows); and a grey model
/// is one channel. With grid antialiasing: adaptive refines pixels by the whole picture's
/// colour contrast, which differs between the coloured and the grey renders.
#[test]
fn a_coloured_render_is_three_grey_renders() {
    let mut spec = SceneSpec::new();
    spec.albedo = Vec3::new(0.7, 0.5, 0.3);
    spec.lights = vec![Light {
        kind: LightKind::Directional {
            to_light: Vec3::new(0.4, 0.5, 1.0).normalize(),
        },
        color: Vec3::new(1.0, 0.8, 0.6),
        intensity: 2.0,
    }];
    let gold = fastbrdf::colour::metal("gold").unwrap();
    let base = [("d", "ggx"), ("alpha", "0.2"), ("f", "conductor")];
    let (eta, k) = (
        format!("{},{},{}", gold.eta[0], gold.eta[1], gold.eta[2]),
        format!("{},{},{}", gold.k[0], gold.k[1], gold.k[2]),
    );
    for shading in [Shading::Batch, Shading::Scalar] {
        let o = Options {
            shading,
            aa: fastbrdf_render::render::Antialias::Grid,
            ..opts(48, 40, 2)
        };
        let mut coloured = base.to_vec();
        coloured.extend([("eta", eta.as_str()), ("k", k.as_str())]);
        let (rgb, _) = shoot(&spec, "cook-torrance", &coloured, o);
        for c in 0..3 {
            let (e, kk) = (gold.eta[c].to_string(), gold.k[c].to_string());
            let mut grey = base.to_vec();
            grey.extend([("eta", e.as_str()), ("k", kk.as_str())]);
            let (one, _) = shoot(&spec, "cook-torrance", &grey, o);
            let mut lit = 0;
            for (a, b) in rgb.pixels.iter().zip(&one.pixels) {
                assert_eq!(a[c].to_bits(), b[c].to_bits(), "{shading:?} channel {c}");
                lit += usize::from(a[c] > 0.1);
            }
            assert!(lit > 100, "{shading:?} channel {c}: the sphere is lit");
        }
    }
    let grey =
        Specular::new(&ModelSpec::parse("cook-torrance", &[("alpha", "0.2")]).unwrap()).unwrap();
    assert!(!grey.is_coloured() && grey.channels.len() == 1);
    let err = ModelSpec::parse("cook-torrance", &[("eta", "1,2")])
        .expect_err("two numbers are refused")
        .to_string();
    assert!(err.contains("eta") && err.contains("2 given"), "{err}");
}

#[test]
fn the_specular_model_is_the_shaded_spec() {
    let lobe = Specular::new(&ModelSpec::parse("flog", &[("n", "20")]).unwrap()).unwrap();
    let brdf = lobe.brdf.as_ref().expect("a model's specular has a spec");
    assert_eq!((lobe.id.as_str(), brdf.id()), ("flog", "blinn-phong"));
    assert_eq!(brdf.to_string(), "blinn-phong n=20 lobe=flog norm=none");
    let d = Specular::new(&ModelSpec::parse("ggx", &[("alpha", "0.3")]).unwrap()).unwrap();
    assert_eq!(
        d.brdf.as_ref().unwrap().to_string(),
        "cook-torrance alpha=0.3 d=ggx"
    );
    let err = Specular::new(&ModelSpec::parse("smith", &[]).unwrap())
        .err()
        .expect("a shadowing term is refused")
        .to_string();
    assert!(
        err.contains("'smith' is a shadowing, not something to shade with"),
        "{err}"
    );
}

/// `Rays::extend_row` (four lanes at a time) gives `Rays::ray`'s rays to the bit: whole rows,
/// lengths that leave a partial chunk, positions off the pixel centres and at the image's
/// edges, for two cameras and image shapes.
#[test]
fn a_row_of_rays_is_ray_by_ray_to_the_bit() {
    use fastbrdf_render::scene::Camera;
    let sphere = Camera {
        eye: Vec3::new(0.0, 0.0, 4.6),
        target: Vec3::ZERO,
        up: Vec3::Y,
        fov_y_deg: 30.0,
    };
    let tilted = Camera::framing(
        Vec3::new(-1.0, -2.0, 0.5),
        Vec3::new(3.0, 1.0, 2.0),
        Vec3::new(0.3, -0.2, -1.0),
        42.0,
    );
    for (camera, w, h) in [(sphere, 512, 512), (tilted, 37, 19)] {
        let rays = camera.rays(w, h);
        let xs: Vec<f32> = (0..w)
            .map(|x| x as f32 + 0.5)
            .chain([0.0, 3.125, w as f32, 0.001])
            .collect();
        for y in [0.0, 0.5, 7.25, h as f32 - 0.5, h as f32] {
            for len in [0, 1, 2, 3, 4, 5, 7, 8, 9, xs.len()] {
                let mut out = vec![rays.ray(1.0, 1.0)];
                rays.extend_row(&xs[..len], y, &mut out);
                assert_eq!(out.len(), len + 1, "appends");
                for (&x, r) in xs.iter().zip(&out[1..]) {
                    let want = rays.ray(x, y);
                    let bits = |v: Vec3| v.to_array().map(f32::to_bits);
                    assert_eq!(bits(r.o), bits(want.o), "origin at ({x}, {y})");
                    assert_eq!(bits(r.d), bits(want.d), "direction at ({x}, {y}), {w}x{h}");
                }
            }
        }
    }
}

/// A tile whose rays all see the background is filled without tracing them (its pixels the
/// background times their samples' share, as traced): the same pixels to the bit as the
/// traced path, which a plane behind the camera forces (no ray reaches it, but a plane bounds
/// no slopes, so nothing is skipped), for a small sphere and the face seen from afar (with its
/// bundles and, in a smaller picture, without), with and without the adaptive probe, one and
/// N x N samples, sizes that leave partial tiles.
#[test]
fn tiles_that_see_only_the_background_are_the_traced_pixels() {
    use fastbrdf_render::geometry::Plane;
    use fastbrdf_render::render::Antialias;
    use fastbrdf_render::scene::{Material, Object, Shape};
    let mut mesh = SceneSpec::new();
    mesh.mesh = Some(face());
    // The face at 203 x 141 has its bundles (32 pixels a triangle); at 96 x 64 (7) it has
    // none, and its bounding box bounds its slopes.
    for (what, spec, eye, (w, h)) in [
        (
            "sphere",
            SceneSpec::new(),
            Vec3::new(1.5, -0.7, 14.0),
            (203, 141),
        ),
        ("face", mesh.clone(), Vec3::new(4.0, 2.0, 40.0), (203, 141)),
        (
            "face without bundles",
            mesh,
            Vec3::new(4.0, 2.0, 30.0),
            (96, 64),
        ),
    ] {
        let loaded = setup::load(&spec).unwrap();
        let specular = Arc::new(
            Specular::new(&ModelSpec::parse("cook-torrance", &[("alpha", "0.3")]).unwrap())
                .unwrap(),
        );
        let mut scene = setup::scene(&spec, &loaded, specular.clone());
        scene.camera.eye += eye;
        scene.camera.target += Vec3::new(0.6 * eye.x, 0.6 * eye.y, 0.0);
        scene.shadows = false;
        let mut traced = setup::scene(&spec, &loaded, specular.clone());
        traced.camera = scene.camera;
        traced.shadows = false;
        let behind = scene.camera.eye + (scene.camera.eye - scene.camera.target);
        traced.objects.push(Object {
            shape: Shape::Plane(Plane {
                point: behind,
                normal: (scene.camera.eye - scene.camera.target).normalize(),
            }),
            material: Material {
                kd: 0.5,
                ks: 0.0,
                albedo: Vec3::ONE,
                texture: None,
                bump: None,
                specular,
                maps: None,
            },
        });
        for (aa, spp) in [
            (Antialias::Adaptive, 2),
            (Antialias::Adaptive, 3),
            (Antialias::Adaptive, 1),
            (Antialias::Grid, 2),
            (Antialias::Grid, 3),
        ] {
            let o = Options {
                aa,
                ..opts(w, h, spp)
            };
            let a = render(&scene, &o, &|_, _| {}).unwrap();
            let b = render(&traced, &o, &|_, _| {}).unwrap();
            let bits = |f: &Film| -> Vec<[u32; 3]> {
                f.pixels
                    .iter()
                    .map(|p| p.to_array().map(f32::to_bits))
                    .collect()
            };
            let object = a.pixels.iter().filter(|p| **p != a.pixels[0]).count();
            assert!(
                object > 50 && object < a.pixels.len() / 4,
                "{what}: the object should cover a little of the picture ({object} pixels)"
            );
            assert!(
                bits(&a) == bits(&b),
                "{what}, {aa:?} {spp}: the pixels differ"
            );
        }
    }
}

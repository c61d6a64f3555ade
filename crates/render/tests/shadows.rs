//! Shadow rays (issue 15): a sphere above a plane under a directional light darkens the plane
//! beneath it to the ambient term only, leaves the rest lit; a point light's shadow ray stops
//! at the light; a lit sphere does not shadow itself (no acne): with shadows on it renders as
//! with shadows off.

use fastbrdf::ModelSpec;
use fastbrdf_render::film::Film;
use fastbrdf_render::render::{Options, Shading, render};
use fastbrdf_render::scene::{Light, LightKind, Scene, Specular};
use fastbrdf_render::setup::{self, SceneSpec};
use glam::Vec3;
use std::sync::Arc;

fn scene(spec: &SceneSpec) -> Scene {
    let loaded = setup::load(spec).unwrap();
    let ward = ModelSpec::parse("ward", &[("alpha", "0.2")]).unwrap();
    setup::scene(spec, &loaded, Arc::new(Specular::new(&ward).unwrap()))
}

fn shoot(scene: &Scene, size: u32) -> Film {
    let o = Options {
        width: size,
        height: size,
        spp: 1,
        shading: Shading::Batch,
        sampler: fastbrdf_render::render::Sampler::default(),
        aa: fastbrdf_render::render::Antialias::default(),
    };
    render(scene, &o, &|_, _| {}).unwrap()
}

fn dir(x: f32, y: f32, z: f32, i: f32) -> Light {
    Light {
        kind: LightKind::Directional {
            to_light: Vec3::new(x, y, z).normalize(),
        },
        color: Vec3::ONE,
        intensity: i,
    }
}

/// The pixel whose centre ray hits the floor (object 1) nearest to world point `p`.
fn floor_pixel(scene: &Scene, p: Vec3, size: u32) -> usize {
    let (x, y) = scene.camera.project(p, size, size);
    let (x, y) = (x.floor() as u32, y.floor() as u32);
    let hit = scene
        .intersect(&scene.camera.ray(x as f32 + 0.5, y as f32 + 0.5, size, size))
        .expect("the floor is hit");
    assert_eq!(hit.object, 1, "pixel {x},{y} sees the floor");
    assert!((hit.p - p).length() < 0.2, "{:?} near {p:?}", hit.p);
    (y * size + x) as usize
}

#[test]
fn a_sphere_shadows_the_floor_beneath_it() {
    let mut spec = SceneSpec::new();
    spec.floor = true;
    spec.lights = vec![dir(0.0, 1.0, 0.0, 3.0)];
    let size = 128;
    let on = scene(&spec);
    spec.shadows = false;
    let off = scene(&spec);
    let (f_on, f_off) = (shoot(&on, size), shoot(&off, size));
    // Beneath the sphere (x^2 + z^2 < 1 on the plane y = -1): only the ambient term.
    let under = floor_pixel(&on, Vec3::new(0.0, -1.0, 0.8), size);
    // The floor material: kd 0.8, albedo 0.5, no specular; ambient 0.04.
    let ambient = 0.04 * 0.8 * 0.5;
    let got = f_on.pixels[under];
    assert!(
        (got - Vec3::splat(ambient)).abs().max_element() < 1e-6,
        "shadowed floor {got:?}, ambient {ambient}"
    );
    let lit_off = f_off.pixels[under];
    assert!(lit_off.x > 10.0 * ambient, "unshadowed {lit_off:?}");
    // Away from the sphere the floor is lit, identically with shadows on or off.
    let away = floor_pixel(&on, Vec3::new(1.1, -1.0, -0.8), size);
    let lit = f_on.pixels[away];
    let want = ambient + 3.0 * 0.8 * 0.5 / std::f32::consts::PI;
    assert!(
        (lit - Vec3::splat(want)).abs().max_element() < 1e-4,
        "lit floor {lit:?}, want {want}"
    );
    assert_eq!(lit, f_off.pixels[away]);
    // The sphere itself (top, facing the light) is lit.
    assert_eq!(
        f_on.pixels[(size / 2 * size + size / 2) as usize],
        f_off.pixels[(size / 2 * size + size / 2) as usize]
    );
}

#[test]
fn a_point_lights_shadow_ray_stops_at_the_light() {
    let s = scene(&SceneSpec::new());
    // From (-3, 0, 0) towards +x: the unit sphere at the origin lies beyond x = -1.
    let (p, n, l) = (Vec3::new(-3.0, 0.0, 0.0), Vec3::X, Vec3::X);
    assert!(
        !s.shadowed(p, n, l, 1.5),
        "light at x = -1.5, before the sphere"
    );
    assert!(
        s.shadowed(p, n, l, 5.0),
        "light at x = 2, behind the sphere"
    );
    assert!(s.shadowed(p, n, l, f32::INFINITY), "directional");
    assert!(!s.shadowed(p, n, -l, f32::INFINITY), "away from the sphere");
}

#[test]
fn a_lit_sphere_does_not_shadow_itself() {
    // Lights from many directions, grazing ones included, and a near point light: shadow
    // rays from a convex object's lit side must miss it (no acne), so the pictures match.
    let mut lights = vec![
        dir(-0.45, 0.55, 0.7, 3.0),
        dir(1.0, 0.0, 0.01, 2.0),
        dir(0.0, -1.0, 0.2, 1.0),
        dir(0.3, 0.2, -1.0, 1.0),
    ];
    lights.push(Light {
        kind: LightKind::Point {
            position: Vec3::new(1.2, 0.4, 1.1),
        },
        color: Vec3::ONE,
        intensity: 2.0,
    });
    for light in lights {
        let mut spec = SceneSpec::new();
        spec.lights = vec![light];
        let on = shoot(&scene(&spec), 96);
        spec.shadows = false;
        let off = shoot(&scene(&spec), 96);
        let worst = on
            .pixels
            .iter()
            .zip(&off.pixels)
            .map(|(a, b)| (*a - *b).abs().max_element())
            .fold(0.0f32, f32::max);
        assert!(
            worst == 0.0,
            "{light:?}: shadows changed a pixel by {worst}"
        );
    }
}

/// A direction uniform on the sphere.
fn unit_vector(rng: &mut fastbrdf_render::env::Rng) -> Vec3 {
    let z = 2.0 * rng.uniform() - 1.0;
    let phi = std::f32::consts::TAU * rng.uniform();
    let r = (1.0 - z * z).max(0.0).sqrt();
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// `Scene::shadowed_from` (the renderer's shadow test, which leaves a sphere or a plane out
/// of its own points' search) answers as `Scene::shadowed` (every object searched) for points
/// on the sphere and on the floor of the sphere-on-a-floor scene, towards directions on the
/// side the normal faces, grazing ones included: 20,000 rays each, both answers seen.
#[test]
fn leaving_a_convex_object_out_of_its_own_shadow_rays_changes_no_answer() {
    let mut spec = SceneSpec::new();
    spec.floor = true;
    let s = scene(&spec);
    assert_eq!(s.objects.len(), 2, "the sphere and the floor");
    let mut rng = fastbrdf_render::env::Rng::new(7, 11);
    let mut unit = || unit_vector(&mut rng);
    let mut seen = [[0u32; 2]; 2];
    for k in 0..40_000 {
        let on_sphere = k % 2 == 0;
        let (from, p, n) = if on_sphere {
            let n = unit();
            (0, n, n)
        } else {
            let q = unit() * 3.0;
            (1, Vec3::new(q.x, -1.0, q.z), Vec3::Y)
        };
        let mut l = unit();
        if l.dot(n) < 0.0 {
            l = -l;
        }
        if k % 5 == 0 {
            // Grazing: within a few thousandths of the tangent plane.
            l = (l - n * l.dot(n) + n * (0.004 * unit().x.abs())).normalize();
        }
        if l.dot(n) <= 0.0 {
            continue;
        }
        let want = s.shadowed(p, n, l, f32::INFINITY);
        assert_eq!(
            s.shadowed_from(from, p, n, l, f32::INFINITY),
            want,
            "from object {from}, p {p}, l {l}"
        );
        seen[usize::from(on_sphere)][usize::from(want)] += 1;
    }
    assert!(
        seen.iter().flatten().all(|&c| c > 100),
        "both answers from both objects: {seen:?}"
    );
}

/// `l` turned to the side of `n`; `None` within `min_cos` of the tangent plane.
fn on_the_side_of(n: Vec3, l: Vec3, min_cos: f32) -> Option<Vec3> {
    let l = if l.dot(n) < 0.0 { -l } else { l };
    (l.dot(n) > min_cos).then_some(l)
}

/// `Scene::shadowed_from` of object 0 at `p` (normal `n`) towards `l`, asserted equal to
/// `Scene::shadowed`'s answer.
fn shadowed_from_as_shadowed(s: &Scene, p: Vec3, n: Vec3, l: Vec3, what: &str) -> bool {
    let want = s.shadowed(p, n, l, f32::INFINITY);
    let got = s.shadowed_from(0, p, n, l, f32::INFINITY);
    assert_eq!(got, want, "{what}: p {p}, l {l}");
    want
}

/// A lone object: `Scene::shadowed_from` skips the search only for a sphere or a plane (the
/// default scene's sphere: nothing can block it), and still searches a lone mesh, which can
/// shadow itself (the face's nose and brows): both answers as `Scene::shadowed`, 20,000 rays
/// each from random points of the object (vertices of the face) towards directions on the
/// side of its normal.
#[test]
fn a_lone_object_skips_its_search_only_when_it_is_convex() {
    let mut face = SceneSpec::new();
    face.mesh = Some(std::path::PathBuf::from("face"));
    let mut rng = fastbrdf_render::env::Rng::new(3, 5);
    let mut unit = || unit_vector(&mut rng);
    for (what, spec) in [("sphere", SceneSpec::new()), ("face", face)] {
        let s = scene(&spec);
        assert_eq!(s.objects.len(), 1, "{what}: one object");
        let points: Vec<(Vec3, Vec3)> = match &s.objects[0].shape {
            fastbrdf_render::scene::Shape::Mesh(m) => (0..m.positions.len())
                .map(|i| (m.positions[i], m.normals[i]))
                .collect(),
            _ => (0..1000).map(|_| unit()).map(|n| (n, n)).collect(),
        };
        let mut shadowed = 0;
        for k in 0..20_000 {
            let (p, n) = points[k % points.len()];
            if let Some(l) = on_the_side_of(n, unit(), 0.0) {
                shadowed += u32::from(shadowed_from_as_shadowed(&s, p, n, l, what));
            }
        }
        eprintln!("{what}: {shadowed} of 20000 rays blocked");
        assert_eq!(
            shadowed > 100,
            what == "face",
            "{what}: {shadowed} rays blocked"
        );
        // The renderer asks once per object whether to search at all.
        assert_eq!(s.may_shadow(0), what == "face", "{what}: may_shadow(0)");
        assert!(s.may_shadow(usize::MAX), "{what}: a point of no object");
    }
}

/// A sphere seen from inside shadows itself: the shadow ray leaves along the normal facing the
/// eye, the inward one, and meets the far wall. `Scene::may_shadow` keeps the search for a lone
/// sphere then, and `shadowed_from` tests the sphere against its own points (both skipped it
/// for any sphere, so the inside of a sphere was lit by a light outside): it answers as
/// `shadowed` for the inward normals, alone or on a floor.
#[test]
fn a_lone_sphere_seen_from_inside_shadows_itself() {
    let mut rng = fastbrdf_render::env::Rng::new(7, 11);
    let mut unit = || unit_vector(&mut rng);
    let mut on_floor = SceneSpec::new();
    on_floor.floor = true;
    for spec in [SceneSpec::new(), on_floor] {
        let mut s = scene(&spec);
        let fastbrdf_render::scene::Shape::Sphere(sphere) = s.objects[0].shape else {
            panic!("the default scene is a sphere")
        };
        assert_eq!(s.may_shadow(0), spec.floor, "seen from outside");
        s.camera.eye = sphere.center + Vec3::new(0.1, 0.2, 0.3) * sphere.radius;
        assert!(s.may_shadow(0), "seen from inside: the far wall");
        let mut shadowed = 0;
        for _ in 0..2000 {
            let out = unit();
            let (p, n) = (sphere.center + out * sphere.radius, -out);
            if let Some(l) = on_the_side_of(n, unit(), 1e-3) {
                shadowed += u32::from(shadowed_from_as_shadowed(&s, p, n, l, "inside"));
            }
        }
        assert!(shadowed > 1900, "{shadowed} of about 2000 rays blocked");
    }
}

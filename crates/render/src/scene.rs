//! Scenes: a perspective camera, directional and point lights, an ambient term, and objects
//! (sphere, plane, triangle mesh) each with a material.

use crate::bump::Bump;
use crate::error::{RenderError, Result};
use crate::geometry::bundle::Bundle;
use crate::geometry::{Hit, Plane, Ray, Sphere, TriMesh};
use crate::texture::Texture;
use glam::{Vec3, Vec4};
use std::sync::Arc;

// The specular term lives in its own leaf module (`crate::maps` uses it too); its types are
// this module's as before.
pub use crate::specular::{Channel, RgbBrdf, Specular, Tint, shading_brdf};

/// The relative offset of a shadow ray's origin from the surface (times 1 + the largest
/// coordinate of the point).
pub const SHADOW_EPS: f32 = 1e-4;

/// A pinhole camera.
#[derive(Clone, Copy, Debug)]
pub struct Camera {
    pub eye: Vec3,
    pub target: Vec3,
    pub up: Vec3,
    /// Vertical field of view in degrees.
    pub fov_y_deg: f32,
}

impl Camera {
    /// The camera frame: forward `f`, right `r`, up `u` (unit), and tan(fov_y / 2). The GPU
    /// renderer uses it too, so both build rays from the same f32 values.
    pub fn frame(&self) -> (Vec3, Vec3, Vec3, f32) {
        let f = (self.target - self.eye).normalize();
        let r = f.cross(self.up).normalize();
        let u = r.cross(f);
        (f, r, u, (self.fov_y_deg.to_radians() * 0.5).tan())
    }

    /// The ray through image position (x, y) in pixels (y down) of a `w` x `h` image. For many
    /// rays, build [`Camera::rays`] once: the frame costs two normalisations and a `tan`.
    pub fn ray(&self, x: f32, y: f32, w: u32, h: u32) -> Ray {
        self.rays(w, h).ray(x, y)
    }

    /// The ray generator of a `w` x `h` image: the frame computed once, the same rays as
    /// [`Camera::ray`] to the bit (which calls it).
    pub fn rays(&self, w: u32, h: u32) -> Rays {
        let (f, r, u, th) = self.frame();
        Rays {
            eye: self.eye,
            f,
            r,
            u,
            th,
            aspect: w as f32 / h as f32,
            w: w as f32,
            h: h as f32,
        }
    }

    /// The image position (x, y) in pixels of world point `p` (inverse of `ray`).
    pub fn project(&self, p: Vec3, w: u32, h: u32) -> (f32, f32) {
        let (f, r, u, th) = self.frame();
        let d = p - self.eye;
        let z = d.dot(f);
        let aspect = w as f32 / h as f32;
        let (sx, sy) = (d.dot(r) / z / (th * aspect), d.dot(u) / z / th);
        ((sx + 1.0) * 0.5 * w as f32, (1.0 - sy) * 0.5 * h as f32)
    }

    /// A camera looking along `dir` at the box `[lo, hi]`, far enough to frame it.
    pub fn framing(lo: Vec3, hi: Vec3, dir: Vec3, fov_y_deg: f32) -> Self {
        let c = 0.5 * (lo + hi);
        let radius = 0.5 * (hi - lo).length();
        let dist = radius / (fov_y_deg.to_radians() * 0.5).sin() * 1.05;
        let up = if dir.normalize().y.abs() > 0.95 {
            Vec3::Z
        } else {
            Vec3::Y
        };
        Self {
            eye: c - dir.normalize() * dist,
            target: c,
            up,
            fov_y_deg,
        }
    }
}

/// A camera's rays for one image size: the frame of [`Camera::frame`] and the image scale,
/// computed once per render rather than per ray.
#[derive(Clone, Copy, Debug)]
pub struct Rays {
    eye: Vec3,
    f: Vec3,
    r: Vec3,
    u: Vec3,
    th: f32,
    aspect: f32,
    w: f32,
    h: f32,
}

impl Rays {
    /// The slopes (d.r / d.f, d.u / d.f) of the ray through image position (x, y) before
    /// its rounding (`ray` normalises `f + sx r + sy u`).
    #[inline]
    pub(crate) fn slopes(&self, x: f32, y: f32) -> [f32; 2] {
        [
            (2.0 * x / self.w - 1.0) * self.th * self.aspect,
            (1.0 - 2.0 * y / self.h) * self.th,
        ]
    }

    /// The ray through image position (x, y) in pixels (y down).
    #[inline]
    pub fn ray(&self, x: f32, y: f32) -> Ray {
        // The same operations in the same order as before the frame was hoisted: the rays (and
        // so every picture) are unchanged to the bit.
        let sx = (2.0 * x / self.w - 1.0) * self.th * self.aspect;
        let sy = (1.0 - 2.0 * y / self.h) * self.th;
        Ray {
            o: self.eye,
            d: (self.f + sx * self.r + sy * self.u).normalize(),
        }
    }

    /// Appends the rays through (x, `y`) for every x of `xs`: [`Rays::ray`]'s operations to
    /// the bit, four lanes at a time (per ray two divisions and a square root, which one at a
    /// time kept the divider busy for a tenth of a directly lit render).
    pub fn extend_row(&self, xs: &[f32], y: f32, out: &mut Vec<Ray>) {
        use crate::geometry::bvh4::lanes::F4;
        let sy = (1.0 - 2.0 * y / self.h) * self.th;
        let s = F4::splat;
        let (two, one, w, th, aspect, sy4) =
            (s(2.0), s(1.0), s(self.w), s(self.th), s(self.aspect), s(sy));
        out.reserve(xs.len());
        for chunk in xs.chunks(4) {
            let mut x = [0.5f32; 4];
            x[..chunk.len()].copy_from_slice(chunk);
            let sx = two.mul(F4::load(&x)).div(w).sub(one).mul(th).mul(aspect);
            // `f + sx * r + sy * u`, per axis.
            let axis = |f: f32, r: f32, u: f32| s(f).add(sx.mul(s(r))).add(sy4.mul(s(u)));
            let (dx, dy, dz) = (
                axis(self.f.x, self.r.x, self.u.x),
                axis(self.f.y, self.r.y, self.u.y),
                axis(self.f.z, self.r.z, self.u.z),
            );
            // `Vec3::normalize`: times the reciprocal of the length.
            let inv = one.div(dx.mul(dx).add(dy.mul(dy)).add(dz.mul(dz)).sqrt());
            let (dx, dy, dz) = (
                dx.mul(inv).store(),
                dy.mul(inv).store(),
                dz.mul(inv).store(),
            );
            out.extend((0..chunk.len()).map(|k| Ray {
                o: self.eye,
                d: Vec3::new(dx[k], dy[k], dz[k]),
            }));
        }
    }
}

/// Largest magnitude of a light's position or direction components and of its colour x
/// intensity per channel: with BRDF peaks of at most ~1e8 and 1 / distance^2 clamped at 1e12
/// the render stays well inside f32 in practice; [`crate::film::Film::check_finite`] refuses
/// whatever still overflows.
pub const MAX_LIGHT: f32 = 1e6;

/// Where a light is.
#[derive(Clone, Copy, Debug)]
pub enum LightKind {
    /// Light arriving from direction `to_light` (unit, from the surface towards the light).
    Directional { to_light: Vec3 },
    /// A point light; its irradiance falls off as 1 / distance^2.
    Point { position: Vec3 },
}

/// A light: where, colour (linear RGB), intensity.
#[derive(Clone, Copy, Debug)]
pub struct Light {
    pub kind: LightKind,
    pub color: Vec3,
    pub intensity: f32,
}

impl Light {
    /// Parses `dir:X,Y,Z[:R,G,B[:I]]` or `point:X,Y,Z[:R,G,B[:I]]`.
    pub fn parse(s: &str) -> Result<Self> {
        let bad = |m: &str| {
            RenderError::Invalid(format!(
                "--light '{s}': {m} (expected dir:X,Y,Z[:R,G,B[:INTENSITY]] or point:X,Y,Z[:R,G,B[:INTENSITY]])"
            ))
        };
        let parts: Vec<&str> = s.split(':').collect();
        let vec3 = |t: &str| -> Result<Vec3> {
            let v: Vec<f32> = t
                .split(',')
                .map(|x| x.trim().parse::<f32>())
                .collect::<Result<_, _>>()
                .map_err(|_| bad("not a number"))?;
            if v.len() != 3 || v.iter().any(|x| !x.is_finite() || x.abs() > MAX_LIGHT) {
                return Err(bad(&format!(
                    "three finite numbers needed (each of magnitude at most {MAX_LIGHT:e})"
                )));
            }
            Ok(Vec3::new(v[0], v[1], v[2]))
        };
        if parts.len() < 2 || parts.len() > 4 {
            return Err(bad("wrong number of fields"));
        }
        let p = vec3(parts[1])?;
        let color = if parts.len() > 2 {
            vec3(parts[2])?
        } else {
            Vec3::ONE
        };
        let intensity: f32 = if parts.len() > 3 {
            parts[3]
                .trim()
                .parse()
                .map_err(|_| bad("the intensity is not a number"))?
        } else {
            1.0
        };
        if !(intensity >= 0.0 && intensity.is_finite()) || color.min_element() < 0.0 {
            return Err(bad("colour and intensity must be non-negative"));
        }
        if (color * intensity).max_element() > MAX_LIGHT {
            return Err(bad(&format!(
                "colour x intensity must be at most {MAX_LIGHT:e} per channel (so that the render stays finite in f32)"
            )));
        }
        let kind = match parts[0] {
            "dir" => {
                if p == Vec3::ZERO {
                    return Err(bad("a zero-length direction"));
                }
                // Scale-safe: divide by the largest component first (1e-30,0,1e-30 is fine).
                LightKind::Directional {
                    to_light: (p / p.abs().max_element()).normalize(),
                }
            }
            "point" => LightKind::Point { position: p },
            _ => return Err(bad("unknown kind")),
        };
        Ok(Self {
            kind,
            color,
            intensity,
        })
    }

    /// (unit direction to the light, radiance scale) seen from `p`.
    pub fn at(&self, p: Vec3) -> (Vec3, Vec3) {
        let (l, li, _) = self.towards(p);
        (l, li)
    }

    /// (unit direction to the light, radiance scale, distance to the light: infinite for a
    /// directional light) seen from `p`.
    pub fn towards(&self, p: Vec3) -> (Vec3, Vec3, f32) {
        match self.kind {
            LightKind::Directional { to_light } => {
                (to_light, self.color * self.intensity, f32::INFINITY)
            }
            LightKind::Point { position } => {
                let d = position - p;
                let d2 = d.length_squared().max(1e-12);
                let dist = d2.sqrt();
                (d / dist, self.color * (self.intensity / d2), dist)
            }
        }
    }
}

/// A surface material.
pub struct Material {
    pub kd: f32,
    pub ks: f32,
    /// Linear RGB albedo (multiplied by the texture when there is one).
    pub albedo: Vec3,
    pub texture: Option<Arc<Texture>>,
    pub bump: Option<Bump>,
    pub specular: Arc<Specular>,
    /// A glTF material's textures beyond its base colour (metallic-roughness, normal,
    /// occlusion, emission: [`crate::maps`]); the GPU renderer reads them too.
    pub maps: Option<Arc<crate::maps::SurfaceMaps>>,
}

/// Geometry.
pub enum Shape {
    Sphere(Sphere),
    Plane(Plane),
    Mesh(Arc<TriMesh>),
}

/// An object: a shape and its material.
pub struct Object {
    pub shape: Shape,
    pub material: Material,
}

/// A scene.
pub struct Scene {
    pub camera: Camera,
    pub lights: Vec<Light>,
    /// Ambient radiance (times kd * albedo).
    pub ambient: Vec3,
    pub background: Vec3,
    pub objects: Vec<Object>,
    /// Shadow rays for the point and directional lights (and the environment's samples): a
    /// light blocked by any object between the shading point and the light adds nothing.
    /// Off, every light reaches every point facing it (the renderer before issue 15). The GPU
    /// renderer (`fastbrdf_gpu::render`) casts the same shadow rays.
    pub shadows: bool,
    /// Image-based lighting (a latitude-longitude map), CPU renderer only.
    pub environment: Option<crate::env::Environment>,
}

impl Scene {
    /// The nearest hit along `ray`.
    pub fn intersect(&self, ray: &Ray) -> Option<Hit> {
        self.nearest(ray, |_| true, &[])
    }

    /// The nearest hit along `ray` for shading: texture coordinates only on objects whose
    /// material has a texture or a tinted specular term (zero elsewhere), since nothing else reads them (the sphere's
    /// cost an `atan2` and an `asin` per ray).
    #[inline]
    pub fn intersect_shading(&self, ray: &Ray) -> Option<Hit> {
        self.intersect_shading_in(ray, &[])
    }

    /// [`Scene::intersect_shading`] with each object's bundle of the camera's rays
    /// ([`Views`], by object; fewer or `None`: the BVH): the same hit.
    #[inline]
    pub(crate) fn intersect_shading_in(&self, ray: &Ray, eye: &[Option<Bundle>]) -> Option<Hit> {
        let uv = |o: &Object| {
            o.material.texture.is_some()
                || o.material.specular.tint.is_some()
                || o.material.maps.is_some()
        };
        // A lone sphere (the default scene): its test alone, without the search's loop (the
        // same operations as [`Scene::nearest`] on one object: 7% fewer instructions in a
        // directly lit render).
        if let [only] = &self.objects[..]
            && let Shape::Sphere(s) = &only.shape
        {
            return s
                .hit(ray, 1e-4, f32::INFINITY, uv(only))
                .map(|(t, n, uv)| Hit {
                    t,
                    p: ray.o + t * ray.d,
                    n,
                    uv,
                    tangent: Vec4::ZERO,
                    object: 0,
                });
        }
        self.nearest(ray, uv, eye)
    }

    /// Whether anything lies along `ray` strictly between `t_min` and `t_max` (a shadow ray:
    /// any hit ends the search).
    pub fn occluded(&self, ray: &Ray, t_min: f32, t_max: f32) -> bool {
        self.objects.iter().any(|o| match &o.shape {
            Shape::Sphere(s) => s.hit(ray, t_min, t_max, false).is_some(),
            Shape::Plane(p) => p.hit(ray, t_min, t_max, false).is_some(),
            Shape::Mesh(m) => m.occluded(ray, t_min, t_max),
        })
    }

    /// Whether light from direction `l` (unit) is blocked at `p` (on a surface with the
    /// normal `n`, facing `l`), up to `dist` along `l` (infinity for directional light).
    /// The origin moves off the surface along `n` by a distance proportional to `p`'s
    /// magnitude (f32 rounding of the hit point grows with it), so a surface does not shadow
    /// itself (acne); a point light's ray stops just short of the light.
    pub fn shadowed(&self, p: Vec3, n: Vec3, l: Vec3, dist: f32) -> bool {
        self.shadowed_from(usize::MAX, p, n, l, dist)
    }

    /// [`Scene::shadowed`] for a point of object `from`, with `n` its geometric normal and
    /// `l` on the side `n` faces (`n . l > 0`, as the renderer's shadow rule asks). A sphere
    /// or a plane is then left out of its own points' search: a ray leaving a convex surface
    /// on the side its normal faces never meets it again (the origin, offset along `n`, lies
    /// outside it: the sphere's quadratic has two negative roots or none, the plane's
    /// crossing is behind the origin), so the test could only say no. The same answers as
    /// [`Scene::shadowed`] (`tests/shadows.rs` compares them), at the cost of the other
    /// objects alone: nothing at all for a lone sphere. `from` beyond the objects (as
    /// [`Scene::shadowed`] passes) searches them all.
    #[inline]
    pub fn shadowed_from(&self, from: usize, p: Vec3, n: Vec3, l: Vec3, dist: f32) -> bool {
        self.shadowed_in(from, p, n, l, dist, &[])
    }

    /// [`Scene::shadowed_from`] with each object's bundle of the light's rays ([`Views`], by
    /// object; fewer or `None`: the BVH): the same answer.
    #[inline]
    pub(crate) fn shadowed_in(
        &self,
        from: usize,
        p: Vec3,
        n: Vec3,
        l: Vec3,
        dist: f32,
        along: &[Option<Bundle>],
    ) -> bool {
        // A lone sphere or plane (the default scene): nothing to search, and no ray to build
        // (the call and the ray's set-up were 7% of the default directly lit render).
        if !self.may_shadow(from) {
            return false;
        }
        let eps = SHADOW_EPS * (1.0 + p.abs().max_element());
        let ray = Ray {
            o: p + n * eps,
            d: l,
        };
        let (t_min, t_max) = (eps, dist * (1.0 - 1e-5) - eps);
        self.objects
            .iter()
            .enumerate()
            .any(|(i, o)| match &o.shape {
                // A convex object never shadows its own points seen from outside (the ray
                // leaves along its outward normal); a sphere seen from inside does.
                Shape::Sphere(s) => {
                    (i != from || self.sees_inside(s)) && s.hit(&ray, t_min, t_max, false).is_some()
                }
                Shape::Plane(p) => i != from && p.hit(&ray, t_min, t_max, false).is_some(),
                Shape::Mesh(m) => {
                    m.occluded_in(along.get(i).and_then(Option::as_ref), &ray, t_min, t_max)
                }
            })
    }

    /// Each mesh's bundles (`geometry::bundle`) for the primary rays of `rays` (this
    /// scene's camera) and, with shadows, for each directional light's shadow rays: built
    /// once per render, in parallel.
    pub(crate) fn views(&self, rays: &Rays) -> Views {
        use rayon::prelude::*;
        let window = [rays.th * rays.aspect, rays.th];
        let frame = (rays.f, rays.r, rays.u);
        // A bundle costs its build (~0.2 to 0.5 us a triangle) and saves ~0.1 us a ray: a
        // mesh gets them only with at least PIXELS_PER_TRIANGLE pixels a triangle (at
        // 512 x 512, a 10k-triangle torus rendered 1.6x faster with them, a 25k one 1.16x,
        // a 50k one 0.78x, a 200k one 0.28x).
        let pixels = f64::from(rays.w) * f64::from(rays.h);
        let worth = |m: &TriMesh| (m.triangles.len() as f64) * PIXELS_PER_TRIANGLE <= pixels;
        let (eye, lights): (Vec<Option<Bundle>>, _) = rayon::join(
            || {
                self.objects
                    .par_iter()
                    .map(|o| match &o.shape {
                        Shape::Mesh(m) if worth(m) => Bundle::from_eye(m, rays.eye, frame, window),
                        _ => None,
                    })
                    .collect()
            },
            || {
                self.lights
                    .par_iter()
                    .map(|l| match l.kind {
                        LightKind::Directional { to_light } if self.shadows => self
                            .objects
                            .par_iter()
                            .map(|o| match &o.shape {
                                Shape::Mesh(m) if worth(m) => Bundle::along(m, to_light),
                                _ => None,
                            })
                            .collect(),
                        _ => Vec::new(),
                    })
                    .collect()
            },
        );
        // The slopes the objects cover: the eye's bundles' boxes, else a mesh's or a sphere's
        // bounding box's corners' where they all lie in front of the eye; a plane covers
        // every slope.
        let covered = self.objects.iter().zip(&eye).try_fold(
            ([f32::INFINITY; 2], [f32::NEG_INFINITY; 2]),
            |(lo, hi), (o, b)| {
                let (l, h) = match (&o.shape, b) {
                    (Shape::Mesh(_), Some(b)) => b.slopes()?,
                    (Shape::Mesh(m), None) if !m.triangles.is_empty() => {
                        let (lo, hi) = m.bounds();
                        box_slopes(lo, hi, rays)?
                    }
                    // No triangle: nothing to meet.
                    (Shape::Mesh(_), None) => ([f32::INFINITY; 2], [f32::NEG_INFINITY; 2]),
                    (Shape::Sphere(s), _) => {
                        let r = Vec3::splat(s.radius.abs());
                        box_slopes(s.center - r, s.center + r, rays)?
                    }
                    (Shape::Plane(_), _) => return None,
                };
                Some((
                    [lo[0].min(l[0]), lo[1].min(l[1])],
                    [hi[0].max(h[0]), hi[1].max(h[1])],
                ))
            },
        );
        Views {
            eye,
            lights,
            covered,
        }
    }

    /// Whether the eye may see the inside of sphere `s`: it is inside, or on the surface
    /// within a margin (there the search stays: only a clearly outside eye skips it).
    #[inline]
    fn sees_inside(&self, s: &crate::geometry::Sphere) -> bool {
        (self.camera.eye - s.center).length() <= s.radius * (1.0 + 1e-3)
    }

    /// Whether anything can block light from the points of object `from` (as
    /// [`Scene::shadowed_from`] takes it): false only for a lone plane, or a lone sphere seen
    /// from outside, whose own points it never shadows: a shadow ray leaves along the normal
    /// facing the eye, and at a point seen from outside a sphere that is the outward normal
    /// (seen from inside, the inward one: the ray meets the far wall). A renderer's loop asks
    /// once per object, not per point.
    #[inline]
    pub fn may_shadow(&self, from: usize) -> bool {
        match &self.objects[..] {
            [only] if from == 0 => match &only.shape {
                Shape::Plane(_) => false,
                Shape::Sphere(s) => self.sees_inside(s),
                Shape::Mesh(_) => true,
            },
            _ => true,
        }
    }

    #[inline]
    fn nearest(
        &self,
        ray: &Ray,
        uv: impl Fn(&Object) -> bool,
        eye: &[Option<Bundle>],
    ) -> Option<Hit> {
        let mut best: Option<Hit> = None;
        let mut t_max = f32::INFINITY;
        for (i, o) in self.objects.iter().enumerate() {
            let bundle = eye.get(i).and_then(Option::as_ref);
            // A mesh's tangent is zero where it has none.
            let h = match &o.shape {
                Shape::Sphere(s) => s
                    .hit(ray, 1e-4, t_max, uv(o))
                    .map(|(t, n, uv)| (t, n, uv, Vec4::ZERO)),
                Shape::Plane(p) => p
                    .hit(ray, 1e-4, t_max, uv(o))
                    .map(|(t, n, uv)| (t, n, uv, Vec4::ZERO)),
                Shape::Mesh(m) => m.hit_tangent_in(bundle, ray, 1e-4, t_max, uv(o)),
            };
            if let Some((t, n, uv, tangent)) = h {
                t_max = t;
                best = Some(Hit {
                    t,
                    p: ray.o + t * ray.d,
                    n,
                    uv,
                    tangent,
                    object: i,
                });
            }
        }
        best
    }
}

/// Pixels a triangle of a mesh needs for its bundles ([`Scene::views`]).
const PIXELS_PER_TRIANGLE: f64 = 12.0;

/// The box of slopes (as [`Rays::slopes`]) outside which no ray from `rays`' eye meets
/// anything inside the box `lo..=hi`: its corners', padded far above their rounding; `None`
/// if a corner lies near or behind the eye's plane.
fn box_slopes(lo: Vec3, hi: Vec3, rays: &Rays) -> Option<([f32; 2], [f32; 2])> {
    let scale = 1.0 + rays.eye.abs().max_element() + lo.abs().max(hi.abs()).max_element();
    let corners = (0..8).map(|k| {
        Vec3::new(
            if k & 1 == 0 { lo.x } else { hi.x },
            if k & 2 == 0 { lo.y } else { hi.y },
            if k & 4 == 0 { lo.z } else { hi.z },
        )
    });
    crate::geometry::bundle::slope_box(rays.eye, (rays.f, rays.r, rays.u), corners, 1e-4 * scale)
}

/// Per render: each mesh's bundles ([`Scene::views`]).
#[derive(Default)]
pub(crate) struct Views {
    /// By object: its bundle of the camera's rays.
    pub(crate) eye: Vec<Option<Bundle>>,
    /// By light, then object: its bundle of a directional light's shadow rays.
    lights: Vec<Vec<Option<Bundle>>>,
    /// The box of slopes outside which the camera's rays meet nothing (`None`: unbounded).
    covered: Option<([f32; 2], [f32; 2])>,
}

impl Views {
    /// Whether a ray of `rays` through a point of the pixel rectangle (x0, y0)..(x1, y1) may
    /// meet an object (false: every such ray sees the background).
    #[inline]
    pub(crate) fn may_hit(&self, rays: &Rays, (x0, y0): (f32, f32), (x1, y1): (f32, f32)) -> bool {
        let Some((lo, hi)) = self.covered else {
            return true;
        };
        // Slopes grow with x and fall with y.
        let (a, b) = (rays.slopes(x0, y1), rays.slopes(x1, y0));
        a[0] <= hi[0] && b[0] >= lo[0] && a[1] <= hi[1] && b[1] >= lo[1]
    }

    /// Light `i`'s bundles by object (none for a point light or without shadows).
    #[inline]
    pub(crate) fn light(&self, i: usize) -> &[Option<Bundle>] {
        self.lights.get(i).map_or(&[], |v| &v[..])
    }
}

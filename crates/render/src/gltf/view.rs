//! A node's camera and punctual light in world space.

use super::Ctx;
use crate::error::Result;
use crate::scene::{Camera, Light, LightKind, MAX_LIGHT};
use glam::{Mat4, Vec3};

/// The node's perspective camera (looking down its -z, up its +y); an orthographic one is
/// named in a warning and not used.
pub(super) fn camera(node: &gltf::Node, world: Mat4, warnings: &mut Vec<String>) -> Option<Camera> {
    let cam = node.camera()?;
    let ptr = format!("/cameras/{}", cam.index());
    match cam.projection() {
        gltf::camera::Projection::Perspective(p) => {
            let eye = world.transform_point3(Vec3::ZERO);
            let f = world.transform_vector3(-Vec3::Z).normalize_or_zero();
            let up = world.transform_vector3(Vec3::Y).normalize_or_zero();
            let fov = p.yfov().to_degrees();
            if f == Vec3::ZERO
                || up == Vec3::ZERO
                || f.cross(up) == Vec3::ZERO
                || !(fov > 0.0 && fov < 180.0)
            {
                warnings.push(format!(
                    "camera {ptr} (node /nodes/{}): a degenerate transform or field of view: not used",
                    node.index()
                ));
                return None;
            }
            if p.aspect_ratio().is_some() {
                warnings.push(format!(
                    "camera {ptr}: its aspectRatio is not used (the picture's is --size's)"
                ));
            }
            Some(Camera {
                eye,
                target: eye + f,
                up,
                fov_y_deg: fov,
            })
        }
        gltf::camera::Projection::Orthographic(_) => {
            warnings.push(format!(
                "camera {ptr} is orthographic: not supported, not used"
            ));
            None
        }
    }
}

/// The node's `KHR_lights_punctual` light: directional (along the node's -z) and point lights
/// as the renderer's (intensity as given: lux and candela as the renderer's scale; `range` not
/// used); a spot light is named in a warning.
pub(super) fn light(
    ctx: &Ctx,
    node: &gltf::Node,
    world: Mat4,
    warnings: &mut Vec<String>,
) -> Result<Option<Light>> {
    let Some(l) = node.light() else {
        return Ok(None);
    };
    let ptr = format!("/extensions/KHR_lights_punctual/lights/{}", l.index());
    let color = Vec3::from(l.color());
    let intensity = l.intensity();
    if !(color.is_finite()
        && color.min_element() >= 0.0
        && intensity.is_finite()
        && intensity >= 0.0)
    {
        return Err(ctx.err(&ptr, "colour and intensity must be finite and non-negative"));
    }
    if (color * intensity).max_element() > MAX_LIGHT {
        return Err(ctx.err(
            &ptr,
            format!("colour x intensity must be at most {MAX_LIGHT:e} per channel"),
        ));
    }
    if l.range().is_some() {
        warnings.push(format!(
            "light {ptr}: its range is not used (1/d^2 everywhere)"
        ));
    }
    let kind = match l.kind() {
        gltf::khr_lights_punctual::Kind::Directional => {
            let d = world.transform_vector3(-Vec3::Z);
            if d.length().is_nan() || d.length() <= 0.0 {
                warnings.push(format!("light {ptr}: a degenerate transform: not used"));
                return Ok(None);
            }
            LightKind::Directional {
                to_light: -d.normalize(),
            }
        }
        gltf::khr_lights_punctual::Kind::Point => LightKind::Point {
            position: world.transform_point3(Vec3::ZERO),
        },
        gltf::khr_lights_punctual::Kind::Spot { .. } => {
            warnings.push(format!(
                "light {ptr} is a spot light: not supported, not used"
            ));
            return Ok(None);
        }
    };
    Ok(Some(Light {
        kind,
        color,
        intensity,
    }))
}

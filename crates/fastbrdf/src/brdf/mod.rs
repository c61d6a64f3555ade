//! Full BRDFs of (wi, wo) in the local frame (normal +z, both directions pointing away from
//! the surface), returned without the cosine factor.

pub mod cook_torrance;
pub mod gltf_pbr;
mod gltf_pbr_wgsl;
pub mod lambert;
pub mod phong;
pub mod ward;

//! The kinds of model, by what they take as input.

use serde::Serialize;

/// The kinds of model, by what they take as input.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Kind {
    /// A function of one cosine `c` in [0, 1] (input column `cos`).
    Lobe,
    /// A microfacet distribution `D(cos theta_h)` (input column `cos_h`).
    Distribution,
    /// A shadowing-masking term (input columns `cos_v`, optional `cos_l`; the V-cavity also
    /// `cos_h`, `cos_vh`).
    Shadowing,
    /// A Fresnel term of the cosine between the view and the microfacet normal (`cos_vh`).
    Fresnel,
    /// A full BRDF of `(wi, wo)` in the local frame, without the cosine factor.
    Brdf,
    /// A split-sum term of image-based lighting (the scale or bias of `f0` in the directional
    /// albedo of a specular BRDF): input columns `cos_v` and `alpha`.
    Env,
}

impl Kind {
    /// The name used in tables and errors.
    pub fn name(self) -> &'static str {
        match self {
            Kind::Lobe => "lobe",
            Kind::Distribution => "distribution",
            Kind::Shadowing => "shadowing",
            Kind::Fresnel => "fresnel",
            Kind::Brdf => "brdf",
            Kind::Env => "env",
        }
    }
}

impl Kind {
    /// The input columns of a model of this kind (`fastbrdf eval`, batch inputs):
    /// `(required, optional)`. Shadowing terms that use the half vector (V-cavity, Kelemen) also
    /// need `cos_h` and `cos_vh` (`half_vector`).
    pub fn columns(self, half_vector: bool) -> (&'static [&'static str], &'static [&'static str]) {
        match self {
            Kind::Lobe => (&["cos"], &[]),
            Kind::Distribution => (&["cos_h"], &[]),
            Kind::Shadowing if half_vector => (&["cos_v", "cos_h", "cos_vh"], &["cos_l"]),
            Kind::Shadowing => (&["cos_v"], &["cos_l"]),
            Kind::Fresnel => (&["cos_vh"], &[]),
            Kind::Brdf => (&["wi_x", "wi_y", "wi_z", "wo_x", "wo_y", "wo_z"], &[]),
            Kind::Env => (&["cos_v", "alpha"], &[]),
        }
    }

    /// The inputs of a model's WGSL function `fb_<id>`, as WGSL parameters (shadowing:
    /// two-sided; BRDF: local frame, normal +z, no cosine factor).
    pub fn wgsl_signature(self) -> &'static str {
        match self {
            Kind::Lobe => "c: f32",
            Kind::Distribution => "cos_h: f32",
            Kind::Shadowing => "cos_v: f32, cos_l: f32, cos_h: f32, cos_vh: f32",
            Kind::Fresnel => "cos_vh: f32",
            Kind::Brdf => "wi: vec3<f32>, wo: vec3<f32>",
            Kind::Env => "cos_v: f32, alpha: f32",
        }
    }
}

/// How a model of a kind is shaded (the renderers' and BRDF Explorer exports' policy, one
/// place): as the BRDF it is, or as the BRDF `brdf` with the model as its parameter `param`
/// (plus fixed `extra` parameters); shadowing and Fresnel terms are not shaded.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shading {
    AsIs,
    Via {
        brdf: &'static str,
        param: &'static str,
        extra: &'static [(&'static str, &'static str)],
    },
    Not,
}

impl Kind {
    /// The shading policy: a lobe as `blinn-phong` of that lobe with `norm = none` (the
    /// seeds' pictures), a distribution as `cook-torrance` with that `d`.
    pub fn shading(self) -> Shading {
        match self {
            Kind::Brdf => Shading::AsIs,
            Kind::Lobe => Shading::Via {
                brdf: "blinn-phong",
                param: "lobe",
                extra: &[("norm", "none")],
            },
            Kind::Distribution => Shading::Via {
                brdf: "cook-torrance",
                param: "d",
                extra: &[],
            },
            Kind::Shadowing | Kind::Fresnel | Kind::Env => Shading::Not,
        }
    }
}

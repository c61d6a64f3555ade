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
        }
    }
}


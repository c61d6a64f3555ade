//! Microfacet terms: distributions `D`, shadowing-masking `G` and Fresnel `F`.

pub mod beckmann;
pub mod beckmann_pow;
pub mod fresnel;
pub mod shadowing;

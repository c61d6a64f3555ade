//! Microfacet terms: distributions `D`, shadowing-masking `G` and Fresnel `F`.

pub mod beckmann;
pub mod beckmann_pow;
pub mod env_brdf;
pub mod env_rational;
pub mod env_table;
pub mod fresnel;
pub mod ggx;
pub mod kelemen_neumann;
pub mod ms;
pub mod shadowing;
pub mod sheen;
pub mod sheen_albedo;
pub mod smith_ggx;

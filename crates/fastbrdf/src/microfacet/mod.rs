//! Microfacet terms: distributions `D`, shadowing-masking `G` and Fresnel `F`.

pub mod beckmann;
pub mod beckmann_pow;
pub mod fresnel;
pub mod shadowing;

/// Every distribution id (the choices of `cook-torrance`'s `d`).
pub const DISTRIBUTION_IDS: &[&str] = &[
    "beckmann",
    "beckmann-ct",
    "beckmann-pow",
    "beckmann-power4",
    "beckmann-power8",
    "beckmann-power16",
];

// fastbrdf WGSL library: microfacet distributions D, shadowing G and Fresnel F.
// Each family's WGSL functions are in the .wgsl file beside its Rust file in this folder
// (beckmann.wgsl beside beckmann.rs, ...; the Rust headers give formulas, sources and bounds),
// collected through plan.rs's family lists (DistForm/ShadowForm/FresnelForm::WGSL); the Rust
// formulas have the same arrangement. This file holds no functions.

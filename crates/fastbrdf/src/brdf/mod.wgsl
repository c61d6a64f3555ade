// fastbrdf WGSL library: full BRDFs of (wi, wo) in the local frame (normal +z), without the
// cosine factor. Each family's WGSL functions are in the .wgsl file beside its Rust file in this
// folder (ward.wgsl beside ward.rs), collected through plan.rs's family list (BrdfForm::WGSL);
// the Rust formulas (BrdfForm::at_pair) have the same arrangement. Cook-Torrance, Phong, Blinn-Phong and Lambert
// are assembled per model instance by their wgsl_body (their D, G, F or lobe are parameters),
// which fastbrdf_gpu::spec wraps; cook_torrance.wgsl holds only its anisotropic stretch.
// This file holds no functions.

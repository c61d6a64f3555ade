// fastbrdf WGSL library: full BRDFs of (wi, wo) in the local frame (normal +z), without the
// cosine factor. Each family's WGSL functions are in the .wgsl file beside its Rust file in this
// folder (ward.wgsl beside ward.rs), collected through plan.rs's family list (BrdfForm::WGSL);
// the Rust formulas (BrdfForm::at_pair) have the same arrangement. Cook-Torrance, Phong, Blinn-Phong and Lambert have no
// .wgsl file: they are assembled per model instance by their wgsl_body (their D, G, F or lobe
// are parameters), which fastbrdf_gpu::spec wraps. This file holds no functions.

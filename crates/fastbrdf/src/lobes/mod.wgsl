// fastbrdf WGSL library: specular lobes f(c), c = cos of the angle to the lobe's axis (n.h for
// Blinn-Phong, r.v for Phong). Argument clamped to [0, 1]. Each family's WGSL functions are in
// the .wgsl file beside its Rust file in this folder (pow.wgsl beside pow.rs, ...; the Rust
// headers give formulas, sources and error bounds), collected through plan.rs's family list
// (LobeForm::WGSL); the Rust formulas (LobeForm::at) have this arrangement. This file holds no functions: it is the
// header that explains all of them.
// Precision on the GPU: shader compilers reassociate. Mesa's NIR (lavapipe) recognises
// `1 + t (c - 1)` as the lerp a + t (b - a) and lowers it to (1 - t) + t c, which cancels when
// t ~ n (the power lobes and the cubics' Newton form erred by about n ulp of c absolute, 4.8e-4
// at n = 10000 on lavapipe; fma() does not stop it), and with literal coefficients it folds
// `(y + #a) * #k` into `y #k + #(a k)` and sums of literals (seed 003's rational: 2.6e-4 at
// c = 1). So the lobes here are written in y = 1 - c (exact for c >= 0.5): no lerp shape, the
// constant term exactly 1 or exactly the peak, every other term a multiple of y, so that at
// c = 1 any such folding still gives the peak (crates/gpu/tests/fold.rs models the folding,
// crates/gpu/tests/exact.rs runs lavapipe). The CPU twins keep the seed's arrangements;
// crates/gpu/tests/parity.rs compares them.
// Coefficients that need care (cubic shapes, rational nodes, tuned slopes, normalisation) are
// computed once on the CPU in f64 and passed in, as the CPU kernels do.

//! Lobes: functions of one cosine `c` in [0, 1] with a specular exponent `n`.
//! The reference is [`pow`] (`c^n`); every other lobe approximates it.
//!
//! Conventions shared by every lobe (see `Lobe::eval`): the cosine is clamped to [0, 1]
//! (../shared/MODELS.md), so `c < 0` gives the value at 0 (non-zero for `sg`, `gauss` and the
//! power forms with `n < g`) and `c > 1` the value at 1; NaN gives 0. `n` is in [1, 100000]; error bounds are documented for n in [1, 100000] (and the seeds' narrower ranges).

pub mod cubic;
pub mod fits;
pub mod flog;
pub mod gauss;
pub mod pow;
pub mod power;
pub mod rational;
pub mod schlick;
pub mod sg;
pub mod tuned;

/// The lenient lobe argument: `c` clamped to [0, 1]; `None` (value 0) for NaN.
pub use crate::forms::lobe_arg as arg;

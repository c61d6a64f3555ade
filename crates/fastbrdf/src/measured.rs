//! Measured isotropic BRDFs in MERL's binary format (Matusik et al. 2003, `BRDFRead.cpp`).
//!
//! The file: three little-endian `int32` dimensions (90, 90, 180: theta_half, theta_diff,
//! phi_diff), then 90 * 90 * 180 little-endian `f64` for red, then as many for green, then for
//! blue: 12 + 3 * 1,458,000 * 8 = 34,992,012 bytes. A stored value times its channel's scale
//! (1/1500, 1.15/1500, 1.66/1500) is the BRDF value. A negative stored value marks a sample
//! that was not measured: the lookup returns 0 for it and [`MeasuredBrdf::stats`] counts it.
//!
//! The lookup is the reference code's, step for step: the half vector's polar angle and
//! azimuth, the difference vector (`wi` rotated by -phi_h about the normal, then by -theta_h
//! about the binormal, `rotate_vector`), then nearest-bin indices: theta_h non-linearly
//! (`floor(sqrt(theta_h / (pi/2)) * 90)`), theta_d and phi_d linearly, phi_d folded into
//! [0, pi] by reciprocity (`phi_d + pi` for a negative one), every index clamped. phi_h is
//! ignored (isotropy).
//!
//! Reading is bounded (`fastbrdf_io`): the 12-byte header is read and checked first (a file
//! whose dimensions are not 90 x 90 x 180, or negative, is refused before anything else is
//! read or allocated), then at most the 34,992,000 bytes of samples plus one; a shorter or
//! longer file is an error naming the byte counts, a NaN or infinite sample an error naming
//! its channel and index, and so is a sample whose BRDF value (stored value times scale) is
//! above [`MAX_VALUE`] (1e8 sr^-1, see there): such a file is not a measurement, and its
//! values would overflow the sums every consumer makes (a mean, an albedo, a pixel).

use fastbrdf_io::IoError;
use std::f64::consts::{FRAC_PI_2, PI};
use std::io::Read;
use std::path::Path;

/// Bins of theta_half (non-linear: bin `i` starts at `(i / 90)^2 * pi / 2`).
pub const RES_THETA_H: usize = 90;
/// Bins of theta_diff (linear over [0, pi/2]).
pub const RES_THETA_D: usize = 90;
/// Bins of phi_diff (linear over [0, pi]; the reference's `BRDF_SAMPLING_RES_PHI_D / 2`).
pub const RES_PHI_D: usize = 180;
/// Samples per channel.
pub const SAMPLES: usize = RES_THETA_H * RES_THETA_D * RES_PHI_D;
/// The header: three `int32`.
pub const HEADER_BYTES: u64 = 12;
/// The whole file: the header and three channels of `f64`.
pub const FILE_BYTES: u64 = HEADER_BYTES + 3 * SAMPLES as u64 * 8;
/// The per-channel scale factors of the format (R, G, B).
pub const SCALE: [f64; 3] = [1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0];
/// Channel names, for messages.
pub const CHANNELS: [&str; 3] = ["red", "green", "blue"];

/// The largest BRDF value (sr^-1, after the channel's scale) a file may hold; a larger one is
/// refused at read time naming the file, channel and bin.
///
/// Why 1e8. A BRDF that conserves energy (albedo at most 1) and puts all of it into the
/// incident directions of MERL's smallest bin has there `f <= 1 / (cos_i * omega)`, `omega`
/// the bin's solid angle in incident directions: theta_h bin 0 ends at `(1/90)^2 pi/2 =
/// 1.94e-4` rad, so `wi` lies within about `2 * 1.94e-4` rad of the mirror direction, `omega
/// ~ pi (3.9e-4)^2 = 4.7e-7` sr, and `f <= 2.1e6 / cos_i` sr^-1. 1e8 admits that perfect mirror
/// down to cos_i = 0.02 (89 degrees; real measurements, blurred by the gonioreflectometer's
/// aperture, peak orders of magnitude lower), so no plausible file is refused. And it keeps
/// every sum the tools make finite with room to spare: a channel's 1.46 million samples sum to
/// at most 1.5e14, their squares to 1.5e22, and an f32 render multiplies values by radiances
/// far below f32's 3.4e38. Values of 1e300 (finite) made `errors --measured` report zero
/// albedos and `render` blame the model for non-finite pixels.
pub const MAX_VALUE: f64 = 1e8;

/// A measured BRDF: the three channels' samples, already multiplied by their scales; a
/// missing sample is stored as a negative number.
#[derive(Clone)]
pub struct MeasuredBrdf {
    /// `3 * SAMPLES` values: R, then G, then B; index
    /// `phi_d + theta_d * 180 + theta_h * 180 * 90` within a channel.
    data: Vec<f64>,
}

/// Per-channel statistics of the valid (non-negative) samples. With no valid sample
/// (`valid == 0`) `min`, `max` and `mean` are NaN: there is nothing to describe.
#[derive(Clone, Debug, PartialEq)]
pub struct ChannelStats {
    pub min: f64,
    pub max: f64,
    pub mean: f64,
    /// Valid samples.
    pub valid: usize,
    /// Samples marked missing (negative in the file).
    pub missing: usize,
}

fn input_err(name: &Path, message: impl Into<String>) -> IoError {
    IoError::Input {
        path: name.display().to_string(),
        message: message.into(),
    }
}

/// What the file should be, for messages.
fn expected() -> String {
    format!(
        "a MERL BRDF file is {FILE_BYTES} bytes (a 12-byte header of dimensions \
         {RES_THETA_H}, {RES_THETA_D}, {RES_PHI_D}, then 3 x {SAMPLES} doubles)"
    )
}

/// The (theta_h, theta_d, phi_d) bin of a flat index within a channel.
pub fn bin_of(index: usize) -> (usize, usize, usize) {
    let pd = index % RES_PHI_D;
    let td = (index / RES_PHI_D) % RES_THETA_D;
    let th = index / (RES_PHI_D * RES_THETA_D);
    (th, td, pd)
}

/// The flat index within a channel of bin (theta_h, theta_d, phi_d).
pub fn index_of(th: usize, td: usize, pd: usize) -> usize {
    pd + td * RES_PHI_D + th * RES_PHI_D * RES_THETA_D
}

/// The angles (theta_h, theta_d, phi_d) at the centre of a bin, in index space: the lookup
/// maps them back to that same bin (theta_h's centre is `((i + 0.5) / 90)^2 * pi / 2`).
pub fn bin_centre(th: usize, td: usize, pd: usize) -> (f64, f64, f64) {
    let u = (th as f64 + 0.5) / RES_THETA_H as f64;
    (
        u * u * FRAC_PI_2,
        (td as f64 + 0.5) / RES_THETA_D as f64 * FRAC_PI_2,
        (pd as f64 + 0.5) / RES_PHI_D as f64 * PI,
    )
}

/// The reference's `theta_half_index`.
pub fn theta_half_index(theta_h: f64) -> usize {
    if !(theta_h > 0.0) {
        return 0;
    }
    let t = (theta_h / FRAC_PI_2 * RES_THETA_H as f64 * RES_THETA_H as f64).sqrt();
    (t as usize).min(RES_THETA_H - 1)
}

/// The reference's `theta_diff_index`.
pub fn theta_diff_index(theta_d: f64) -> usize {
    if !(theta_d > 0.0) {
        return 0;
    }
    ((theta_d / FRAC_PI_2 * RES_THETA_D as f64) as usize).min(RES_THETA_D - 1)
}

/// The reference's `phi_diff_index`: a negative phi_d is moved by pi (reciprocity).
pub fn phi_diff_index(phi_d: f64) -> usize {
    let p = if phi_d < 0.0 { phi_d + PI } else { phi_d };
    if !(p > 0.0) {
        return 0;
    }
    ((p / PI * RES_PHI_D as f64) as usize).min(RES_PHI_D - 1)
}

/// The reference's `rotate_vector`: `v` rotated by `angle` about the unit `axis` (Rodrigues).
fn rotate(v: [f64; 3], axis: [f64; 3], angle: f64) -> [f64; 3] {
    let (s, c) = angle.sin_cos();
    let dot = axis[0] * v[0] + axis[1] * v[1] + axis[2] * v[2];
    let t = dot * (1.0 - c);
    let cross = [
        axis[1] * v[2] - axis[2] * v[1],
        axis[2] * v[0] - axis[0] * v[2],
        axis[0] * v[1] - axis[1] * v[0],
    ];
    [
        v[0] * c + axis[0] * t + cross[0] * s,
        v[1] * c + axis[1] * t + cross[1] * s,
        v[2] * c + axis[2] * t + cross[2] * s,
    ]
}

fn normalise(v: [f64; 3]) -> Option<[f64; 3]> {
    let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    (l > 0.0 && l.is_finite()).then(|| [v[0] / l, v[1] / l, v[2] / l])
}

/// The reference's `std_coords_to_half_diff_coords` on vectors: (theta_h, phi_h, theta_d,
/// phi_d) of unit `wi`, `wo`, or `None` for a zero or non-finite vector.
pub fn half_diff(wi: [f64; 3], wo: [f64; 3]) -> Option<(f64, f64, f64, f64)> {
    let wi = normalise(wi)?;
    let wo = normalise(wo)?;
    let h = normalise([
        (wi[0] + wo[0]) / 2.0,
        (wi[1] + wo[1]) / 2.0,
        (wi[2] + wo[2]) / 2.0,
    ])?;
    let theta_h = h[2].clamp(-1.0, 1.0).acos();
    let phi_h = h[1].atan2(h[0]);
    let t = rotate(wi, [0.0, 0.0, 1.0], -phi_h);
    let d = rotate(t, [0.0, 1.0, 0.0], -theta_h);
    Some((
        theta_h,
        phi_h,
        d[2].clamp(-1.0, 1.0).acos(),
        d[1].atan2(d[0]),
    ))
}

/// Unit `wi`, `wo` whose half/difference angles are (theta_h, phi_h = 0, theta_d, phi_d): the
/// inverse of [`half_diff`] (for tests and tabulation).
pub fn from_half_diff(theta_h: f64, theta_d: f64, phi_d: f64) -> ([f64; 3], [f64; 3]) {
    let (st, ct) = theta_d.sin_cos();
    let (sp, cp) = phi_d.sin_cos();
    let d = [st * cp, st * sp, ct];
    let wi = rotate(d, [0.0, 1.0, 0.0], theta_h);
    let d_o = [-d[0], -d[1], d[2]];
    let wo = rotate(d_o, [0.0, 1.0, 0.0], theta_h);
    (wi, wo)
}

impl MeasuredBrdf {
    /// Reads a MERL `.binary` file (see the module's documentation for what is checked).
    pub fn read(path: &Path) -> Result<Self, IoError> {
        if path.is_dir() {
            return Err(input_err(path, "is a folder, not a file"));
        }
        let file =
            std::fs::File::open(path).map_err(|e| input_err(path, format!("cannot open: {e}")))?;
        Self::from_reader(file, path)
    }

    /// Reads MERL's format from `reader`, named `name` in messages. At most the header and
    /// `FILE_BYTES - 12 + 1` bytes are read, whatever the reader holds.
    pub fn from_reader(mut reader: impl Read, name: &Path) -> Result<Self, IoError> {
        let mut header = Vec::with_capacity(HEADER_BYTES as usize);
        reader
            .by_ref()
            .take(HEADER_BYTES)
            .read_to_end(&mut header)
            .map_err(|e| input_err(name, format!("cannot read: {e}")))?;
        if header.len() < HEADER_BYTES as usize {
            return Err(input_err(
                name,
                format!(
                    "only {} bytes, too short for the 12-byte header; {}",
                    header.len(),
                    expected()
                ),
            ));
        }
        let dims: Vec<i32> = header
            .chunks_exact(4)
            .map(|c| i32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect();
        if dims.iter().any(|&d| d < 0) {
            return Err(input_err(
                name,
                format!(
                    "negative dimension in the header ({} x {} x {}); {}",
                    dims[0],
                    dims[1],
                    dims[2],
                    expected()
                ),
            ));
        }
        if dims != [RES_THETA_H as i32, RES_THETA_D as i32, RES_PHI_D as i32] {
            return Err(input_err(
                name,
                format!(
                    "dimensions {} x {} x {} in the header; the MERL lookup is defined for \
                     {RES_THETA_H} x {RES_THETA_D} x {RES_PHI_D} (theta_h x theta_d x phi_d) only",
                    dims[0], dims[1], dims[2]
                ),
            ));
        }
        let body = FILE_BYTES - HEADER_BYTES;
        let mut bytes = Vec::with_capacity(body as usize);
        reader
            .take(body + 1)
            .read_to_end(&mut bytes)
            .map_err(|e| input_err(name, format!("cannot read: {e}")))?;
        if bytes.len() as u64 != body {
            let got = if bytes.len() as u64 > body {
                "more than that (nothing was read past one byte over)".to_string()
            } else {
                format!("{} bytes", HEADER_BYTES + bytes.len() as u64)
            };
            return Err(input_err(
                name,
                format!("{} bytes expected, the file has {got}", FILE_BYTES),
            ));
        }
        let mut data = Vec::with_capacity(3 * SAMPLES);
        for (k, c) in bytes.chunks_exact(8).enumerate() {
            let v = f64::from_le_bytes(c.try_into().expect("8 bytes"));
            let channel = k / SAMPLES;
            // The bad sample, named by channel and bin.
            let refuse = |why: String| {
                let i = k % SAMPLES;
                let (th, td, pd) = bin_of(i);
                input_err(
                    name,
                    format!(
                        "{} channel, sample {i} (theta_h bin {th}, theta_d bin {td}, phi_d bin \
                         {pd}): {why}",
                        CHANNELS[channel]
                    ),
                )
            };
            if !v.is_finite() {
                return Err(refuse(format!("{v} is not a finite number")));
            }
            let value = v * SCALE[channel];
            if value > MAX_VALUE {
                return Err(refuse(format!(
                    "{v:e} is a BRDF value of {value:e} sr^-1, above the {MAX_VALUE:e} a \
                     measured BRDF can plausibly reach (not a MERL measurement?)"
                )));
            }
            data.push(value);
        }
        Ok(Self { data })
    }

    /// The scaled sample of `channel` (0 R, 1 G, 2 B) at flat index `i`; negative = missing.
    pub fn sample(&self, channel: usize, i: usize) -> f64 {
        self.data[channel * SAMPLES + i]
    }

    /// The flat index (within a channel) the reference lookup reads for `wi`, `wo`, or `None`
    /// for a zero, non-finite or below-the-horizon direction.
    pub fn lookup_index(wi: [f64; 3], wo: [f64; 3]) -> Option<usize> {
        if !(wi[2] > 0.0 && wo[2] > 0.0) {
            return None;
        }
        let (th, _, td, pd) = half_diff(wi, wo)?;
        Some(index_of(
            theta_half_index(th),
            theta_diff_index(td),
            phi_diff_index(pd),
        ))
    }

    /// The BRDF's R, G, B values for `wi`, `wo` in the local frame (normal +z, any length).
    /// Below the horizon (either z <= 0), a zero or non-finite vector, or a missing sample: 0.
    pub fn eval_rgb(&self, wi: [f64; 3], wo: [f64; 3]) -> [f64; 3] {
        match Self::lookup_index(wi, wo) {
            None => [0.0; 3],
            Some(i) => [0, 1, 2].map(|c| self.sample(c, i).max(0.0)),
        }
    }

    /// [`eval_rgb`](Self::eval_rgb) for f32 directions. The angles and bin indices are computed
    /// in f64 (the vectors are widened exactly), so both precisions read the same bin as the
    /// f64 reference code; only the result is rounded to f32.
    pub fn eval_rgb_f32(&self, wi: [f32; 3], wo: [f32; 3]) -> [f32; 3] {
        self.eval_rgb(wi.map(f64::from), wo.map(f64::from))
            .map(|v| v as f32)
    }

    /// Min, max and mean of each channel's valid samples, and how many are missing.
    pub fn stats(&self) -> [ChannelStats; 3] {
        [0, 1, 2].map(|c| {
            let s = &self.data[c * SAMPLES..(c + 1) * SAMPLES];
            let (mut min, mut max, mut sum, mut valid) = (f64::INFINITY, f64::NEG_INFINITY, 0.0, 0);
            for &v in s.iter().filter(|v| **v >= 0.0) {
                min = min.min(v);
                max = max.max(v);
                sum += v;
                valid += 1;
            }
            if valid == 0 {
                (min, max) = (f64::NAN, f64::NAN);
            }
            ChannelStats {
                min,
                max,
                mean: if valid == 0 {
                    f64::NAN
                } else {
                    sum / valid as f64
                },
                valid,
                missing: SAMPLES - valid,
            }
        })
    }
}

/// A MERL file's bytes tabulating `f(theta_h, theta_d, phi_d) -> [r, g, b]` at every bin's
/// centre ([`bin_centre`]), each value divided by its channel's scale. A negative value is
/// written as -1 (a missing sample).
pub fn merl_bytes(f: impl Fn(f64, f64, f64) -> [f64; 3]) -> Vec<u8> {
    let mut values = vec![0.0f64; 3 * SAMPLES];
    for i in 0..SAMPLES {
        let (th, td, pd) = bin_of(i);
        let (a, b, c) = bin_centre(th, td, pd);
        let v = f(a, b, c);
        for ch in 0..3 {
            values[ch * SAMPLES + i] = if v[ch] < 0.0 { -1.0 } else { v[ch] / SCALE[ch] };
        }
    }
    let mut out = Vec::with_capacity(FILE_BYTES as usize);
    for d in [RES_THETA_H, RES_THETA_D, RES_PHI_D] {
        out.extend_from_slice(&(d as i32).to_le_bytes());
    }
    for v in values {
        out.extend_from_slice(&v.to_le_bytes());
    }
    out
}

/// Writes [`merl_bytes`] of `f` to `path` atomically (`fastbrdf_io::write_atomic`).
pub fn write_merl(path: &Path, f: impl Fn(f64, f64, f64) -> [f64; 3]) -> Result<(), IoError> {
    fastbrdf_io::write_atomic(path, &merl_bytes(f))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn half_diff_inverts_from_half_diff() {
        for &(th, td, pd) in &[(0.3, 0.5, 1.0), (1.2, 0.1, 2.5), (0.01, 1.4, 0.2)] {
            let (wi, wo) = from_half_diff(th, td, pd);
            let (a, ph, b, c) = half_diff(wi, wo).unwrap();
            assert!((a - th).abs() < 1e-12 && ph.abs() < 1e-12, "{a} {ph}");
            assert!((b - td).abs() < 1e-12 && (c - pd).abs() < 1e-12, "{b} {c}");
            // Swapping wi and wo moves phi_d by pi: the same bin after folding.
            let (_, _, b2, c2) = half_diff(wo, wi).unwrap();
            assert!((b2 - td).abs() < 1e-12);
            assert_eq!(phi_diff_index(c2), phi_diff_index(pd));
        }
    }

    #[test]
    fn bin_centres_map_to_their_bins() {
        for th in 0..RES_THETA_H {
            for td in [0, 17, 89] {
                for pd in [0, 90, 179] {
                    let (a, b, c) = bin_centre(th, td, pd);
                    assert_eq!(theta_half_index(a), th);
                    assert_eq!(theta_diff_index(b), td);
                    assert_eq!(phi_diff_index(c), pd);
                }
            }
        }
    }

    #[test]
    fn file_size() {
        assert_eq!(FILE_BYTES, 34_992_012);
    }
}

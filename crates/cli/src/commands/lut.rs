//! `fastbrdf lut`: the split-sum "DFG" look-up table (scale, bias) of an env model, as EXR,
//! PNG or CSV (fastbrdf-analysis's `lut`).

use super::common::progress::bar;
use crate::CliError;
use fastbrdf_analysis::lut::{self, Axis, MAX_SIZE};
use fastbrdf_io::shorten_middle;
use std::path::{Path, PathBuf};

#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  fastbrdf lut --out dfg.exr                         \
(128 x 128, env-brdf, x = cos_v, y = roughness)\n  \
fastbrdf lut --out dfg.png --size 64\n  \
fastbrdf lut --out dfg.csv --size 32 --axis alpha\n  \
fastbrdf lut --out approx.exr --model env-brdf-approx-tuned\n\n\
The table of GGX's split-sum terms (height-correlated Smith): specular = prefiltered radiance\n\
x (f0 scale + bias). Texel (i, j) holds cos_v = (i + 0.5) / N and, on the y axis, t = (j + 0.5)\n\
/ N: perceptual roughness r = t with alpha = r^2 (--axis roughness, as Unreal and Filament\n\
index their tables) or alpha = t (--axis alpha). Values are sampled at texel centres, where\n\
an engine's bilinear fetch returns them exactly. Row 0 is the smallest roughness and is the\n\
top row of the images (y = 0). alpha is clamped to the models' domain, alpha >= 0.005: the\n\
first rows, where r^2 (or t) is below 0.005, hold the values at alpha = 0.005 (9 rows at\n\
N = 128 on the roughness axis; the message on stderr says how many).\n\n\
Formats (by the extension of --out, or --format):\n  \
.exr  32-bit float RGB, linear, scanline ZIP: R = scale, G = bias, B = 0\n  \
.png  16-bit RGB, no colour-space conversion: R = scale, G = bias, B = 0, each clamped to\n        \
[0, 1] and stored as round(v x 65535)\n  \
.csv  header cos_v,roughness,alpha,scale,bias; one line per texel, row by row (roughness\n        \
outer, cos_v inner); roughness is the row's nominal r, alpha the value evaluated\n\n\
env-brdf costs about 20 us per value (two per texel): 128 x 128 is well under a second of\n\
CPU time, 1024 x 1024 about 40 s, 4096 x 4096 about 10 minutes, shared across the cores (a\n\
progress bar shows on a terminal). Bad input (a size outside 1..4096, an unknown format,\n\
a model that is not an env model) is exit code 2 and writes nothing; a failed write is exit\n\
code 3 and leaves no file or temporary behind.\n\n\
--out (as every --out of fastbrdf): a regular file is replaced atomically; a symbolic link is\n\
followed and the file it names is replaced (the link stays); a FIFO, a character device\n\
(/dev/null) or /dev/stdout is written in place, never replaced (no extension there: give\n\
--format); a socket, a block device or a link loop is exit code 2."
)]
pub struct Args {
    /// Output file: .exr, .png or .csv (see --format); a link is followed, a FIFO, a device or
    /// /dev/stdout is written in place.
    #[arg(long)]
    out: PathBuf,
    /// An env model (split-sum terms; see `fastbrdf models --kind env`).
    #[arg(long, default_value = "env-brdf")]
    model: String,
    /// Table side N (an N x N table), 1 to 4096.
    #[arg(long, default_value_t = 128, value_name = "N")]
    size: u64,
    /// What the y axis indexes: perceptual roughness r (alpha = r^2) or alpha.
    #[arg(long, default_value = "roughness", value_parser = ["roughness", "alpha"])]
    axis: String,
    /// The file format, instead of the one named by the extension of --out.
    #[arg(long, value_parser = ["exr", "png", "csv"])]
    format: Option<String>,
}

/// The output format: `--format`, else the extension of `out`.
fn format_of(out: &Path, format: Option<&str>) -> Result<&'static str, CliError> {
    fastbrdf_analysis::lut::format_of(out, format).ok_or_else(|| {
        CliError::input(format!(
            "--out {}: the file must end in .exr, .png or .csv (or give --format)",
            shorten_middle(&out.display().to_string(), 80)
        ))
    })
}

pub fn run(a: &Args) -> Result<(), CliError> {
    let format = format_of(&a.out, a.format.as_deref())?;
    let size = usize::try_from(a.size)
        .ok()
        .filter(|n| (1..=MAX_SIZE).contains(n))
        .ok_or_else(|| {
            CliError::input(format!(
                "--size {}: expected 1 to {MAX_SIZE} (an N x N table)",
                a.size
            ))
        })?;
    let axis = if a.axis == "alpha" {
        Axis::Alpha
    } else {
        Axis::Roughness
    };
    // An unknown or non-env model is refused before any work.
    lut::kernels(&a.model)?;
    let pb = bar(size as u64, "lut rows");
    let table = lut::compute(&a.model, size, axis, &|| pb.inc(1))?;
    pb.finish_and_clear();
    let fail = |e: String| CliError::io(format!("{}: {e}", a.out.display()));
    match format {
        "csv" => fastbrdf_io::write_atomic_with(&a.out, |w| table.write_csv(w))?,
        "exr" => fastbrdf_io::write_atomic(&a.out, &table.exr_bytes().map_err(fail)?)?,
        _ => fastbrdf_io::write_atomic(&a.out, &table.png_bytes().map_err(fail)?)?,
    }
    let clamped = table.clamped_rows();
    let note = match clamped {
        0 => String::new(),
        1 => "; row 0 holds alpha = 0.005 (clamped)".to_string(),
        k => format!("; rows 0 to {} hold alpha = 0.005 (clamped)", k - 1),
    };
    eprintln!(
        "wrote {}: {size} x {size} {format}, {}, x = cos_v, y = {} (row 0 = {} at the top){note}",
        a.out.display(),
        table.model,
        axis.name(),
        match axis {
            Axis::Roughness => format!("r {}", table.rows[0].roughness),
            Axis::Alpha => format!("alpha {}", (0.5 / size as f64) as f32),
        }
    );
    Ok(())
}

//! `fastbrdf measured`: measured BRDFs in MERL's `.binary` format (`fastbrdf::measured`).
//!
//! `info FILE` prints the dimensions and each channel's min, max and mean over its valid
//! samples and how many are missing (`--json`: numbers; a channel with no valid sample has
//! null statistics). `eval FILE` reads the CSV `fastbrdf eval` reads for BRDFs
//! (`wi_x,wi_y,wi_z,wo_x,wo_y,wo_z`, other columns passed through) and writes the input
//! columns then `value_r,value_g,value_b`. A malformed MERL file or CSV is exit code 2 naming
//! the file (and the CSV's line and field), with nothing on stdout.

use super::common::input::{Lines, csv_error, csv_headers, read_input, required_columns};
use super::common::pictures::render_rgb;
use super::common::scene::{SceneArgs, check_out};
use crate::{CliError, outln};
use fastbrdf::measured::{self, CHANNELS, MeasuredBrdf};
use fastbrdf_io::shorten;
use std::path::PathBuf;

/// The input columns, in order.
const COLUMNS: [&str; 6] = ["wi_x", "wi_y", "wi_z", "wo_x", "wo_y", "wo_z"];
/// The output columns.
const VALUES: [&str; 3] = ["value_r", "value_g", "value_b"];

#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  fastbrdf measured info gold-metallic-paint.binary\n  \
fastbrdf measured info gold-metallic-paint.binary --json\n  \
printf 'wi_x,wi_y,wi_z,wo_x,wo_y,wo_z\\n0,0,1,0.5,0,0.866\\n' | fastbrdf measured eval gold-metallic-paint.binary\n  \
fastbrdf measured render gold-metallic-paint.binary --out gold.png\n  \
fastbrdf measured render gold-metallic-paint.binary --mesh face --size 256x256 --out face.exr\n  \
fastbrdf fit-measured --data gold-metallic-paint.binary --model cook-torrance --param f=schlick\n\n\
The files are the MERL BRDF database's (Matusik et al. 2003, merl.com/brdf): 100 isotropic\n\
materials, 90 x 90 x 180 samples per colour channel, 34,992,012 bytes each. The lookup is the\n\
reference code's (BRDFRead.cpp): nearest bin in the half/difference angles. Missing samples\n\
(negative in the file) and directions below the horizon evaluate to 0."
)]
pub struct Args {
    #[command(subcommand)]
    command: Sub,
}

#[derive(clap::Subcommand)]
enum Sub {
    /// Dimensions, per-channel min/max/mean of the valid samples, and the missing count.
    Info(InfoArgs),
    /// Evaluate the measured BRDF on CSV rows (wi_x..wo_z): writes value_r,value_g,value_b.
    Eval(EvalArgs),
    /// Render the measured material on a sphere or mesh, like `fastbrdf render` (colour).
    Render(RenderArgs),
}

#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  fastbrdf measured render brass.binary --out brass.png\n  \
fastbrdf measured render brass.binary --mesh face --light dir:0,0,1 --size 256x256 --out face.exr\n  \
fastbrdf measured render brass.binary --env sky --floor --out sky.png\n\n\
The file is the whole BRDF (diffuse part included, in colour): the scene's weights are 0,1\n\
(--weights, --albedo and --texture, which colour the diffuse term, have no effect on it).\n\
Shading looks up the file per direction pair (scalar lookups, f32 directions, the bin found\n\
in f64 as in the reference code). With --env only the map's directions are sampled (the data\n\
has no importance sampling), so it needs more --env-samples than a model for the same noise.\n\
CPU only. Errors as for `fastbrdf render`; a malformed file is exit 2 naming it, and no\n\
picture is written."
)]
struct RenderArgs {
    /// A MERL `.binary` file.
    file: PathBuf,
    #[command(flatten)]
    scene: SceneArgs,
    /// Output file: .png (8-bit sRGB, --exposure applied) or .exr (linear radiance).
    #[arg(long)]
    out: PathBuf,
}

#[derive(clap::Args)]
struct InfoArgs {
    /// A MERL `.binary` file.
    file: PathBuf,
    /// JSON with numbers instead of a table.
    #[arg(long)]
    json: bool,
}

#[derive(clap::Args)]
#[command(
    after_help = "Input: CSV with a header and columns wi_x,wi_y,wi_z,wo_x,wo_y,wo_z (the local frame,\n\
normal +z, any length); other columns are passed through. Output: the input columns then\n\
value_r,value_g,value_b. Errors name the file, line and field; exit code 2 for bad input\n\
(nothing on stdout), 3 when stdout cannot be written."
)]
struct EvalArgs {
    /// A MERL `.binary` file.
    file: PathBuf,
    /// Read CSV from this file instead of stdin.
    #[arg(long)]
    input: Option<PathBuf>,
    /// Arithmetic precision of the returned values (the bin is always found in f64, as in the
    /// reference code).
    #[arg(long, default_value = "f32", value_parser = ["f32", "f64"])]
    precision: String,
    /// The most CSV input read, in MiB.
    #[arg(long, default_value_t = 256, value_name = "MIB")]
    max_input_mib: u64,
}

pub fn run(a: &Args) -> Result<(), CliError> {
    match &a.command {
        Sub::Info(a) => info(a),
        Sub::Eval(a) => eval(a),
        Sub::Render(a) => render(a),
    }
}

fn render(a: &RenderArgs) -> Result<(), CliError> {
    let (spec, opts) = a.scene.spec()?;
    check_out(&a.out, &["png", "exr"])?;
    let b = MeasuredBrdf::read(&a.file)?;
    let loaded = fastbrdf_render::setup::load(&spec)?;
    let t = std::time::Instant::now();
    let label = a.file.display().to_string();
    let film = render_rgb(&spec, &loaded, &opts, &label, std::sync::Arc::new(b))?;
    let rendered = t.elapsed().as_secs_f64();
    film.save(&a.out, a.scene.exposure)?;
    eprintln!(
        "wrote {} ({}x{}, {} samples/pixel, render {:.3} s)",
        a.out.display(),
        opts.width,
        opts.height,
        opts.spp * opts.spp,
        rendered
    );
    Ok(())
}

fn info(a: &InfoArgs) -> Result<(), CliError> {
    let b = MeasuredBrdf::read(&a.file)?;
    let dims = [
        measured::RES_THETA_H,
        measured::RES_THETA_D,
        measured::RES_PHI_D,
    ];
    if a.json {
        let doc = fastbrdf_analysis::measured_json::info(&a.file.display().to_string(), &b);
        outln!(
            "{}",
            serde_json::to_string_pretty(&doc).expect("serialisable")
        );
        return Ok(());
    }
    let stats = b.stats();
    let mut s = format!(
        "{}: MERL BRDF, {} x {} x {} (theta_h x theta_d x phi_d), {} samples per channel\n\
         {:<6} {:>12} {:>12} {:>12} {:>9}\n",
        a.file.display(),
        dims[0],
        dims[1],
        dims[2],
        measured::SAMPLES,
        "channel",
        "min",
        "max",
        "mean",
        "missing"
    );
    for (c, name) in stats.iter().zip(CHANNELS) {
        if c.valid == 0 {
            // Nothing measured: no statistic to print (they would read NaN).
            s.push_str(&format!(
                "{name:<7} {:>12} {:>12} {:>12} {:>9}\n",
                "-", "-", "-", c.missing
            ));
        } else {
            s.push_str(&format!(
                "{name:<7} {:>12.6} {:>12.6} {:>12.6} {:>9}\n",
                c.min, c.max, c.mean, c.missing
            ));
        }
    }
    let empty: Vec<&str> = stats
        .iter()
        .zip(CHANNELS)
        .filter(|(c, _)| c.valid == 0)
        .map(|(_, n)| n)
        .collect();
    if !empty.is_empty() {
        s.push_str(&format!(
            "no measured sample in the {} channel{}: every value is negative (MERL's mark for \
             a missing sample), so min, max and mean are undefined (-)\n",
            empty.join(", "),
            if empty.len() > 1 { "s" } else { "" }
        ));
    }
    super::write_stdout(s.as_bytes())
}

fn eval(a: &EvalArgs) -> Result<(), CliError> {
    let b = MeasuredBrdf::read(&a.file)?;
    let (text, source) = read_input(a.input.as_deref(), a.max_input_mib, "measured eval")?;
    let (mut reader, headers, hline) = csv_headers(&text, &source, &VALUES)?;
    let index = required_columns(&headers, &COLUMNS, &source, hline, "a measured BRDF")?;
    let mut writer = csv::Writer::from_writer(Vec::new());
    let mut header_out: Vec<&str> = headers.iter().collect();
    header_out.extend(VALUES);
    writer.write_record(&header_out).expect("writing to memory");
    let mut lines = Lines::new(&text);
    for record in reader.records() {
        let record = record.map_err(|e| csv_error(&source, &text, &e))?;
        let line = record.position().map_or(0, |p| lines.of(p));
        let mut v = [0.0f64; 6];
        for (k, &i) in index.iter().enumerate() {
            let field = record.get(i).unwrap_or("");
            let x: f64 = field
                .parse()
                .ok()
                .filter(|x: &f64| x.is_finite())
                .ok_or_else(|| {
                    CliError::input(format!(
                        "{source}: line {line}, field {} ('{}'): '{}' is not a finite number",
                        i + 1,
                        COLUMNS[k],
                        shorten(field, 40)
                    ))
                })?;
            v[k] = x;
        }
        let (wi, wo) = ([v[0], v[1], v[2]], [v[3], v[4], v[5]]);
        let mut out: Vec<String> = record.iter().map(str::to_string).collect();
        if a.precision == "f64" {
            out.extend(b.eval_rgb(wi, wo).map(|x| x.to_string()));
        } else {
            let f = |w: [f64; 3]| w.map(|x| x as f32);
            out.extend(b.eval_rgb_f32(f(wi), f(wo)).map(|x| x.to_string()));
        }
        writer.write_record(&out).expect("writing to memory");
    }
    let bytes = writer.into_inner().expect("writing to memory");
    super::write_stdout(&bytes)
}

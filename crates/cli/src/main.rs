//! The `fastbrdf` command: parses arguments (clap), calls the library, prints, and maps
//! errors to exit codes. Exit codes: 0 success, 1 a check failed (`check`) or the GPU failed,
//! 2 bad usage or bad input (unknown model, invalid parameter, malformed CSV, an unreadable
//! or oversized input file), 3 an output could not be written (I/O failure).

// Guards written `if !(x >= lo)` also catch NaN, on purpose (see the fastbrdf crate).
#![allow(clippy::neg_cmp_op_on_partial_ord)]

mod commands;
mod model_args;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// An error the CLI reports: a message and an exit code.
#[derive(Debug)]
pub struct CliError {
    pub code: u8,
    pub message: String,
}

/// Exit code: a check failed (`check`), or the GPU itself failed.
pub const EXIT_CHECK_FAILED: u8 = 1;
/// Exit code: bad usage or bad input.
pub const EXIT_INPUT: u8 = 2;
/// Exit code: an output could not be written.
pub const EXIT_IO: u8 = 3;

impl CliError {
    /// An output could not be written (exit code 3).
    pub fn io(message: impl Into<String>) -> Self {
        Self {
            code: EXIT_IO,
            message: message.into(),
        }
    }

    /// Bad usage or bad input (exit code 2).
    pub fn input(message: impl Into<String>) -> Self {
        Self {
            code: EXIT_INPUT,
            message: message.into(),
        }
    }
}

/// An unreadable or oversized input is exit code 2; an output that cannot be written is 3.
impl From<fastbrdf_io::IoError> for CliError {
    fn from(e: fastbrdf_io::IoError) -> Self {
        match e {
            fastbrdf_io::IoError::Input { .. } => Self::input(e.to_string()),
            fastbrdf_io::IoError::Output { .. } => Self::io(e.to_string()),
        }
    }
}

impl From<fastbrdf::Error> for CliError {
    fn from(e: fastbrdf::Error) -> Self {
        Self::input(e.to_string())
    }
}

/// A renderer's bad input is exit code 2; an output it could not write is 3.
impl From<fastbrdf_render::RenderError> for CliError {
    fn from(e: fastbrdf_render::RenderError) -> Self {
        match e {
            fastbrdf_render::RenderError::Output { .. } => CliError::io(e.to_string()),
            _ => CliError::input(e.to_string()),
        }
    }
}

/// Bad input and a missing adapter are exit code 2; failures on the GPU itself (a shader that
/// does not validate, a failed read-back) are 1.
impl From<fastbrdf_gpu::GpuError> for CliError {
    fn from(e: fastbrdf_gpu::GpuError) -> Self {
        use fastbrdf_gpu::GpuError as G;
        let code = match e {
            G::Input(_) | G::Model(_) | G::NoAdapter(_) => 2,
            _ => 1,
        };
        Self {
            code,
            message: e.to_string(),
        }
    }
}

/// `fastbrdf --version`: the package's version and the commit it was built from (`build.rs`).
const VERSION: &str = concat!(
    env!("CARGO_PKG_VERSION"),
    " (commit ",
    env!("FASTBRDF_COMMIT"),
    ")"
);

#[derive(Parser)]
#[command(
    name = "fastbrdf",
    version = VERSION,
    about = "Exact and fast approximate specular reflectance models: evaluate, compare, check",
    long_about = "fastbrdf implements the exact reflectance models (cos^n, Beckmann, Ward, Cook-Torrance) \
beside the cheaper stand-ins proposed by three papers and by production engines, in f32 and f64, \
each with a documented and tested error bound.",
    after_help = "Examples:\n  fastbrdf models\n  fastbrdf models --kind lobe --json\n  \
printf 'cos\\n1\\n0.99\\n0.9\\n' | fastbrdf eval --model flog --param n=20\n  \
fastbrdf eval --model cook-torrance --param alpha=0.2 --param f=schlick --input pairs.csv\n  fastbrdf check\n  \
fastbrdf errors --model flog --reference pow --n 1..1000 --zone epicentre\n  \
fastbrdf materials\n  fastbrdf errors --over materials\n  fastbrdf measured info brass.binary\n  \
fastbrdf fit-measured --data brass.binary --model cook-torrance --param f=schlick\n  fastbrdf reproduce --out report/\n  \
fastbrdf lut --out dfg.exr\n  \
printf 'wo_x,wo_y,wo_z,u1,u2\\n0,0,1,0.3,0.7\\n' | fastbrdf sample --model cook-torrance --param d=ggx\n  \
fastbrdf chi2 --model phong --param n=100 --theta-i 60\n  fastbrdf view --open\n\n\
Exit codes:\n  0  success\n  1  a check failed (`check`), or the GPU itself failed\n  \
2  bad usage or bad input (unknown model, invalid parameter or range, malformed CSV or mesh,\n     \
an unreadable or oversized input file); nothing is written\n  \
3  an output could not be written (disk full, file-size limit, a reader that went away);\n     no partial \
file or temporary is left behind\n\n\
Machine outputs (--json, --csv) carry numbers; a value with no finite number (an infinite\n\
relative error) is null in JSON and an empty field in CSV. Parameter columns and keys use the\n\
parameter's own name (n, alpha)."
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// List every model: id, kind, parameters, cost, documented error bounds.
    Models(commands::models::Args),
    /// Evaluate one model on CSV rows (stdin or --input) and write CSV with a `value` column.
    Eval(commands::eval::Args),
    /// Importance-sample a BRDF on CSV rows (wo, u): wi, weight = f cos / pdf, pdf.
    Sample(commands::sample::SampleArgs),
    /// Chi-square goodness of fit of a BRDF's sampling against its pdf, with a picture.
    Chi2(commands::sample::Chi2Args),
    /// The checks a renderer's BSDF must pass (finite, reciprocal, energy, sampling against
    /// its pdf), on a registry BRDF or a user's model, with a verdict per check.
    Conform(commands::conform::Args),
    /// Re-measure every documented bound on this machine (error vs reference, f32 vs f64).
    Check(commands::check::Args),
    /// Max absolute, max relative and RMS error of a model against a reference, per n or m.
    Errors(commands::errors::Args),
    /// Int(n) and coef(n) = 1 / (2 pi Int(n)) of a lobe by quadrature, and closed-form fits.
    Normalize(commands::normalize::Args),
    /// Directional albedo against incidence angle, with a white-furnace verdict.
    Albedo(commands::albedo::Args),
    /// Charts as PNG and SVG: lobes, error, max-error, coef, polar, albedo.
    Plot(commands::plot::Args),
    /// Every numeric claim of the three seed papers, measured, with a verdict.
    Reproduce(commands::reproduce::Args),
    /// Scalar and SIMD throughput of every model, the FMA peak, and the seeds' speedups.
    Bench(commands::bench::Args),
    /// Render a sphere or an OBJ mesh shaded by one model, to PNG or EXR.
    Render(commands::render::RenderArgs),
    /// Render several models and a reference side by side, with heat maps and RMSE/PSNR/FLIP.
    Compare(commands::compare::CompareArgs),
    /// The main job on built-in defaults: every lobe on spheres, the seeds' comparisons,
    /// plots and the reproduction table, in a folder with index.html.
    Demo(commands::demo::Args),
    /// The 86 MERL materials' published fits (Ngan et al. 2005): n, m, f0, Ward alpha, albedos.
    Materials(commands::materials::Args),
    /// The named metals: complex index eta + i k per R, G, B channel, F0, sources (--metal).
    Metals(commands::metals::Args),
    /// Measured BRDFs in MERL's .binary format: `info` (statistics), `eval` (CSV rows),
    /// `render` (a picture).
    Measured(commands::measured::Args),
    /// Fit a registry BRDF (with per-channel albedos) to a MERL file: Ngan 2005's L2, Low 2012's
    /// log or the max error; fitted parameters, residuals and a comparison picture.
    FitMeasured(commands::fit_measured::Args),
    /// Minimax-tuned coefficients of an approximation family, per n, and their closed form.
    Fit(commands::fit::FitArgs),
    /// Every lobe's error against its measured SIMD cost, with the Pareto front (table, plot);
    /// --brdf: every Cook-Torrance configuration against an exact one (BRDF and image error).
    Pareto(commands::pareto::Args),
    /// One model as a shader function: WGSL, GLSL, HLSL, MSL, or a BRDF Explorer .brdf file.
    Shader(commands::shader::Args),
    /// The split-sum "DFG" look-up table (scale, bias) of GGX for image-based lighting, as EXR,
    /// PNG or CSV.
    Lut(commands::lut::Args),
    /// An interactive explorer in the browser: plots, renders, errors and shader export of
    /// any models, served on a local port (loopback only unless --allow-remote).
    View(commands::view::Args),
}

/// A file-size limit (`ulimit -f`) must make a write fail with EFBIG, which the atomic writers
/// turn into exit code 3 and a removed temporary, instead of SIGXFSZ killing the process and
/// leaving the temporary behind.
fn ignore_file_size_signal() {
    #[cfg(unix)]
    // SAFETY: setting a signal's disposition to SIG_IGN at start-up, before any thread exists,
    // has no preconditions.
    unsafe {
        libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
    }
}

/// Commands print through `commands::write_stdout` (exit 3 on a failed stdout). A `println!`
/// left in a command panics when stdout is closed or full; this turns that panic into the same
/// exit code 3 and message instead of a panic report (exit 101). Other panics are unchanged.
fn stdout_failures_exit_3() {
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let msg = info
            .payload()
            .downcast_ref::<String>()
            .map(String::as_str)
            .or_else(|| info.payload().downcast_ref::<&str>().copied())
            .unwrap_or("");
        if let Some(rest) = msg.strip_prefix("failed printing to stdout: ") {
            eprintln!("error: cannot write to stdout: {rest}");
            std::process::exit(i32::from(EXIT_IO));
        }
        default(info);
    }));
}

/// mimalloc: the face's default 512 x 512 render took 2,900 page faults with the system
/// allocator (the film and the tiles' buffers, fresh memory; ~1.4 us each on the 2-core VM,
/// 15% of the render's CPU time) and 470 with mimalloc, which backs its segments with
/// transparent huge pages and reuses freed memory across threads (`perf stat -e
/// minor-faults fastbrdf render ...`); the render ran 1.05-1.10x faster
/// (`tools/render_speed.sh`).
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() -> ExitCode {
    ignore_file_size_signal();
    stdout_failures_exit_3();
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Models(a) => commands::models::run(&a),
        Command::Eval(a) => commands::eval::run(&a),
        Command::Sample(a) => commands::sample::run_sample(&a),
        Command::Chi2(a) => commands::sample::run_chi2(&a),
        Command::Conform(a) => commands::conform::run(&a),
        Command::Check(a) => commands::check::run(&a),
        Command::Errors(a) => commands::errors::run(&a),
        Command::Normalize(a) => commands::normalize::run(&a),
        Command::Albedo(a) => commands::albedo::run(&a),
        Command::Plot(a) => commands::plot::run(&a),
        Command::Reproduce(a) => commands::reproduce::run(&a),
        Command::Bench(a) => commands::bench::run(&a),
        Command::Render(a) => commands::render::run_render(&a),
        Command::Compare(a) => commands::compare::run_compare(&a),
        Command::Demo(a) => commands::demo::run(&a),
        Command::Materials(a) => commands::materials::run(&a),
        Command::Metals(a) => commands::metals::run(&a),
        Command::Measured(a) => commands::measured::run(&a),
        Command::FitMeasured(a) => commands::fit_measured::run(&a),
        Command::Fit(a) => commands::fit::run_fit(&a),
        Command::Pareto(a) => commands::pareto::run(&a),
        Command::Shader(a) => commands::shader::run(&a),
        Command::Lut(a) => commands::lut::run(&a),
        Command::View(a) => commands::view::run(&a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", e.message);
            ExitCode::from(e.code)
        }
    }
}

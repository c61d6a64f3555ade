//! Users' models in `fastbrdf bench --gpu --model file:PATH` (issue 31): each file read and
//! its `--param` values checked before any timing (a bad file is exit 2 at once, naming the
//! file, line and column), its instruction count taken once (`spirv-opt`; without it the count
//! is unknown, with a note on stderr), then timed on the GPU as the built-in models are
//! (`fastbrdf_gpu::user::bench::measure`) and listed in the same tables.

use crate::CliError;
use crate::model_args::{USER_PREFIX, is_user, pairs};
use fastbrdf_analysis::speed::{self, Instructions, KernelRow};
use fastbrdf_gpu::cost::Counts;
use fastbrdf_gpu::user::{UserError, UserErrorKind, UserShader};
use fastbrdf_io::{shorten, shorten_middle};

/// The most characters of a given value quoted in a message.
const QUOTE: usize = 60;

/// A user's model to time.
pub struct UserModel {
    /// Its rows' model name: `file:PATH`, with `[NAME=VALUE,...]` when values were given.
    pub name: String,
    pub shader: UserShader,
    /// The `--param` values it declares.
    pub given: Vec<(String, String)>,
    /// Its instruction counts, `None` when they could not be taken (no `spirv-opt`).
    pub instructions: Option<Instructions>,
}

/// A [`UserError`] as the CLI reports it: the user's input exit 2, the GPU exit 1.
pub fn cli_error(e: UserError) -> CliError {
    CliError {
        code: match e.kind {
            UserErrorKind::Input => crate::EXIT_INPUT,
            UserErrorKind::Gpu => crate::EXIT_CHECK_FAILED,
        },
        message: e.message,
    }
}

/// The counts as the report stores them.
pub fn instructions(c: Counts) -> Instructions {
    Instructions {
        arithmetic: c.arithmetic,
        transcendental: c.transcendental,
        division_sqrt: c.division_sqrt,
        branches: c.branches,
        select: c.select,
        other: c.other,
        total: c.total,
    }
}

/// Reads every `--model` file and gives each the `--param` values it declares. A registry id,
/// a repeated file, an unreadable or malformed file, a compile error, a value outside a
/// declared range and a value no file declares are exit 2; nothing is timed before this.
pub fn load(ids: &[String], params: &[String]) -> Result<Vec<UserModel>, CliError> {
    let all = pairs(params)?;
    if ids.is_empty() {
        if let Some((k, v)) = all.first() {
            return Err(CliError::input(format!(
                "--param {}={}: bench takes parameters only for a user's model (--model \
                 file:PATH); the built-in models run at their benchmark configurations",
                shorten(k, QUOTE),
                shorten(v, QUOTE)
            )));
        }
        return Ok(vec![]);
    }
    let mut out: Vec<UserModel> = Vec::new();
    for id in ids {
        if !is_user(id) {
            return Err(CliError::input(format!(
                "--model {}: bench's --model takes a user's model, file:PATH; choose built-in \
                 models with --models {}",
                shorten_middle(id, QUOTE),
                shorten_middle(id, QUOTE)
            )));
        }
        let path = &id[USER_PREFIX.len()..];
        if path.is_empty() {
            return Err(CliError::input(
                "--model file:: no path after 'file:' (e.g. --model file:my.brdf)",
            ));
        }
        let shader = UserShader::load(std::path::Path::new(path)).map_err(cli_error)?;
        if out.iter().any(|u| u.shader.name() == shader.name()) {
            return Err(CliError::input(format!(
                "--model {}: given twice",
                shorten_middle(id, QUOTE)
            )));
        }
        let given: Vec<(String, String)> = all
            .iter()
            .filter(|(k, _)| shader.params().iter().any(|p| &p.name == k))
            .cloned()
            .collect();
        shader.values(&given).map_err(cli_error)?;
        let name = if given.is_empty() {
            shader.name()
        } else {
            let v: Vec<String> = given.iter().map(|(k, v)| format!("{k}={v}")).collect();
            format!("{}[{}]", shader.name(), v.join(","))
        };
        out.push(UserModel {
            name,
            shader,
            given,
            instructions: None,
        });
    }
    if let Some((k, _)) = all
        .iter()
        .find(|(k, _)| !out.iter().any(|u| u.given.iter().any(|(g, _)| g == k)))
    {
        let declared: Vec<String> = out
            .iter()
            .map(|u| {
                let names: Vec<&str> = u.shader.params().iter().map(|p| p.name.as_str()).collect();
                format!(
                    "{}: {}",
                    u.shader.name(),
                    if names.is_empty() {
                        "none".into()
                    } else {
                        names.join(", ")
                    }
                )
            })
            .collect();
        return Err(CliError::input(format!(
            "--param {}: no --model file declares it (declared: {})",
            shorten(k, QUOTE),
            declared.join("; ")
        )));
    }
    for u in &mut out {
        match u.shader.instructions() {
            Ok(c) => u.instructions = Some(instructions(c)),
            Err(e) => eprintln!(
                "note: instruction count of {} unknown (shown as -): {e}",
                u.name
            ),
        }
    }
    Ok(out)
}

/// Times the user's model `u` on `gpu` over the first `n` direction pairs of `inputs` (the
/// built-in BRDFs' batch), spending about `budget` on each figure, into `r`: two rows, `gpu`
/// and `gpu+transfer`, as each built-in model gets (or two `skipped` entries).
pub fn measure(
    r: &mut speed::Report,
    gpu: &fastbrdf_gpu::Gpu,
    u: &UserModel,
    inputs: &speed::Inputs,
    n: usize,
    budget: std::time::Duration,
) -> Result<(), CliError> {
    let dirs: [&[f32]; 6] = std::array::from_fn(|k| &inputs.dirs[k][..n]);
    let t = fastbrdf_gpu::user::bench::measure(
        &gpu.device,
        &gpu.queue,
        &u.shader,
        &u.given,
        dirs,
        budget,
    )
    .map_err(cli_error)?;
    super::push_gpu(r, &u.name, n, t, u.instructions);
    Ok(())
}

/// Sets every built-in row's instruction counts from the committed table (by the
/// benchmark's configuration name; rows the table lacks, such as the C loops, stay unknown).
pub fn fill_builtin(rows: &mut [KernelRow]) {
    let table: Vec<(String, Option<Counts>)> = speed::configurations()
        .into_iter()
        .map(|(name, spec)| (name, fastbrdf_gpu::cost::lookup(&spec)))
        .collect();
    for r in rows.iter_mut().filter(|r| r.instructions.is_none()) {
        if let Some((_, Some(c))) = table.iter().find(|(n, _)| *n == r.model) {
            r.instructions = Some(instructions(*c));
        }
    }
}

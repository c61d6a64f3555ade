//! A WGSL function inside a compute entry point, through naga to SPIR-V and `spirv-opt -O`.

use std::io::Write;
use std::process::{Command, Stdio};

/// The entry point's name, and the prefix of every name the wrapper adds.
pub const ENTRY: &str = "fbcost_main";
const PREFIX: &str = "fbcost_";

/// Parses and validates WGSL, errors as naga prints them (line and column in `what`).
fn parse(src: &str, what: &str) -> Result<(naga::Module, naga::valid::ModuleInfo), String> {
    let module = naga::front::wgsl::parse_str(src)
        .map_err(|e| format!("{what}: {}", e.emit_to_string_with_path(src, what)))?;
    let info = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(&module)
    .map_err(|e| format!("{what}: {}", e.emit_to_string_with_path(src, what)))?;
    Ok((module, info))
}

/// The WGSL name of a 32-bit scalar or vector type, or `None`.
fn type_name(inner: &naga::TypeInner) -> Option<String> {
    let scalar = |s: &naga::Scalar| match (s.kind, s.width) {
        (naga::ScalarKind::Float, 4) => Some("f32"),
        (naga::ScalarKind::Sint, 4) => Some("i32"),
        (naga::ScalarKind::Uint, 4) => Some("u32"),
        _ => None,
    };
    match inner {
        naga::TypeInner::Scalar(s) => scalar(s).map(str::to_string),
        naga::TypeInner::Vector { size, scalar: s } => {
            scalar(s).map(|t| format!("vec{}<{t}>", *size as u8))
        }
        _ => None,
    }
}

/// `module` with a compute entry point that reads `function`'s arguments from a storage
/// struct, calls it, and stores the result in a storage variable.
pub fn wrapped(module: &str, function: &str, what: &str) -> Result<String, String> {
    let (m, _) = parse(module, what)?;
    let names = m
        .functions
        .iter()
        .filter_map(|(_, f)| f.name.as_deref())
        .chain(m.entry_points.iter().map(|e| e.name.as_str()))
        .chain(
            m.global_variables
                .iter()
                .filter_map(|(_, g)| g.name.as_deref()),
        )
        .chain(m.types.iter().filter_map(|(_, t)| t.name.as_deref()))
        .chain(m.constants.iter().filter_map(|(_, c)| c.name.as_deref()));
    for n in names {
        if n.starts_with(PREFIX) {
            return Err(format!(
                "{what}: the name {n} is reserved for the counting wrapper (names starting {PREFIX})"
            ));
        }
    }
    let (_, f) = m
        .functions
        .iter()
        .find(|(_, f)| f.name.as_deref() == Some(function))
        .ok_or_else(|| {
            let known: Vec<&str> = m
                .functions
                .iter()
                .filter_map(|(_, f)| f.name.as_deref())
                .collect();
            format!(
                "{what}: no function {function} (functions: {})",
                if known.is_empty() {
                    "none".into()
                } else {
                    known.join(", ")
                }
            )
        })?;
    let unsupported = |t: naga::Handle<naga::Type>| {
        m.types[t]
            .name
            .clone()
            .unwrap_or_else(|| format!("{:?}", m.types[t].inner))
    };
    let mut fields = Vec::new();
    for (k, a) in f.arguments.iter().enumerate() {
        let ty = type_name(&m.types[a.ty].inner).ok_or_else(|| {
            format!(
                "{what}: argument {} of {function} has type {}: only f32, i32, u32 and their vectors can be counted",
                a.name.as_deref().unwrap_or("?"),
                unsupported(a.ty)
            )
        })?;
        fields.push(format!("    a{k}: {ty},"));
    }
    let ret = f
        .result
        .as_ref()
        .ok_or_else(|| format!("{what}: {function} returns nothing"))?;
    let ret_ty = type_name(&m.types[ret.ty].inner).ok_or_else(|| {
        format!(
            "{what}: {function} returns {}: only f32, i32, u32 and their vectors can be counted",
            unsupported(ret.ty)
        )
    })?;
    // A free bind group: one past the module's own.
    let group = m
        .global_variables
        .iter()
        .filter_map(|(_, g)| g.binding.as_ref().map(|b| b.group + 1))
        .max()
        .unwrap_or(0);
    let args: Vec<String> = (0..f.arguments.len())
        .map(|k| format!("{PREFIX}in.a{k}"))
        .collect();
    let input = if fields.is_empty() {
        String::new()
    } else {
        format!(
            "struct {PREFIX}In {{\n{}\n}}\n@group({group}) @binding(0) var<storage, read> {PREFIX}in: {PREFIX}In;\n",
            fields.join("\n")
        )
    };
    Ok(format!(
        "{module}\n// fastbrdf's counting wrapper (fastbrdf_gpu::cost).\n{input}@group({group}) @binding(1) var<storage, read_write> {PREFIX}out: {ret_ty};\n@compute @workgroup_size(1)\nfn {ENTRY}() {{\n    {PREFIX}out = {function}({});\n}}\n",
        args.join(", ")
    ))
}

/// `src` (with entry point [`ENTRY`]) as SPIR-V, naga's writer set for counting: no debug
/// information, no loop-bounding counters (a wgpu safety net, not the shader's work), the
/// entry point alone.
pub fn spirv(src: &str, what: &str) -> Result<Vec<u32>, String> {
    let (module, info) = parse(src, what)?;
    let options = naga::back::spv::Options {
        lang_version: (1, 3),
        flags: naga::back::spv::WriterFlags::empty(),
        force_loop_bounding: false,
        ..Default::default()
    };
    let pipeline = naga::back::spv::PipelineOptions {
        shader_stage: naga::ShaderStage::Compute,
        entry_point: ENTRY.into(),
    };
    naga::back::spv::write_vec(&module, &info, &options, Some(&pipeline))
        .map_err(|e| format!("{what}: naga's SPIR-V writer: {e}"))
}

/// The `spirv-opt` program: `$FASTBRDF_SPIRV_OPT` or `spirv-opt` on `PATH`.
fn program() -> String {
    std::env::var("FASTBRDF_SPIRV_OPT").unwrap_or_else(|_| "spirv-opt".into())
}

fn missing(p: &str, e: &std::io::Error) -> String {
    format!(
        "cannot run {p} ({e}): instruction counts need SPIRV-Tools' spirv-opt on PATH (Debian and \
         Ubuntu: apt-get install spirv-tools; or set FASTBRDF_SPIRV_OPT to its path)"
    )
}

/// `spirv-opt --version`'s first line, or an error naming what is missing.
pub fn version() -> Result<String, String> {
    let p = program();
    let out = Command::new(&p)
        .arg("--version")
        .output()
        .map_err(|e| missing(&p, &e))?;
    // SPIRV-Tools 2023.1 prints its version on stderr.
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    let line = text
        .lines()
        .find(|l| !l.trim().is_empty())
        .unwrap_or("")
        .trim();
    if !out.status.success() || line.is_empty() {
        return Err(format!("{p} --version failed ({}): {line}", out.status));
    }
    Ok(line.to_string())
}

/// `words` through `spirv-opt -O` (stdin to stdout).
pub fn optimise(words: &[u32], what: &str) -> Result<Vec<u32>, String> {
    let p = program();
    let mut child = Command::new(&p)
        .args(["-O", "--target-env=vulkan1.1", "-", "-o", "-"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| missing(&p, &e))?;
    let bytes: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
    let mut stdin = child.stdin.take().expect("piped stdin");
    // A writer thread: spirv-opt may fill its stdout before it has read all of stdin.
    let writer = std::thread::spawn(move || stdin.write_all(&bytes));
    let out = child
        .wait_with_output()
        .map_err(|e| format!("{what}: {p}: {e}"))?;
    let written = writer.join().expect("writer thread");
    if !out.status.success() {
        return Err(format!(
            "{what}: {p} -O failed ({}): {}",
            out.status,
            String::from_utf8_lossy(&out.stderr).trim()
        ));
    }
    written.map_err(|e| format!("{what}: writing to {p}: {e}"))?;
    if out.stdout.len() % 4 != 0 {
        return Err(format!(
            "{what}: {p} wrote {} bytes, not whole SPIR-V words",
            out.stdout.len()
        ));
    }
    Ok(out
        .stdout
        .chunks_exact(4)
        .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect())
}

//! Generated sections (`<!-- NAME:begin -->` ... `<!-- NAME:end -->`): each equals its
//! command's output; `FASTBRDF_BLESS=1` rewrites them.

use super::*;
use std::path::Path;
use std::process::Command;

/// A section of the documentation that is a command's output: its marker, its page, the
/// command (run in the repository root), and whether the output sits in a ```text block.
struct Generated {
    marker: &'static str,
    page: &'static str,
    args: &'static [&'static str],
    fenced: bool,
    /// Turns the command's output into the section (default: the output as it is).
    render: Option<fn(&str) -> String>,
}

const GENERATED: &[Generated] = &[
    Generated {
        marker: "models-detail",
        page: "docs/book/src/models.md",
        args: &["models", "--json"],
        fenced: false,
        render: Some(model_details),
    },
    Generated {
        marker: "models",
        page: "docs/book/src/models.md",
        args: &["models"],
        fenced: true,
        render: None,
    },
    Generated {
        marker: "bench",
        page: "docs/book/src/speed.md",
        args: &["bench", "--from", "docs/bench/bench.json", "--markdown"],
        fenced: false,
        render: None,
    },
    Generated {
        marker: "bench-gpu",
        page: "docs/book/src/gpu.md",
        args: &[
            "bench",
            "--from",
            "docs/bench/bench-gpu.json",
            "--gpu-only",
            "--markdown",
        ],
        fenced: false,
        render: None,
    },
    Generated {
        marker: "pareto",
        page: "docs/book/src/tuned.md",
        args: &["pareto", "--bench", "docs/bench/bench.json", "--markdown"],
        fenced: false,
        render: None,
    },
    Generated {
        marker: "pareto-brdf",
        page: "docs/book/src/pareto-brdf.md",
        args: &[
            "pareto",
            "--brdf",
            "--costs",
            "docs/bench/pareto-brdf.json",
            "--mesh",
            "crates/render/data/canonical_face_model.obj",
            "--markdown",
        ],
        fenced: false,
        render: None,
    },
    Generated {
        marker: "reproduce",
        page: "docs/book/src/reproduction.md",
        args: &[
            "reproduce",
            "--markdown",
            "--speedups",
            "docs/bench/bench.json",
        ],
        fenced: false,
        render: None,
    },
];

fn bless() -> bool {
    std::env::var("FASTBRDF_BLESS").is_ok_and(|v| v == "1")
}

/// The section `g` of its page equals the command's output (with FASTBRDF_BLESS=1: is
/// rewritten to it).
fn check_generated(marker: &str) {
    let g = GENERATED.iter().find(|g| g.marker == marker).unwrap();
    let root = root();
    let o = Command::new(env!("CARGO_BIN_EXE_fastbrdf"))
        .current_dir(&root)
        .args(g.args)
        .output()
        .unwrap();
    assert!(
        o.status.success(),
        "fastbrdf {}: {}",
        g.args.join(" "),
        String::from_utf8_lossy(&o.stderr)
    );
    let out = String::from_utf8(o.stdout).unwrap();
    let out = match g.render {
        Some(render) => render(&out),
        None => out,
    };
    let want = if g.fenced {
        format!("```text\n{out}```\n")
    } else {
        out
    };
    let path = root.join(g.page);
    let page = std::fs::read_to_string(&path).unwrap();
    let open = format!("<!-- {marker}:begin -->\n");
    let close = format!("<!-- {marker}:end -->");
    let start = page
        .find(&open)
        .unwrap_or_else(|| panic!("{} has no {open}", g.page))
        + open.len();
    let end = start
        + page[start..]
            .find(&close)
            .unwrap_or_else(|| panic!("{} does not close {marker}", g.page));
    if page[start..end] == want {
        return;
    }
    if bless() {
        let new = format!("{}{want}{}", &page[..start], &page[end..]);
        std::fs::write(&path, new).unwrap();
        return;
    }
    panic!(
        "{}'s section {marker} is stale: it is the output of `fastbrdf {}`. Regenerate it with \
         `FASTBRDF_BLESS=1 cargo test -p fastbrdf-cli --test docs generated` and review the diff",
        g.page,
        g.args.join(" ")
    );
}

#[test]
fn generated_models_reference_is_the_registry() {
    check_generated("models");
    check_generated("models-detail");
}

/// The model reference's sections, one per model, from `fastbrdf models --json`: formula,
/// source, note, parameters (range, default, choices), bounds, f32 bound and operation counts.
fn model_details(json: &str) -> String {
    use serde_json::Value;
    use std::fmt::Write;
    let v: Value = serde_json::from_str(json).unwrap();
    let num = |x: &Value| match x.as_f64() {
        Some(f) if f != 0.0 && f.abs() < 1e-3 => format!("{f:e}"),
        Some(f) => format!("{f}"),
        None => x.to_string(),
    };
    let mut out = String::new();
    let mut kind = String::new();
    for m in v["models"].as_array().unwrap() {
        let k = m["kind"].as_str().unwrap();
        if k != kind {
            kind = k.to_string();
            let _ = write!(out, "\n### Kind `{kind}`\n");
        }
        let _ = write!(out, "\n#### `{}`\n\n", m["id"].as_str().unwrap());
        let _ = writeln!(out, "- formula: `{}`", m["formula"].as_str().unwrap_or(""));
        let _ = writeln!(out, "- source: {}", m["source"].as_str().unwrap_or(""));
        if let Some(note) = m["note"].as_str().filter(|s| !s.is_empty()) {
            let _ = writeln!(out, "- note: {note}");
        }
        for p in m["params"].as_array().unwrap() {
            let name = p["name"].as_str().unwrap();
            let doc = p["doc"].as_str().unwrap_or("");
            if p["type"] == "number" {
                let _ = writeln!(
                    out,
                    "- `{name}` in [{}, {}], default {}: {doc}",
                    num(&p["min"]),
                    num(&p["max"]),
                    num(&p["default"])
                );
            } else {
                let options: Vec<String> = p["options"]
                    .as_array()
                    .map(|o| {
                        o.iter()
                            .map(|x| format!("`{}`", x.as_str().unwrap()))
                            .collect()
                    })
                    .unwrap_or_default();
                let _ = writeln!(
                    out,
                    "- `{name}`, one of {}; default `{}`: {doc}",
                    options.join(", "),
                    p["default"].as_str().unwrap_or("")
                );
            }
        }
        for b in m["bounds"].as_array().unwrap() {
            let range = &b["param"];
            let _ = writeln!(
                out,
                "- bound against `{}`: {} {} (divided by the {}) <= {}, {} in [{}, {}]",
                b["reference"].as_str().unwrap_or(""),
                b["metric"].as_str().unwrap_or(""),
                b["zone"].as_str().unwrap_or(""),
                b["divided_by"].as_str().unwrap_or(""),
                num(&b["bound"]),
                range[0].as_str().unwrap_or(""),
                num(&range[1]),
                num(&range[2])
            );
        }
        let o = &m["ops"];
        let _ = writeln!(
            out,
            "- f32 bound {}; operations (multiplies/adds/divides/square roots/transcendentals) {}/{}/{}/{}/{}",
            num(&m["f32_bound"]),
            num(&o["mul"]),
            num(&o["add"]),
            num(&o["div"]),
            num(&o["sqrt"]),
            num(&o["transcendental"])
        );
    }
    out
}

#[test]
fn generated_bench_tables_are_the_saved_run() {
    check_generated("bench");
}

#[test]
fn generated_gpu_bench_tables_are_the_saved_run() {
    check_generated("bench-gpu");
}

#[test]
fn generated_pareto_table_is_current() {
    check_generated("pareto");
}

#[test]
fn generated_pareto_brdf_table_is_current() {
    check_generated("pareto-brdf");
}

#[test]
fn generated_reproduction_table_is_current() {
    check_generated("reproduce");
}

/// Every `<!-- NAME:begin -->` in the documentation is one of `GENERATED` (a section nobody
/// regenerates would go stale), on the page named there, once.
#[test]
fn every_generated_section_is_checked() {
    let root = root();
    let mut found = Vec::new();
    for p in pages() {
        let text = std::fs::read_to_string(root.join(&p)).unwrap();
        for line in text.lines() {
            if let Some(m) = line
                .strip_prefix("<!-- ")
                .and_then(|l| l.strip_suffix(":begin -->"))
            {
                found.push((m.to_string(), p.clone()));
            }
        }
    }
    for (marker, page) in &found {
        let g = GENERATED.iter().find(|g| g.marker == marker);
        assert!(
            g.is_some_and(|g| Path::new(g.page) == page),
            "{}: section {marker} is not in docs.rs's GENERATED list (or not on its page)",
            page.display()
        );
    }
    for g in GENERATED {
        assert_eq!(
            found.iter().filter(|(m, _)| m == g.marker).count(),
            1,
            "section {} appears once",
            g.marker
        );
    }
}

//! The library chapter's example is a function compiled and run here; ARCHITECTURE.md's
//! "Where a model lives" names every family file.

use super::*;
use std::path::Path;

// --- The library chapter's example ---------------------------------------------------------

/// The ```rust block of docs/book/src/library.md is this function's body, text for text
/// (between the `doc:library` markers), so it compiles with the library as it is.
#[allow(dead_code)]
fn library_example() -> Result<(), fastbrdf::Error> {
    // doc:library:begin
    use fastbrdf::{Given, Model, ModelSpec};

    // Text from a command line or a file: parsed and validated once.
    let spec = ModelSpec::parse(
        "cook-torrance",
        &[("alpha", "0.2"), ("d", "beckmann-power16")],
    )?;
    let Model::Brdf(ct) = spec.model::<f32>()? else {
        unreachable!("cook-torrance is a BRDF")
    };
    let f = ct.eval([0.3, 0.0, 0.95], [-0.3, 0.1, 0.95]);
    assert!(f > 0.0);

    // Typed values (a fit, a slider): no text on the way.
    let ggx = ModelSpec::new("ggx", &[("alpha", Given::Num(0.3))])?;
    let Model::Distribution(d) = ggx.model::<f64>()? else {
        unreachable!("ggx is a distribution")
    };
    assert!(d.eval(1.0) > 0.0);

    // The SIMD batch kernel of the same spec.
    let kernel = fastbrdf::batch::Kernel::new(&ggx)?;
    assert!(kernel.simd());
    // doc:library:end
    Ok(())
}

#[test]
fn library_example_runs_and_is_the_chapters_block() {
    library_example().unwrap();
    let me = include_str!("library.rs");
    let begin = me.find("// doc:library:begin\n").unwrap() + "// doc:library:begin\n".len();
    let end = me.find("    // doc:library:end").unwrap();
    let body: String = me[begin..end]
        .lines()
        .map(|l| l.strip_prefix("    ").unwrap_or(l))
        .map(|l| format!("{l}\n"))
        .collect();
    let chapter = std::fs::read_to_string(root().join(BOOK).join("library.md")).unwrap();
    let block = blocks_of(Path::new("library.md"), &chapter)
        .into_iter()
        .find(|b| b.lang == "rust")
        .expect("library.md has a rust block");
    assert_eq!(
        block.body, body,
        "docs/book/src/library.md's rust block must be library_example's body in crates/cli/tests/docs_support/library.rs"
    );
}

// --- ARCHITECTURE.md's list of model files --------------------------------------------------

/// ARCHITECTURE.md's "Where a model lives" names every family file of the core crate (the
/// ids they serve are the generated model reference), so a new family cannot be left out.
#[test]
fn architecture_names_every_family_file() {
    let root = root();
    let arch = std::fs::read_to_string(root.join("ARCHITECTURE.md")).unwrap();
    let section = &arch[arch
        .find("## Where a model lives")
        .expect("ARCHITECTURE.md has 'Where a model lives'")..];
    let block = blocks_of(Path::new("ARCHITECTURE.md"), section)
        .into_iter()
        .next()
        .expect("a code block listing the files")
        .body;
    let words: Vec<&str> = block
        .split(|c: char| !(c.is_alphanumeric() || c == '_'))
        .collect();
    let mut missing = Vec::new();
    for dir in ["lobes", "microfacet", "brdf"] {
        for e in std::fs::read_dir(root.join("crates/fastbrdf/src").join(dir)).unwrap() {
            let p = e.unwrap().path();
            let stem = p.file_stem().unwrap().to_string_lossy().into_owned();
            if p.extension().is_some_and(|x| x == "rs")
                && stem != "mod"
                && !words.contains(&stem.as_str())
            {
                missing.push(format!("src/{dir}/{stem}.rs"));
            }
        }
    }
    assert!(
        missing.is_empty(),
        "ARCHITECTURE.md's 'Where a model lives' does not name {missing:?}"
    );
}

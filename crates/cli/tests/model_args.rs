//! The model options (`--param`, `--material`, `--metal`), declared once in the CLI's
//! `model_args` and parsed once into a validated model spec: every command that takes them
//! refuses the same bad text with the same message (exit code 2, nothing on stdout), given
//! values win over a material's and a metal's, and a shaded model takes the values of the BRDF
//! it is shaded as.

mod common;

use common::{fastbrdf, stderr, stdout, temp_dir};

/// Every command that takes `--param`, with what else it needs to get as far as the model.
fn commands_with_param(out: &str) -> Vec<Vec<String>> {
    let v = |a: &[&str]| a.iter().map(|s| s.to_string()).collect::<Vec<_>>();
    vec![
        v(&["eval", "--model", "flog"]),
        v(&["sample", "--model", "phong"]),
        v(&["chi2", "--model", "phong", "--samples", "1000"]),
        v(&["albedo", "--model", "ward"]),
        v(&["conform", "ward"]),
        v(&["render", "--model", "flog", "--size", "16x16", "--out", out]),
        v(&[
            "compare",
            "--models",
            "flog",
            "--reference",
            "pow",
            "--size",
            "16x16",
            "--out",
            out,
        ]),
        v(&["shader", "--model", "flog"]),
        v(&["plot", "polar", "--model", "ward", "--out", out]),
        v(&["plot", "albedo", "--model", "ward", "--out", out]),
    ]
}

#[test]
fn every_command_refuses_the_same_bad_param_text() {
    let dir = temp_dir("model-args-text");
    let out = dir.join("x.png");
    let out = out.to_str().unwrap();
    for base in commands_with_param(out) {
        // The model follows --model or --models, or is the first argument (conform's MODEL).
        let model = match base.iter().position(|a| a == "--model" || a == "--models") {
            Some(at) => &base[at + 1],
            None => &base[1],
        };
        let unknown = if base[0] == "compare" {
            "--param q: none of the models takes it".to_string()
        } else {
            // Named after the model chosen, even when it is shaded as another BRDF.
            format!("model '{model}' has no parameter 'q'")
        };
        for (bad, expected) in [
            ("n", "--param 'n': expected NAME=VALUE".to_string()),
            ("q=1", unknown.clone()),
        ] {
            let mut args: Vec<&str> = base.iter().map(String::as_str).collect();
            args.extend(["--param", bad]);
            let r = fastbrdf(&args, "cos\n1\n");
            assert_eq!(r.status.code(), Some(2), "{args:?}: {}", stderr(&r));
            assert!(
                stderr(&r).contains(&expected),
                "{args:?}: {:?} lacks {expected:?}",
                stderr(&r)
            );
            assert!(r.stdout.is_empty(), "{args:?} printed {}", stdout(&r));
        }
    }
    assert!(!dir.join("x.png").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn an_out_of_range_value_names_the_model_parameter_and_value() {
    for args in [
        vec!["eval", "--model", "flog", "--param", "n=-3"],
        vec!["shader", "--model", "flog", "--param", "n=-3"],
        vec!["albedo", "--model", "phong", "--param", "n=-3"],
    ] {
        let r = fastbrdf(&args, "cos\n1\n");
        assert_eq!(r.status.code(), Some(2), "{args:?}");
        let e = stderr(&r);
        assert!(
            e.contains("flog") || e.contains("phong"),
            "{args:?}: {e} does not name the model"
        );
        assert!(e.contains("n = -3"), "{args:?}: {e}");
    }
}

/// Given values win over the metal's: `--param eta=1.5` keeps eta grey while k comes from the
/// metal, so the output is still coloured (three columns) and differs from plain gold.
#[test]
fn given_values_win_over_a_metal() {
    let input = "cos_vh\n1\n0.5\n";
    let gold = fastbrdf(
        &["eval", "--model", "fresnel-conductor", "--metal", "gold"],
        input,
    );
    assert!(gold.status.success(), "{}", stderr(&gold));
    let mine = fastbrdf(
        &[
            "eval",
            "--model",
            "fresnel-conductor",
            "--metal",
            "gold",
            "--param",
            "eta=1.5",
        ],
        input,
    );
    assert!(mine.status.success(), "{}", stderr(&mine));
    let (g, m) = (stdout(&gold), stdout(&mine));
    assert!(g.starts_with("cos_vh,value_r,value_g,value_b") && m.starts_with("cos_vh,value_r"));
    assert_ne!(g, m, "--param eta was ignored");
}

/// Given values win over a material's: the label of a comparison shows the value given, not
/// the fit's.
#[test]
fn given_values_win_over_a_material() {
    let dir = temp_dir("model-args-material");
    let out = dir.join("cmp.png");
    let r = fastbrdf(
        &[
            "compare",
            "--models",
            "flog",
            "--reference",
            "pow",
            "--material",
            "gold-paint",
            "--param",
            "n=20",
            "--size",
            "16x16",
            "--json",
            "--out",
            out.to_str().unwrap(),
        ],
        "",
    );
    assert!(r.status.success(), "{}", stderr(&r));
    let v: serde_json::Value = serde_json::from_str(&stdout(&r)).unwrap();
    assert_eq!(v["metrics"][0]["model"], "flog n=20");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A distribution renders as cook-torrance: the values cook-torrance takes (g, f, a metal's
/// eta and k) are accepted for it, and the label names the distribution, not cook-torrance.
#[test]
fn a_shaded_distribution_takes_its_brdfs_values_and_keeps_its_name() {
    let dir = temp_dir("model-args-shaded");
    let png = dir.join("ggx.png");
    let r = fastbrdf(
        &[
            "render",
            "--model",
            "ggx",
            "--param",
            "alpha=0.3",
            "--param",
            "g=smith-ggx-correlated",
            "--metal",
            "gold",
            "--size",
            "16x16",
            "--out",
            png.to_str().unwrap(),
        ],
        "",
    );
    assert!(r.status.success(), "{}", stderr(&r));
    assert!(png.exists());
    let cmp = dir.join("cmp.png");
    let r = fastbrdf(
        &[
            "compare",
            "--models",
            "ggx",
            "--reference",
            "cook-torrance",
            "--param",
            "alpha=0.3",
            "--param",
            "f=schlick",
            "--size",
            "16x16",
            "--json",
            "--out",
            cmp.to_str().unwrap(),
        ],
        "",
    );
    assert!(r.status.success(), "{}", stderr(&r));
    let v: serde_json::Value = serde_json::from_str(&stdout(&r)).unwrap();
    assert_eq!(v["metrics"][0]["model"], "ggx alpha=0.3 f=schlick");
    // A value the model itself takes is checked against it: the message names ggx.
    let r = fastbrdf(
        &[
            "render",
            "--model",
            "ggx",
            "--param",
            "alpha=7",
            "--size",
            "16x16",
            "--out",
            png.to_str().unwrap(),
        ],
        "",
    );
    assert_eq!(r.status.code(), Some(2));
    assert!(stderr(&r).contains("ggx"), "{}", stderr(&r));
    let _ = std::fs::remove_dir_all(&dir);
}

/// A metal needs the conductor term's eta and k: a model without them is refused by every
/// command that takes --metal, with one message naming the model as given.
#[test]
fn a_metal_on_a_model_without_eta_and_k_is_refused_alike() {
    let dir = temp_dir("model-args-metal");
    let out = dir.join("x.png");
    let out = out.to_str().unwrap();
    for args in [
        vec!["eval", "--model", "flog", "--metal", "gold"],
        vec!["shader", "--model", "flog", "--metal", "gold"],
        vec![
            "render", "--model", "flog", "--metal", "gold", "--size", "16x16", "--out", out,
        ],
        vec![
            "compare",
            "--models",
            "flog",
            "--reference",
            "cook-torrance",
            "--metal",
            "gold",
            "--size",
            "16x16",
            "--out",
            out,
        ],
    ] {
        let r = fastbrdf(&args, "cos\n1\n");
        assert_eq!(r.status.code(), Some(2), "{args:?}: {}", stderr(&r));
        assert!(
            stderr(&r).contains("--metal gold: model 'flog' has no conductor Fresnel term"),
            "{args:?}: {}",
            stderr(&r)
        );
        assert!(r.stdout.is_empty());
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Each option is one declaration: its help text is the same in every command that does not
/// reword it (render, compare, errors, fit-measured and plot word theirs for what they do).
#[test]
fn the_shared_options_read_alike_in_every_command() {
    let param = "A parameter, NAME=VALUE; repeat for several";
    let material = "whose published fit supplies the model's n, alpha and f0";
    for cmd in [
        vec!["eval"],
        vec!["sample"],
        vec!["chi2"],
        vec!["albedo"],
        vec!["shader"],
        vec!["conform"],
    ] {
        let mut args = cmd.clone();
        args.push("--help");
        let r = fastbrdf(&args, "");
        assert!(r.status.success());
        let help = stdout(&r).split_whitespace().collect::<Vec<_>>().join(" ");
        assert!(help.contains("--param <NAME=VALUE>"), "{cmd:?}");
        assert!(help.contains(param), "{cmd:?}: {help}");
        if matches!(cmd[0], "eval" | "albedo" | "shader" | "conform") {
            assert!(help.contains("--material <NAME>"), "{cmd:?}");
            assert!(help.contains(material), "{cmd:?}");
        } else {
            assert!(!help.contains("--material"), "{cmd:?} gained --material");
            assert!(!help.contains("--metal"), "{cmd:?} gained --metal");
        }
    }
}

/// A user's model echoed in a message keeps both ends of its long path (the file's name is
/// the part that tells the user which file), shortened in the middle to one line.
#[test]
fn a_long_user_model_path_keeps_its_file_name_in_messages() {
    let dir = temp_dir("model-args-long-path");
    let deep = (0..3).fold(dir.to_path_buf(), |p, _| p.join("d".repeat(100)));
    std::fs::create_dir_all(&deep).unwrap();
    let file = deep.join("mine.brdf");
    let blinn = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../gpu/tests/data/brdf-explorer/blinn.brdf"
    );
    std::fs::copy(blinn, &file).unwrap();
    let long = format!("file:{}", file.display());
    let cases: [&[&str]; 2] = [
        &[
            "render", "--model", &long, "--metal", "gold", "--size", "16x16", "--out", "x.png",
        ],
        &["bench", "--gpu", "--model", &long, "--model", &long],
    ];
    for args in cases {
        let r = fastbrdf(args, "");
        assert_eq!(r.status.code(), Some(2), "{args:?}");
        assert!(stdout(&r).is_empty(), "{args:?}");
        let e = stderr(&r);
        assert!(
            e.contains("/mine.brdf") && e.contains("file:/"),
            "{args:?}: {e}"
        );
        assert!(e.contains("bytes)..."), "{args:?}: {e}");
        assert!(e.len() < 300, "{args:?}: {e}");
    }
}

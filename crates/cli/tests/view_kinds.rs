//! `fastbrdf view` and the terms it does not shade (shadowing, Fresnel, split-sum env): every
//! registry model listed, `/api/plots`' `terms` with the numbers of `fastbrdf errors`, the
//! pictures and the albedo skipping them, and the page's Terms section in headless Chromium.

mod common;
mod explorer;
mod served;

use common::{fastbrdf, stderr};
use explorer::{browser, cdp, cli_errors, get_json, ok_json};
use serde_json::Value;
use served::serve;
use std::time::Duration;

/// The term of `/api/plots`' `terms` with id `id`.
fn term<'a>(v: &'a Value, id: &str) -> &'a Value {
    v["terms"]
        .as_array()
        .unwrap()
        .iter()
        .find(|t| t["id"] == id)
        .unwrap_or_else(|| panic!("{id} not in terms: {}", v["terms"]))
}

/// The term's errors equal the CLI's row exactly (`max_rel` null: infinite).
fn same_numbers(t: &Value, c: &Value) {
    let e = &t["error"];
    for k in [
        "max_abs",
        "max_abs_at",
        "max_rel",
        "max_rel_at",
        "rms",
        "samples",
    ] {
        assert_eq!(e[k], c[k], "{} {k}: {e} against the CLI's {c}", t["id"]);
    }
    assert!(e["max_abs"].as_f64().unwrap() > 0.0, "{e}");
}

#[test]
fn models_lists_every_registry_model_with_its_kind() {
    let s = serve(&[]);
    let o = fastbrdf(&["models", "--json"], "");
    assert!(o.status.success(), "{}", stderr(&o));
    let cli: Value = serde_json::from_slice(&o.stdout).unwrap();
    let cli = cli["models"].as_array().unwrap();
    let api = ok_json(&s.addr, "/api/models");
    let api = api["models"].as_array().unwrap();
    let ids = |l: &[Value]| -> Vec<(String, String)> {
        l.iter()
            .map(|m| (m["id"].to_string(), m["kind"].to_string()))
            .collect()
    };
    assert_eq!(ids(api), ids(cli));
    for kind in ["shadowing", "fresnel", "env"] {
        assert!(api.iter().any(|m| m["kind"] == kind), "no {kind} listed");
    }
    // A split-sum term's inputs are sliders too; a parameter keeps the CLI's fields.
    for m in api {
        let c = cli.iter().find(|c| c["id"] == m["id"]).unwrap();
        let names = |l: &Value| -> Vec<String> {
            l.as_array()
                .unwrap()
                .iter()
                .filter(|p| p["input"] != true)
                .map(|p| p["name"].to_string())
                .collect()
        };
        assert_eq!(names(&m["params"]), names(&c["params"]), "{}", m["id"]);
        let inputs: Vec<&Value> = m["params"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|p| p["input"] == true)
            .map(|p| &p["name"])
            .collect();
        if m["kind"] == "env" {
            assert_eq!(inputs, ["alpha", "cos_v"], "{}", m["id"]);
        } else {
            assert!(inputs.is_empty(), "{}", m["id"]);
        }
    }
}

#[test]
fn terms_numbers_equal_fastbrdf_errors() {
    let s = serve(&[]);
    for alpha in ["0.4", "0.15"] {
        let v = ok_json(
            &s.addr,
            &format!(
                "/api/plots?models=smith-ggx-correlated-fast,fresnel-schlick-sg,env-brdf-approx&alpha={alpha}&f0=0.1&theta=40"
            ),
        );
        assert!(
            v["models"].as_array().unwrap().is_empty(),
            "{}",
            v["models"]
        );
        assert_eq!(v["terms"].as_array().unwrap().len(), 3);
        // The documented bound's reference, at the slider's alpha.
        let g = term(&v, "smith-ggx-correlated-fast");
        assert_eq!(g["reference"], "smith-ggx-correlated");
        assert_eq!(g["reference_rule"], "bound");
        same_numbers(
            g,
            &cli_errors(
                "smith-ggx-correlated-fast",
                "smith-ggx-correlated",
                "--m",
                alpha,
            ),
        );
        let env = term(&v, "env-brdf-approx");
        assert_eq!(env["reference"], "env-brdf");
        same_numbers(
            env,
            &cli_errors("env-brdf-approx", "env-brdf", "--m", alpha),
        );
        // `fastbrdf errors` has no flag for f0: the same library call it makes.
        let f = term(&v, "fresnel-schlick-sg");
        assert_eq!(f["reference"], "fresnel-schlick");
        let spec = fastbrdf_analysis::errors::Spec {
            model: "fresnel-schlick-sg".into(),
            reference: "fresnel-schlick".into(),
            param: "f0".into(),
            zone: fastbrdf::Zone::All,
        };
        let row = fastbrdf_analysis::errors::sweep(&spec, &[0.1], &|| {}).unwrap()[0];
        // Through the JSON text, as the API's numbers came (serde_json's parser may round
        // the last bit; the shortest text of two equal numbers is the same).
        let row: Value = serde_json::from_str(&serde_json::to_string(&row).unwrap()).unwrap();
        same_numbers(f, &row);
        assert_eq!(f["error"]["value"], 0.1);

        // The curves: G1 and G2 against theta_v, each with its reference; G1(0) = 1.
        let p = &g["plots"][0];
        assert_eq!(p["x"][0], 0.0);
        let g1 = &p["curves"][0];
        assert_eq!(g1["model"][0], 1.0);
        assert_eq!(
            g1["model"].as_array().unwrap().len(),
            p["x"].as_array().unwrap().len()
        );
        assert_ne!(g1["model"], g1["reference"]);
        assert!(p["curves"][1]["label"].as_str().unwrap().contains("40"));
        let names: Vec<&Value> = env["plots"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| &p["name"])
            .collect();
        assert_eq!(names, ["env-nov", "env-alpha"]);
    }

    // The chosen reference, when it is of the same kind, replaces the bound's.
    let v = ok_json(
        &s.addr,
        "/api/plots?models=schlick-ggx,flog&ref=smith-ggx-correlated&alpha=0.3&n=50",
    );
    let ids: Vec<&Value> = v["models"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| &m["id"])
        .collect();
    assert_eq!(ids, ["flog"], "the shaded models alone");
    let t = term(&v, "schlick-ggx");
    assert_eq!(t["reference_rule"], "chosen");
    same_numbers(
        t,
        &cli_errors("schlick-ggx", "smith-ggx-correlated", "--m", "0.3"),
    );
    let r = term(&v, "smith-ggx-correlated");
    assert!(r["error"].is_null() && r["why"].is_string(), "{r}");

    // Bad values of a term are refused, naming them.
    for (q, msg) in [
        ("models=fresnel-schlick&bogus=1", "no parameter 'bogus'"),
        ("models=env-brdf&cos_v=3", "cos_v 3"),
        ("models=fresnel-schlick&f0=2", "f0 = 2"),
    ] {
        let (status, e) = get_json(&s.addr, &format!("/api/plots?{q}"));
        assert_eq!(status, 400, "{q}: {e}");
        assert!(e["error"].as_str().unwrap().contains(msg), "{q}: {e}");
    }
}

#[test]
fn render_albedo_and_panes_skip_terms() {
    let s = serve(&[]);
    let q = "models=flog,smith-ggx-correlated-fast&ref=pow&n=40&alpha=0.3";
    let r = ok_json(&s.addr, &format!("/api/render?{q}&size=32&flip=none"));
    let ids: Vec<&Value> = r["images"]
        .as_array()
        .unwrap()
        .iter()
        .map(|i| &i["id"])
        .collect();
    assert_eq!(ids, ["pow", "flog"]);
    let a = ok_json(&s.addr, &format!("/api/albedo?{q}&quick=1"));
    let ids: Vec<&Value> = a["models"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| &m["id"])
        .collect();
    assert_eq!(ids, ["pow", "flog"]);
    let p = ok_json(&s.addr, &format!("/api/panes?{q}"));
    let ids: Vec<&Value> = p["models"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| &m["id"])
        .collect();
    assert_eq!(ids, ["pow", "flog"], "the panes skip the terms too");
    // Terms alone, and a term as the reference: nothing to render or integrate, no error.
    for q in [
        "models=fresnel-schlick-sg,env-brdf-approx&f0=0.2",
        "models=flog&ref=smith-ggx&alpha=0.2",
    ] {
        let r = ok_json(&s.addr, &format!("/api/render?{q}&size=16&flip=none"));
        assert!(r["reference"].is_null(), "{q}: {}", r["reference"]);
        let a = ok_json(&s.addr, &format!("/api/albedo?{q}&quick=1"));
        ok_json(&s.addr, &format!("/api/panes?{q}"));
        let shaded = q.contains("flog");
        assert_eq!(
            r["images"].as_array().unwrap().len(),
            usize::from(shaded),
            "{q}"
        );
        assert_eq!(
            a["models"].as_array().unwrap().len(),
            usize::from(shaded),
            "{q}"
        );
    }
}

/// What the page shows: the Terms section, its canvases' coloured pixels and its table.
const TERMS: &str = r##"JSON.stringify({
  hidden: document.getElementById("terms").hidden,
  status: document.getElementById("status").className,
  canvases: [...document.querySelectorAll("#terms-plots canvas")].map(cv => {
    const d = cv.getContext("2d").getImageData(0, 0, cv.width, cv.height).data;
    let coloured = 0;
    for (let i = 0; i < d.length; i += 4) if (Math.max(d[i], d[i + 1], d[i + 2]) - Math.min(d[i], d[i + 1], d[i + 2]) > 80) coloured++;
    return cv.dataset.model + ":" + cv.dataset.plot + ":" + coloured;
  }),
  rows: Object.fromEntries([...document.querySelectorAll("#terms-numbers tr[data-model]")].map(r => [r.dataset.model,
    Object.fromEntries(["max-abs", "max-abs-at", "max-rel", "max-rel-at"].map(c => [c, r.querySelector("." + c).dataset.value]))])),
  sliders: ["alpha", "f0", "cos_v"].map(n => !!document.getElementById("text-" + n)),
  query: paramQuery().toString(),
})"##;

fn shown(b: &mut cdp::Browser, page: &str) -> Value {
    b.wait_for(
        page,
        "document.body.dataset.ready === '1'",
        Duration::from_secs(60),
    )
    .unwrap();
    serde_json::from_str(b.eval(page, TERMS).unwrap().as_str().unwrap()).unwrap()
}

/// A number the page shows (`data-value`), read by the parser that read the API's and the
/// CLI's JSON (serde_json's may round the last bit: the same text gives the same number).
fn number(text: &Value) -> f64 {
    serde_json::from_str::<f64>(text.as_str().unwrap()).unwrap()
}

/// The page's table equals `/api/plots` for the page's own query, and the CLI's numbers.
fn check_table(addr: &str, v: &Value, alpha: &str) {
    assert_eq!(v["status"], "", "the page shows an error");
    let api = ok_json(
        addr,
        &format!("/api/plots?{}", v["query"].as_str().unwrap()),
    );
    for t in api["terms"].as_array().unwrap() {
        let row = &v["rows"][t["id"].as_str().unwrap()];
        if t["error"].is_null() {
            assert_eq!(row["max-abs"], "", "{}", t["id"]);
            continue;
        }
        for (c, k) in [
            ("max-abs", "max_abs"),
            ("max-abs-at", "max_abs_at"),
            ("max-rel", "max_rel"),
            ("max-rel-at", "max_rel_at"),
        ] {
            match t["error"][k].as_f64() {
                Some(x) => assert_eq!(number(&row[c]), x, "{} {c}", t["id"]),
                // An infinite relative error: null in the JSON, "inf" on the page.
                None => assert_eq!(row[c], "inf", "{} {c}", t["id"]),
            }
        }
    }
    let c = cli_errors(
        "smith-ggx-correlated-fast",
        "smith-ggx-correlated",
        "--m",
        alpha,
    );
    let row = &v["rows"]["smith-ggx-correlated-fast"];
    assert_eq!(
        number(&row["max-abs"]),
        c["max_abs"].as_f64().unwrap(),
        "at alpha {alpha}"
    );
    assert_eq!(
        number(&row["max-rel"]),
        c["max_rel"].as_f64().unwrap(),
        "at alpha {alpha}"
    );
}

#[test]
fn page_terms_section_in_headless_chromium() {
    let Some(path) = browser() else { return };
    let s = serve(&[]);
    let mut b = cdp::Browser::start(&path).unwrap();
    let url = format!(
        "http://{}/#models=smith-ggx-correlated-fast,fresnel-schlick-sg,env-brdf-approx&ref=smith-ggx-correlated&alpha=0.3",
        s.addr
    );
    let page = b.open(&url, 1400, 1050).unwrap();
    let v = shown(&mut b, &page);
    assert_eq!(v["hidden"], false);
    assert_eq!(v["sliders"], serde_json::json!([true, true, true]), "{v}");
    // One canvas per plot: shadowing 1, Fresnel 1, split-sum 2 (the chosen reference is drawn
    // dashed in its term's plot); each with its curves drawn.
    let canvases = v["canvases"].as_array().unwrap();
    assert_eq!(canvases.len(), 4, "{v}");
    for c in canvases {
        let n: u32 = c
            .as_str()
            .unwrap()
            .rsplit(':')
            .next()
            .unwrap()
            .parse()
            .unwrap();
        assert!(n > 200, "blank term plot {c}");
    }
    assert_eq!(v["rows"].as_object().unwrap().len(), 4, "{v}");
    check_table(&s.addr, &v, "0.3");

    // The numbers follow the alpha slider's value.
    b.eval(&page, "(() => { const t = document.getElementById('text-alpha'); t.value = '0.6'; t.dispatchEvent(new Event('change')); })()")
        .unwrap();
    let moved = shown(&mut b, &page);
    assert_ne!(moved["rows"], v["rows"]);
    assert!(moved["query"].as_str().unwrap().contains("alpha=0.6"));
    check_table(&s.addr, &moved, "0.6");

    // Without a term the section is hidden.
    b.eval(&page, "location.hash = '#models=flog&ref=pow&n=20'")
        .unwrap();
    b.wait_for(
        &page,
        "document.getElementById('terms').hidden === true",
        Duration::from_secs(30),
    )
    .unwrap();
}

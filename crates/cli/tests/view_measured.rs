//! `fastbrdf view --measured FILE`: a MERL file as the reference, over the API (equal to
//! `fastbrdf errors --measured` and `compare --measured`) and in headless Chromium (skipped
//! with a message without Chromium unless CI is set), a bad file refused, and hostile names
//! shown as text.

mod common;
mod explorer;
mod served;

use common::{fastbrdf, stderr, temp_dir};
use explorer::{browser, cdp, get_json, ok_json};
use serde_json::Value;
use served::serve;
use std::time::Duration;

/// The synthetic MERL file shared by the tests that need it, and how many hold it.
static MERL: std::sync::Mutex<(usize, Option<std::path::PathBuf>)> =
    std::sync::Mutex::new((0, None));

/// A hold on the synthetic MERL file: the folder is removed when the last hold goes (a file
/// is 35 MB; a later test writes it again).
struct MerlFile(std::path::PathBuf);

impl Drop for MerlFile {
    fn drop(&mut self) {
        let mut m = MERL.lock().unwrap_or_else(|e| e.into_inner());
        m.0 -= 1;
        if m.0 == 0
            && let Some(p) = m.1.take()
        {
            let _ = std::fs::remove_dir_all(p.parent().unwrap());
        }
    }
}

/// One synthetic MERL file for the tests running at once (35 MB, written once):
/// `kd / pi + ks * ward(alpha 0.25)` at the bin centres, from the registry's Ward.
fn merl_file() -> MerlFile {
    use fastbrdf::measured::{from_half_diff, write_merl};
    let mut m = MERL.lock().unwrap_or_else(|e| e.into_inner());
    m.0 += 1;
    if m.1.is_none() {
        // Removed by the last hold (MerlFile), not by the guard.
        let dir = temp_dir("view-measured").keep();
        let path = dir.join("ward-view.binary");
        let fastbrdf::Model::Brdf(b) = fastbrdf::ModelSpec::parse("ward", &[("alpha", "0.25")])
            .and_then(|s| s.model::<f64>())
            .unwrap()
        else {
            panic!("ward is a BRDF")
        };
        let (kd, ks) = ([0.3, 0.1, 0.05], [0.05, 0.04, 0.03]);
        write_merl(&path, |th, td, pd| {
            let (wi, wo) = from_half_diff(th, td, pd);
            if wi[2] <= 0.0 || wo[2] <= 0.0 {
                return [-1.0; 3];
            }
            let s = b.eval(wi, wo);
            [0, 1, 2].map(|c| kd[c] / std::f64::consts::PI + ks[c] * s)
        })
        .unwrap();
        m.1 = Some(path);
    }
    MerlFile(m.1.clone().unwrap())
}

/// `fastbrdf errors --measured FILE --model ID [--m M] --json`: rows[0].
fn cli_measured_errors(file: &str, model: &str, m: Option<&str>) -> Value {
    let mut args = vec!["errors", "--model", model, "--measured", file, "--json"];
    if let Some(m) = m {
        args.extend(["--m", m]);
    }
    let o = fastbrdf(&args, "");
    assert!(o.status.success(), "{}", stderr(&o));
    let v: Value = serde_json::from_slice(&o.stdout).unwrap();
    v["rows"][0].clone()
}

#[test]
fn measured_reference_equals_errors_and_compare_measured() {
    let file = merl_file();
    let fs = file.0.to_str().unwrap();
    let s = serve(&["--measured", fs]);
    let info = ok_json(&s.addr, "/api/models");
    let name = info["measured"]["name"].as_str().unwrap().to_string();
    assert_eq!(name, "ward-view.binary", "named after the file");
    assert_eq!(info["measured"]["file"], fs);

    // Plots: the measured data first (luminance), the models with the residuals of
    // `fastbrdf errors --measured` at the same parameters.
    let v = ok_json(
        &s.addr,
        &format!("/api/plots?models=ward,blinn-phong&ref={name}&alpha=0.3&theta=30"),
    );
    assert_eq!(v["reference"], name.as_str());
    assert_eq!(v["reference_kind"], "measured");
    let ms = v["models"].as_array().unwrap();
    let ids: Vec<&str> = ms.iter().map(|m| m["id"].as_str().unwrap()).collect();
    assert_eq!(ids, [name.as_str(), "ward", "blinn-phong"]);
    let r = &ms[0];
    assert_eq!(r["kind"], "measured");
    assert_eq!(r["channel"], "luminance");
    assert_eq!(
        r["polar"].as_array().unwrap().len(),
        v["polar_theta_deg"].as_array().unwrap().len()
    );
    assert_eq!(
        r["lobe"].as_array().unwrap().len(),
        v["curve_theta_deg"].as_array().unwrap().len()
    );
    let side = v["slice_size"].as_u64().unwrap() as usize;
    assert_eq!(r["slice"].as_array().unwrap().len(), side * side);
    // The polar plot of a glossy material peaks near the mirror direction.
    let polar: Vec<f64> = r["polar"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    let peak = (0..polar.len())
        .max_by(|&a, &b| polar[a].total_cmp(&polar[b]))
        .unwrap();
    let at = v["polar_theta_deg"][peak].as_f64().unwrap();
    assert!((at - 30.0).abs() <= 5.0, "measured polar peaks at {at}");
    for (m, alpha) in [(&ms[1], Some("0.3")), (&ms[2], None)] {
        assert!(m["error"].is_null(), "no error curve against measured data");
        let c = cli_measured_errors(fs, m["id"].as_str().unwrap(), alpha);
        assert!(m["measured"]["ngan_l2"].is_f64(), "{}", m["measured"]);
        for f in ["ngan_l2", "low_log", "max", "rho_d", "rho_s"] {
            assert_eq!(m["measured"][f], c[f], "{}: {f}", m["id"]);
        }
    }
    // The data is Ward at alpha 0.25: Ward's residual there is far below blinn-phong's.
    let at_truth = ok_json(
        &s.addr,
        &format!("/api/errors?model=ward&ref={name}&alpha=0.25"),
    );
    let c = cli_measured_errors(fs, "ward", Some("0.25"));
    assert_eq!(at_truth["ngan_l2"], c["ngan_l2"]);
    assert_eq!(at_truth["model"], "ward");
    assert!(
        at_truth["ngan_l2"].as_f64().unwrap() * 10.0
            < ms[2]["measured"]["ngan_l2"].as_f64().unwrap(),
        "{at_truth} vs {}",
        ms[2]["measured"]
    );

    // Albedo: omitted for the measured data, with the reason.
    let a = ok_json(
        &s.addr,
        &format!("/api/albedo?models=ward&ref={name}&alpha=0.3&quick=1"),
    );
    assert_eq!(a["models"][0]["id"], name.as_str());
    assert!(a["models"][0]["albedo"].is_null());
    assert!(a["models"][0]["why"].as_str().unwrap().contains("measured"));
    assert!(a["models"][1]["albedo"].is_object());

    // Pictures: the measured render beside the model, metrics as `compare --measured`.
    let v = ok_json(
        &s.addr,
        &format!("/api/render?models=ward&ref={name}&alpha=0.3&size=64&spp=1"),
    );
    assert_eq!(v["reference"], name.as_str());
    assert_eq!(v["images"][0]["id"], name.as_str());
    assert_eq!(v["diffs"].as_array().unwrap().len(), 1);
    let dir = temp_dir("view-compare-measured");
    let out = dir.join("c.png");
    let o = fastbrdf(
        &[
            "compare",
            "--models",
            "ward",
            "--measured",
            fs,
            "--param",
            "alpha=0.3",
            "--size",
            "64x64",
            "--spp",
            "1",
            "--json",
            "--out",
            out.to_str().unwrap(),
        ],
        "",
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let c: Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(
        v["metrics"][0]["flip"].as_f64().unwrap() > 0.0,
        "{}",
        v["metrics"]
    );
    for f in ["rmse", "psnr", "flip"] {
        assert_eq!(v["metrics"][0][f], c["metrics"][0][f], "{f}");
    }
    let _ = std::fs::remove_dir_all(dir);
    // A model reference still works beside it, and an unknown reference is the registry's.
    ok_json(
        &s.addr,
        "/api/plots?models=ward&ref=cook-torrance&alpha=0.3",
    );
    let (status, e) = get_json(&s.addr, "/api/plots?models=ward&ref=nonesuch.binary");
    assert_eq!(status, 400, "{e}");
}

#[test]
fn bad_measured_file_is_exit_2_naming_it() {
    let dir = temp_dir("view-bad-measured");
    let short = dir.join("short.binary");
    std::fs::write(&short, [0u8; 100]).unwrap();
    let missing = dir.join("missing.binary");
    for f in [&short, &missing] {
        let o = fastbrdf(
            &["view", "--port", "0", "--measured", f.to_str().unwrap()],
            "",
        );
        assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
        assert!(o.stdout.is_empty());
        assert!(stderr(&o).contains(f.to_str().unwrap()), "{}", stderr(&o));
    }
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn page_chooses_the_measured_reference_in_headless_chromium() {
    let Some(path) = browser() else { return };
    let file = merl_file();
    let fs = file.0.to_str().unwrap();
    let s = serve(&["--measured", fs]);
    let mut b = cdp::Browser::start(&path).unwrap();
    let page = b
        .open(
            &format!("http://{}/#models=ward&alpha=0.3&theta=30", s.addr),
            1400,
            1050,
        )
        .unwrap();
    let ready = "document.body.dataset.ready === '1'";
    b.wait_for(&page, ready, Duration::from_secs(120)).unwrap();
    // Choose the measured file as the reference with its radio button.
    b.eval(&page, "document.getElementById('ref-measured').click()")
        .unwrap();
    b.wait_for(
        &page,
        "document.body.dataset.ready === '1' && location.hash.includes('ref=ward-view.binary') && document.querySelector('#numbers .ngan-l2') !== null && document.querySelectorAll('img.diff').length === 1",
        Duration::from_secs(120),
    )
    .unwrap();
    let v: Value = serde_json::from_str(
        b.eval(
            &page,
            r##"JSON.stringify({
              status: document.getElementById("status").className,
              status_text: document.getElementById("status").textContent,
              ngan: document.querySelector("#numbers tr[data-model=ward] .ngan-l2").dataset.value,
              images: [...document.querySelectorAll("img.render")].map(i => i.dataset.model),
              verdicts: document.getElementById("verdicts").textContent,
            })"##,
        )
        .unwrap()
        .as_str()
        .unwrap(),
    )
    .unwrap();
    assert_eq!(
        v["status"], "",
        "the page shows an error: {}",
        v["status_text"]
    );
    let c = cli_measured_errors(fs, "ward", Some("0.3"));
    assert_eq!(
        v["ngan"].as_str().unwrap().parse::<f64>().unwrap(),
        c["ngan_l2"].as_f64().unwrap()
    );
    assert_eq!(
        v["images"],
        serde_json::json!(["ward-view.binary", "ward"]),
        "{v}"
    );
    assert!(
        v["verdicts"]
            .as_str()
            .unwrap()
            .contains("not computed for measured data"),
        "{v}"
    );
}

/// Model ids from the link and the `--measured` file's name reach the page as text: markup in
/// them shows literally and runs nothing (issue 27: they went into innerHTML).
#[test]
fn hostile_names_show_as_text_in_headless_chromium() {
    let Some(path) = browser() else { return };
    let file = merl_file();
    let dir = temp_dir("view-hostile-name");
    let name = "<img src=x onerror=window.__xss=2>.binary";
    let link = dir.join(name);
    std::os::unix::fs::symlink(&file.0, &link).unwrap();
    let s = serve(&["--measured", link.to_str().unwrap()]);
    let mut b = cdp::Browser::start(&path).unwrap();
    let bad_id = "<img src=x onerror=window.__xss=1>";
    let page = b
        .open(
            &format!(
                "http://{}/#models=flog,{}&ref=pow&n=30",
                s.addr,
                bad_id.replace(' ', "%20")
            ),
            1400,
            1050,
        )
        .unwrap();
    // The page asks the server about the unknown model (a 400 shown as an error) and draws
    // the controls; give an injected image time to fail to load.
    b.wait_for(
        &page,
        "document.body.dataset.ready === '1'",
        Duration::from_secs(120),
    )
    .unwrap();
    std::thread::sleep(Duration::from_millis(1000));
    let v: Value = serde_json::from_str(
        b.eval(
            &page,
            r##"JSON.stringify({
              xss: window.__xss === undefined ? null : window.__xss,
              injected: document.querySelectorAll("img[src=x]").length,
              models: document.getElementById("models").textContent,
            })"##,
        )
        .unwrap()
        .as_str()
        .unwrap(),
    )
    .unwrap();
    drop(b);
    let _ = std::fs::remove_dir_all(dir);
    assert_eq!(v["xss"], Value::Null, "injected script ran: {v}");
    assert_eq!(v["injected"], 0, "{v}");
    let shown = v["models"].as_str().unwrap();
    assert!(shown.contains(bad_id), "the id is not shown as text: {v}");
    assert!(
        shown.contains(name),
        "the file name is not shown as text: {v}"
    );
}

//! `fastbrdf view`'s BRDF Explorer panes (`/api/panes`, issue 32): the 3D lobe, the theta_h,
//! theta_d and theta_v plots and the theta_h x theta_d slice equal an independent evaluation
//! (`fastbrdf eval` for a registry BRDF, the library's shaded spec for a lobe, a direct GPU
//! evaluation for a user's model) at the directions the test builds itself and checks with
//! Rusinkiewicz's forward conversion; bad inputs are 400 naming the parameter; and in
//! headless Chromium a drag on the lobe moves the incident direction and redraws the panes.
//! The GPU test skips without a GPU, and the page test without Chromium, unless CI is set.

mod common;
mod explorer;
mod served;

use common::{fastbrdf, gpu_data, have_gpu, stderr};
use explorer::{browser, cdp, get_json, ok_json};
use fastbrdf::user::UserBrdf;
use serde_json::{Value, json};
use served::serve;
use std::time::Duration;

type Pair = ([f64; 3], [f64; 3]);

/// The angles every query here asks for, degrees.
const TI: f64 = 40.0;
const PI_: f64 = 30.0;
const PH: f64 = 20.0;
const PD: f64 = 70.0;
const PV: f64 = 200.0;
const TH: f64 = 25.0;
const TD: f64 = 35.0;
const RES: usize = 8;
const SIDE: usize = 8;

fn angles() -> String {
    format!(
        "theta_i={TI}&phi_i={PI_}&phi_h={PH}&phi_d={PD}&phi_v={PV}&theta_h={TH}&theta_d={TD}&res={RES}&slice={SIDE}"
    )
}

fn dir(theta_deg: f64, phi_deg: f64) -> [f64; 3] {
    let (t, p) = (theta_deg.to_radians(), phi_deg.to_radians());
    [t.sin() * p.cos(), t.sin() * p.sin(), t.cos()]
}

fn rot_z(v: [f64; 3], a: f64) -> [f64; 3] {
    let (s, c) = a.sin_cos();
    [c * v[0] - s * v[1], s * v[0] + c * v[1], v[2]]
}

fn rot_y(v: [f64; 3], a: f64) -> [f64; 3] {
    let (s, c) = a.sin_cos();
    [c * v[0] + s * v[2], v[1], -s * v[0] + c * v[2]]
}

/// Rusinkiewicz's forward conversion (as MERL's `std_coords_to_half_diff_coords`): (theta_h,
/// phi_h, theta_d, phi_d) in degrees of a pair.
fn half_diff(wi: [f64; 3], wo: [f64; 3]) -> [f64; 4] {
    let h: Vec<f64> = (0..3).map(|k| wi[k] + wo[k]).collect();
    let n = h.iter().map(|x| x * x).sum::<f64>().sqrt();
    let h = [h[0] / n, h[1] / n, h[2] / n];
    let (th, ph) = (h[2].clamp(-1.0, 1.0).acos(), h[1].atan2(h[0]));
    let d = rot_y(rot_z(wi, -ph), -th);
    let (td, pd) = (d[2].clamp(-1.0, 1.0).acos(), d[1].atan2(d[0]));
    [th, ph, td, pd].map(|a| a.to_degrees())
}

/// The pair at (theta_h, phi_h, theta_d, phi_d) degrees, built here (d and its mirror about
/// the half vector, turned by theta_h about y, then phi_h about z) and checked by
/// [`half_diff`].
fn pair_at(th: f64, ph: f64, td: f64, pd: f64) -> Pair {
    let d = dir(td, pd);
    let turn = |v: [f64; 3]| rot_z(rot_y(v, th.to_radians()), ph.to_radians());
    let p = (turn(d), turn([-d[0], -d[1], d[2]]));
    let got = half_diff(p.0, p.1);
    let same = |a: f64, b: f64| ((a - b + 540.0).rem_euclid(360.0) - 180.0).abs() < 1e-7;
    assert!(
        same(got[0], th) && same(got[2], td),
        "{got:?} for {th} {td}"
    );
    // phi_h and phi_d are defined where theta_h and theta_d are not 0.
    assert!(th < 1e-9 || same(got[1], ph), "{got:?} for phi_h {ph}");
    assert!(
        td < 1e-9 || th < 1e-9 || same(got[3], pd),
        "{got:?} for phi_d {pd}"
    );
    p
}

fn nums(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap_or_else(|| panic!("not an array: {v}"))
        .iter()
        .map(|x| x.as_f64().unwrap_or_else(|| panic!("not a number: {x}")))
        .collect()
}

/// The points each check looks at: (pane, index into its array, the pair, the factor the
/// pane multiplies f by: cos theta_o for the lobe).
fn sample_points(d: &Value) -> Vec<(&'static str, usize, Pair, f64)> {
    let mut out = vec![];
    let (lt, lp) = (nums(&d["lobe_theta_deg"]), nums(&d["lobe_phi_deg"]));
    assert_eq!((lt.len(), lp.len()), (RES, 2 * RES));
    let wi = dir(TI, PI_);
    for (i, j) in [(0, 0), (2, 3), (4, 9), (6, 15), (RES - 1, 5)] {
        let wo = dir(lt[i], lp[j]);
        out.push(("lobe", i * 2 * RES + j, (wi, wo), wo[2]));
    }
    let ct = nums(&d["curve_theta_deg"]);
    for k in [0, ct.len() / 5, ct.len() / 2, ct.len() - 1] {
        out.push(("theta_h", k, pair_at(ct[k], PH, TD, PD), 1.0));
        out.push(("theta_d", k, pair_at(TH, PH, ct[k], PD), 1.0));
    }
    let tv = nums(&d["theta_v_deg"]);
    for k in [10, tv.len() / 3, tv.len() / 2, tv.len() - 40] {
        let t = tv[k].to_radians();
        let p = PV.to_radians();
        out.push((
            "theta_v",
            k,
            (wi, [t.sin() * p.cos(), t.sin() * p.sin(), t.cos()]),
            1.0,
        ));
    }
    let st = nums(&d["slice_theta_deg"]);
    assert_eq!(st.len(), SIDE);
    for (jd, jh) in [(0, 0), (1, 5), (3, 2), (6, 1), (SIDE - 1, SIDE - 1)] {
        out.push((
            "slice",
            jd * SIDE + jh,
            pair_at(st[jh], PH, st[jd], PD),
            1.0,
        ));
    }
    out
}

/// Checks model `m`'s panes against `f` at the sample points: equal (relative `tol`) above
/// the horizon, null below it; every array the size the grids give.
fn check(m: &Value, d: &Value, tol: f64, f: &dyn Fn(&[Pair]) -> Vec<f64>) {
    let pts = sample_points(d);
    // Above the horizon (as `fastbrdf eval` takes them), or below it.
    type Point = (&'static str, usize, Pair, f64);
    let (above, below): (Vec<&Point>, Vec<&Point>) = pts
        .iter()
        .filter(|p| p.2.0[2].min(p.2.1[2]).abs() > 1e-6)
        .partition(|p| p.2.0[2] > 0.0 && p.2.1[2] > 0.0);
    let pairs: Vec<Pair> = above.iter().map(|p| p.2).collect();
    let want = f(&pairs);
    assert_eq!(want.len(), pairs.len());
    for ((pane, k, _, factor), w) in above.iter().zip(&want) {
        let got = &m[pane][k];
        let g = got
            .as_f64()
            .unwrap_or_else(|| panic!("{} {pane}[{k}] is {got}", m["id"]));
        let w = w * factor;
        assert!(
            (g - w).abs() <= tol * w.abs().max(1e-12),
            "{} {pane}[{k}]: {g} vs {w}",
            m["id"]
        );
    }
    for (pane, k, _, _) in &below {
        let got = &m[pane][k];
        assert!(
            got.is_null(),
            "{} {pane}[{k}] below the horizon: {got}",
            m["id"]
        );
    }
    let compared = above.len();
    assert!(!below.is_empty(), "no point below the horizon checked");
    assert!(compared >= 15, "{compared} points compared");
    let len = |k: &str| m[k].as_array().unwrap().len();
    assert_eq!(len("lobe"), RES * 2 * RES);
    assert_eq!(len("slice"), SIDE * SIDE);
    assert_eq!(
        len("theta_h"),
        d["curve_theta_deg"].as_array().unwrap().len()
    );
    assert_eq!(len("theta_v"), d["theta_v_deg"].as_array().unwrap().len());
    // phi_d = 70 degrees: the large theta_h of the theta_h plot put wi below the horizon.
    assert!(m["theta_h"].as_array().unwrap().iter().any(Value::is_null));
}

/// `fastbrdf eval --precision f64` of `model` at `pairs`.
fn cli_eval(model: &str, params: &[&str], pairs: &[Pair]) -> Vec<f64> {
    let mut csv = String::from("wi_x,wi_y,wi_z,wo_x,wo_y,wo_z\n");
    for (a, b) in pairs {
        csv += &format!("{},{},{},{},{},{}\n", a[0], a[1], a[2], b[0], b[1], b[2]);
    }
    let mut args = vec!["eval", "--model", model, "--precision", "f64"];
    for p in params {
        args.extend(["--param", p]);
    }
    let o = fastbrdf(&args, &csv);
    assert!(o.status.success(), "{}", stderr(&o));
    String::from_utf8(o.stdout)
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| l.rsplit(',').next().unwrap().parse().unwrap())
        .collect()
}

fn model<'a>(d: &'a Value, id: &str) -> &'a Value {
    d["models"]
        .as_array()
        .unwrap()
        .iter()
        .find(|m| m["id"] == id)
        .unwrap_or_else(|| panic!("no {id}: {}", d["models"]))
}

#[test]
fn registry_panes_equal_an_independent_evaluation_and_bad_inputs_are_named() {
    let s = serve(&[]);
    let d = ok_json(
        &s.addr,
        &format!(
            "/api/panes?models=cook-torrance,flog&ref=pow&alpha=0.3&n=20&{}",
            angles()
        ),
    );
    let ids: Vec<&str> = d["models"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["id"].as_str().unwrap())
        .collect();
    assert_eq!(ids, ["pow", "cook-torrance", "flog"]);
    assert_eq!(
        (d["theta_i_deg"].as_f64(), d["phi_d_deg"].as_f64()),
        (Some(TI), Some(PD))
    );
    let ct = model(&d, "cook-torrance");
    assert_eq!(ct["kind"], "brdf");
    check(ct, &d, 1e-12, &|p| {
        cli_eval("cook-torrance", &["alpha=0.3"], p)
    });
    // A lobe is shown as the BRDF the explorer shades it as.
    let flog = model(&d, "flog");
    assert_eq!(flog["kind"], "lobe");
    let spec = fastbrdf::ModelSpec::parse("flog", &[("n", "20")])
        .unwrap()
        .shaded()
        .unwrap();
    let b = fastbrdf::user::Builtin::new(&spec, fastbrdf::sample::Strategy::Auto).unwrap();
    check(flog, &d, 1e-12, &|p| {
        let (wi, wo): (Vec<_>, Vec<_>) = p.iter().copied().unzip();
        let mut out = vec![0.0; p.len()];
        b.eval(&wi, &wo, &mut out).unwrap();
        out
    });
    // The lobe (f cos theta_o) peaks near the mirror direction of wi (theta 40, phi 210).
    let lobe: Vec<f64> = ct["lobe"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap_or(0.0))
        .collect();
    let top = (0..lobe.len())
        .max_by(|&a, &b| lobe[a].total_cmp(&lobe[b]))
        .unwrap();
    assert_eq!(ct["lobe_max"].as_f64().unwrap(), lobe[top]);
    let (lt, lp) = (nums(&d["lobe_theta_deg"]), nums(&d["lobe_phi_deg"]));
    let (t, p) = (lt[top / (2 * RES)], lp[top % (2 * RES)]);
    assert!(
        (t - TI).abs() <= 20.0 && (p - (PI_ + 180.0)).abs() <= 30.0,
        "peak at {t}, {p}"
    );

    // Bad inputs: 400 naming the parameter; the defaults and the page's `theta` otherwise.
    for (q, name) in [
        ("theta_i=90", "theta_i"),
        ("theta=95", "theta"),
        ("theta_d=-1", "theta_d"),
        ("theta_h=91", "theta_h"),
        ("phi_d=abc", "phi_d"),
        ("phi_v=400", "phi_v"),
        ("res=65", "res"),
        ("slice=1000", "slice"),
        ("bogus=1", "bogus"),
    ] {
        let (status, v) = get_json(&s.addr, &format!("/api/panes?models=flog&{q}"));
        assert_eq!(status, 400, "{q}: {v}");
        let e = v["error"].as_str().unwrap();
        assert!(e.contains(name), "{q}: {e}");
    }
    // A shadowing term is not a BRDF: named in `skipped`, not drawn.
    let d = ok_json(&s.addr, "/api/panes?models=flog,smith&alpha=0.2&theta=20");
    assert_eq!(d["models"].as_array().unwrap().len(), 1);
    assert_eq!(d["skipped"][0]["id"], "smith", "{}", d["skipped"]);
    let d = ok_json(&s.addr, "/api/panes?models=flog&theta=20");
    assert_eq!(d["theta_i_deg"], 20.0);
    assert_eq!(d["phi_v_deg"], 180.0);
    assert_eq!(d["models"][0]["lobe"].as_array().unwrap().len(), 32 * 64);
}

#[test]
fn a_user_model_panes_equal_its_direct_gpu_evaluation() {
    if !have_gpu() {
        return;
    }
    let (walter, ggx) = (
        gpu_data("brdf-explorer/walter.brdf"),
        gpu_data("user/ggx_sampled.wgsl"),
    );
    let s = serve(&[
        "--model",
        &format!("file:{walter}"),
        "--model",
        &format!("file:{ggx}"),
    ]);
    let d = ok_json(
        &s.addr,
        &format!(
            "/api/panes?models=walter.brdf,ggx_sampled.wgsl&alphaG=0.2&Ks=1&alpha=0.25&{}",
            angles()
        ),
    );
    let params = |v: &[(&str, &str)]| -> Vec<(String, String)> {
        v.iter()
            .map(|(k, x)| (k.to_string(), x.to_string()))
            .collect()
    };
    for (id, path, given) in [
        (
            "walter.brdf",
            &walter,
            params(&[("alphaG", "0.2"), ("Ks", "1")]),
        ),
        ("ggx_sampled.wgsl", &ggx, params(&[("alpha", "0.25")])),
    ] {
        let m = model(&d, id);
        assert_eq!(m["kind"], "user");
        let direct = fastbrdf_gpu::user::load(std::path::Path::new(path), &given).unwrap();
        let c = direct.channels();
        assert_eq!(m["channel"], if c == 3 { "luminance" } else { "value" });
        check(m, &d, 1e-9, &|p| {
            let (wi, wo): (Vec<_>, Vec<_>) = p.iter().copied().unzip();
            let mut out = vec![0.0; p.len() * c];
            direct.eval(&wi, &wo, &mut out).unwrap();
            out.chunks(c)
                .map(|v| {
                    if c == 3 {
                        0.2126 * v[0] + 0.7152 * v[1] + 0.0722 * v[2]
                    } else {
                        v[0]
                    }
                })
                .collect()
        });
    }
    // A value outside the file's range: 400 naming it.
    let (status, v) = get_json(
        &s.addr,
        "/api/panes?models=ggx_sampled.wgsl&alpha=7&theta_i=10",
    );
    assert_eq!(status, 400, "{v}");
    assert!(v["error"].as_str().unwrap().contains("alpha"), "{v}");
}

#[test]
fn a_measured_reference_panes_are_its_table() {
    use fastbrdf::measured::{MeasuredBrdf, from_half_diff, write_merl};
    let dir = common::temp_dir("view-panes-merl");
    let path = dir.join("ward-panes.binary");
    let fastbrdf::Model::Brdf(ward) = fastbrdf::ModelSpec::parse("ward", &[("alpha", "0.25")])
        .and_then(|s| s.model::<f64>())
        .unwrap()
    else {
        panic!("ward is a BRDF")
    };
    write_merl(&path, |th, td, pd| {
        let (wi, wo) = from_half_diff(th, td, pd);
        if wi[2] <= 0.0 || wo[2] <= 0.0 {
            return [-1.0; 3];
        }
        let s = ward.eval(wi, wo);
        [0.3, 0.1, 0.05].map(|kd| kd / std::f64::consts::PI + 0.05 * s)
    })
    .unwrap();
    let s = serve(&["--measured", path.to_str().unwrap()]);
    let d = ok_json(
        &s.addr,
        &format!(
            "/api/panes?models=ward&ref=ward-panes.binary&alpha=0.25&{}",
            angles()
        ),
    );
    assert_eq!(d["reference_kind"], "measured");
    let m = &d["models"][0];
    assert_eq!(
        (&m["id"], &m["kind"]),
        (&json!("ward-panes.binary"), &json!("measured"))
    );
    assert_eq!(m["channel"], "luminance");
    let table = MeasuredBrdf::read(&path).unwrap();
    check(m, &d, 1e-12, &|p| {
        p.iter()
            .map(|(a, b)| {
                let c = table.eval_rgb(*a, *b);
                0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
            })
            .collect()
    });
    drop(s);
    let _ = std::fs::remove_dir_all(dir);
}

const CANVASES: &str = r#"JSON.stringify(["panes-lobe", "panes-theta-h", "panes-theta-d", "panes-theta-v", "panes-slice"].map(id => document.getElementById(id).toDataURL()))"#;

fn ready(b: &mut cdp::Browser, s: &str) {
    b.wait_for(
        s,
        "document.body.dataset.ready === '1'",
        Duration::from_secs(60),
    )
    .unwrap();
    let status = b
        .eval(s, "document.getElementById('status').className + ': ' + document.getElementById('status').textContent")
        .unwrap();
    assert!(
        status.as_str().unwrap().starts_with(": "),
        "the page shows an error: {status}"
    );
}

fn canvases(b: &mut cdp::Browser, s: &str) -> Vec<String> {
    serde_json::from_str(b.eval(s, CANVASES).unwrap().as_str().unwrap()).unwrap()
}

#[test]
fn dragging_the_lobe_moves_the_incident_direction_in_headless_chromium() {
    let Some(path) = browser() else { return };
    let s = serve(&[]);
    let mut b = cdp::Browser::start(&path).unwrap();
    let page = b
        .open(
            &format!("http://{}/#models=cook-torrance&theta=30", s.addr),
            1400,
            1050,
        )
        .unwrap();
    ready(&mut b, &page);
    let rect: Value = b
        .eval(&page, "(() => { const c = document.getElementById('panes-lobe'); c.scrollIntoView(); const r = c.getBoundingClientRect(); return [r.left, r.top, r.width, r.height]; })()")
        .unwrap();
    let r = nums(&rect);
    let before = canvases(&mut b, &page);
    let theta = "document.getElementById('panes-lobe').dataset.thetaI + ',' + document.getElementById('panes-lobe').dataset.phiI + ',' + document.getElementById('theta-text').value + ',' + location.hash";
    let t0 = b.eval(&page, theta).unwrap();
    assert!(t0.as_str().unwrap().starts_with("30,0,30,"), "{t0}");

    // A left drag across the lobe: the incident direction follows the cursor.
    let at = |fx: f64, fy: f64| (r[0] + fx * r[2], r[1] + fy * r[3]);
    let (x0, y0) = at(0.7, 0.35);
    b.mouse(&page, "mousePressed", x0, y0).unwrap();
    for k in 1..=4 {
        let (x, y) = at(0.7 - 0.05 * f64::from(k), 0.35 + 0.03 * f64::from(k));
        b.mouse(&page, "mouseMoved", x, y).unwrap();
    }
    let (x1, y1) = at(0.5, 0.47);
    b.mouse(&page, "mouseReleased", x1, y1).unwrap();
    ready(&mut b, &page);
    let t1 = b.eval(&page, theta).unwrap();
    let parts: Vec<&str> = t1.as_str().unwrap().split(',').collect();
    assert_ne!(parts[0], "30", "theta_i did not change: {t1}");
    // The panes were drawn for the new direction, the page's theta follows, and so does the link.
    assert_eq!(parts[0], parts[2], "{t1}");
    assert!(
        parts[3..]
            .join(",")
            .contains(&format!("theta={}", parts[0])),
        "{t1}"
    );
    let after = canvases(&mut b, &page);
    for k in 0..before.len() {
        if k == 1 || k == 2 || k == 4 {
            continue; // theta_h, theta_d and the slice do not depend on wi
        }
        assert_ne!(before[k], after[k], "pane {k} not redrawn");
    }

    // A shift drag turns the view: the lobe is redrawn, theta_i stays.
    let shift = |b: &mut cdp::Browser, kind: &str, (x, y): (f64, f64)| {
        b.call(
            Some(&page),
            "Input.dispatchMouseEvent",
            json!({"type": kind, "x": x, "y": y, "button": "left", "buttons": 1, "modifiers": 8, "clickCount": 1}),
        )
        .unwrap();
    };
    shift(&mut b, "mousePressed", at(0.3, 0.8));
    shift(&mut b, "mouseMoved", at(0.45, 0.7));
    shift(&mut b, "mouseReleased", at(0.45, 0.7));
    ready(&mut b, &page);
    assert_eq!(b.eval(&page, theta).unwrap(), t1);
    assert_ne!(
        canvases(&mut b, &page)[0],
        after[0],
        "the view did not turn"
    );

    // The phi_d slider redraws the slice and the theta_h plot.
    b.eval(&page, "(() => { const s = document.getElementById('panes-phi_d'); s.value = 20; s.dispatchEvent(new Event('input')); })()")
        .unwrap();
    ready(&mut b, &page);
    let phi_d = canvases(&mut b, &page);
    assert_ne!(phi_d[4], after[4], "slice not redrawn");
    assert_ne!(phi_d[1], after[1], "theta_h plot not redrawn");
}

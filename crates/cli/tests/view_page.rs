//! `fastbrdf view`'s page end to end in headless Chromium (driven over the DevTools pipe by the
//! same client as `fastbrdf view --screenshot`): pictures, numbers equal to the CLI's, the
//! link, and Cook-Torrance's `g` menu. Without Chromium these tests are skipped with a
//! message, unless CI is set: then they fail.

mod common;
mod explorer;
mod served;

use explorer::{browser, cdp, cli_errors};
use serde_json::Value;
use served::serve;
use std::time::Duration;

const SNAPSHOT: &str = r##"JSON.stringify({
  plots: ["polar", "lobe", "err-abs", "err-rel", "albedo", "slice"].map(id => document.getElementById(id).toDataURL()),
  images: [...document.querySelectorAll("img.render")].map(i => i.dataset.model + ":" + i.src.length + ":" + i.src.slice(-64)),
  n: document.getElementById("text-n").value,
  rows: Object.fromEntries([...document.querySelectorAll("#numbers tr[data-model]")].map(r => [r.dataset.model,
     {abs: r.querySelector(".max-abs").dataset.value, abs_text: r.querySelector(".max-abs").textContent,
      rel: r.querySelector(".max-rel").dataset.value, psnr: r.querySelector(".psnr").textContent,
      flip: r.querySelector(".flip").dataset.value, flip_text: r.querySelector(".flip").textContent}])),
  status: document.getElementById("status").className,
  status_text: document.getElementById("status").textContent,
  render_info: document.getElementById("render-info").textContent,
  dropped: window.fastbrdfDropped || [],
  albedo_estimate: document.getElementById("albedo").dataset.estimate,
  verdicts: document.getElementById("verdicts").textContent,
  hash: location.hash,
})"##;

fn snapshot(b: &mut cdp::Browser, s: &str) -> Value {
    b.wait_for(
        s,
        "document.body.dataset.ready === '1'",
        Duration::from_secs(120),
    )
    .unwrap();
    let v: Value = serde_json::from_str(b.eval(s, SNAPSHOT).unwrap().as_str().unwrap()).unwrap();
    assert_eq!(
        v["status"], "",
        "the page shows an error: {}; dropped {}",
        v["status_text"], v["dropped"]
    );
    // Once everything has arrived, the precise albedo has replaced the quick estimate, and the
    // verdict shown is the precise computation's.
    assert_eq!(
        v["albedo_estimate"], "0",
        "the albedo estimate was not replaced"
    );
    assert!(
        v["verdicts"].as_str().unwrap().contains(" deg"),
        "{}",
        v["verdicts"]
    );
    assert!(
        !v["verdicts"].as_str().unwrap().contains("computing"),
        "{}",
        v["verdicts"]
    );
    v
}

/// What a failure message adds about the page: its status line, the pictures' `render-info`,
/// what its requests ended without drawing (`window.fastbrdfDropped`: aborted, 409, errors),
/// and the server's log.
fn page_context(v: &Value, log: &str) -> String {
    format!(
        "status {:?}; render-info {:?}; dropped {}; rows {}; server log: {log:?}",
        v["status_text"], v["render_info"], v["dropped"], v["rows"]
    )
}

/// A number the page shows (`key` of `model`'s row), or a failure naming the page's state.
fn shown(v: &Value, model: &str, key: &str, log: &str) -> f64 {
    let text = v["rows"][model][key].as_str().unwrap_or("");
    text.parse().unwrap_or_else(|_| {
        panic!(
            "{model}: {key} {text:?} is not a number; {}",
            page_context(v, log)
        )
    })
}

/// The numbers the page shows for `model` equal `fastbrdf errors` at the page's n (`log`:
/// the server's, for the failure messages).
fn check_numbers(v: &Value, model: &str, log: &str) {
    let n = v["n"].as_str().unwrap();
    let c = cli_errors(model, "pow", "--n", n);
    let row = &v["rows"][model];
    let abs = shown(v, model, "abs", log);
    assert_eq!(abs, c["max_abs"].as_f64().unwrap(), "{model} at n = {n}");
    // An infinite relative error is null in the CLI's JSON and "inf" on the page.
    match c["max_rel"].as_f64() {
        Some(r) => assert_eq!(shown(v, model, "rel", log), r),
        None => assert_eq!(row["rel"], "inf"),
    }
    let text = shown(v, model, "abs_text", log);
    assert!((text - abs).abs() <= 1e-3 * abs, "{text} shown for {abs}");
    shown(v, model, "psnr", log);
    // FLIP comes after the pictures (a second request): once the page is ready it is shown.
    let flip = shown(v, model, "flip", log);
    assert!(
        flip > 0.0 && flip <= 1.0,
        "FLIP {flip} shown; {}",
        page_context(v, log)
    );
    let text = shown(v, model, "flip_text", log);
    assert!(
        (text - flip).abs() <= 1e-3 * flip,
        "{text} shown for {flip}"
    );
}

/// What the server has written on stderr so far.
fn log(s: &served::Served) -> String {
    s.log.lock().unwrap().clone()
}

#[test]
fn page_end_to_end_in_headless_chromium() {
    let Some(path) = browser() else { return };
    let s = serve(&[]);
    let mut b = cdp::Browser::start(&path).unwrap();
    let url = format!("http://{}/#models=flog&ref=pow&n=100&theta=30", s.addr);
    let page = b.open(&url, 1400, 1050).unwrap();
    let before = snapshot(&mut b, &page);
    assert_eq!(before["n"], "100");
    check_numbers(&before, "flog", &log(&s));

    // An answer whose body an abort cuts short (a newer move took over after its headers) is
    // an abort for the page's getJSON, a successful answer whose body fails is an error, and
    // a failed answer that is not JSON is an error naming its status: never an answer. (The
    // first two came back as {error: "HTTP 200"} and broke the newest pictures' task.)
    let cut = b
        .eval(&page, r##"(async () => {
  const real = window.fetch, out = [];
  const failing = c => new ReadableStream({ pull(s) { if (c) c.abort(); s.error(new TypeError("body failed")); } });
  try {
    for (const [abort, status] of [[true, 200], [false, 200], [false, 502]]) {
      const c = new AbortController();
      window.fetch = async () => new Response(status === 200 ? failing(abort && c) : "not json", { status });
      try { out.push("answered " + JSON.stringify(await getJSON("/api/plots", c.signal))); }
      catch (e) { out.push(`${e.name} ${e.message} ${e.status}`); }
    }
  } finally { window.fetch = real; }
  return out.join("; ");
})()"##)
        .unwrap();
    let parts: Vec<&str> = cut.as_str().unwrap().split("; ").collect();
    assert!(
        parts.len() == 3
            && parts[0] == "AbortError aborted while its answer arrived undefined"
            && parts[1].starts_with("TypeError ")
            && parts[2] == "Error HTTP 502 502",
        "{cut}"
    );

    // Drag the n slider with real mouse events.
    let rect: Value = b
        .eval(&page, "(() => { const r = document.getElementById('slider-n').getBoundingClientRect(); return [r.left, r.top, r.width, r.height]; })()")
        .unwrap();
    let (x, y, w, h) = (
        rect[0].as_f64().unwrap(),
        rect[1].as_f64().unwrap(),
        rect[2].as_f64().unwrap(),
        rect[3].as_f64().unwrap(),
    );
    let (x0, x1, yc) = (x + 0.4 * w, x + 0.15 * w, y + h / 2.0);
    b.mouse(&page, "mousePressed", x0, yc).unwrap();
    for k in 1..=5 {
        b.mouse(&page, "mouseMoved", x0 + (x1 - x0) * f64::from(k) / 5.0, yc)
            .unwrap();
    }
    b.mouse(&page, "mouseReleased", x1, yc).unwrap();
    let moved = snapshot(&mut b, &page);
    assert_ne!(moved["n"], before["n"], "the slider moved n");
    for k in 0..5 {
        assert_ne!(
            moved["plots"][k], before["plots"][k],
            "plot {k} unchanged after the slider"
        );
    }
    assert_ne!(
        moved["images"], before["images"],
        "pictures unchanged after the slider"
    );
    check_numbers(&moved, "flog", &log(&s));

    // Choose a second model.
    b.eval(&page, "(() => { const s = document.getElementById('add'); s.value = 'schlick'; s.dispatchEvent(new Event('change')); })()")
        .unwrap();
    let two = snapshot(&mut b, &page);
    assert_ne!(
        two["plots"][0], moved["plots"][0],
        "polar plot unchanged after adding a model"
    );
    assert_eq!(
        two["images"].as_array().unwrap().len(),
        3,
        "{}",
        two["images"]
    );
    check_numbers(&two, "flog", &log(&s));
    check_numbers(&two, "schlick", &log(&s));

    // The URL reproduces the view.
    let again = b
        .open(
            &format!("http://{}/{}", s.addr, two["hash"].as_str().unwrap()),
            1400,
            1050,
        )
        .unwrap();
    let copy = snapshot(&mut b, &again);
    assert_eq!(copy["rows"], two["rows"]);
    assert_eq!(copy["n"], two["n"]);

    // Closing the browser leaves no profile behind.
    drop(b);
    let prefix = format!("fastbrdf-chromium-{}-", std::process::id());
    let left: Vec<_> = std::fs::read_dir(std::env::temp_dir())
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().starts_with(&prefix))
        .collect();
    assert!(left.is_empty(), "profile left behind: {left:?}");
}

/// Waits until the page has drawn everything, without an error shown.
fn ready(b: &mut cdp::Browser, s: &str) {
    b.wait_for(
        s,
        "document.body.dataset.ready === '1'",
        Duration::from_secs(120),
    )
    .unwrap();
    let status = b
        .eval(s, "document.getElementById('status').className")
        .unwrap();
    assert_eq!(status, "", "the page shows an error");
}

/// Cook-Torrance's g follows d on the server (ggx -> smith-ggx): the page's g menu shows the
/// term the pictures use, follows a change of d, and keeps a g the link names.
#[test]
fn page_g_menu_follows_d_in_headless_chromium() {
    let Some(path) = browser() else { return };
    let s = serve(&[]);
    let mut b = cdp::Browser::start(&path).unwrap();
    let g = "document.getElementById('choice-g').value";
    let page = b
        .open(
            &format!("http://{}/#models=cook-torrance&d=ggx", s.addr),
            1400,
            1050,
        )
        .unwrap();
    ready(&mut b, &page);
    assert_eq!(b.eval(&page, g).unwrap(), "smith-ggx");
    b.eval(&page, "(() => { const s = document.getElementById('choice-d'); s.value = 'beckmann'; s.dispatchEvent(new Event('change')); })()")
        .unwrap();
    ready(&mut b, &page);
    assert_eq!(b.eval(&page, g).unwrap(), "smith");
    let named = b
        .open(
            &format!("http://{}/#models=cook-torrance&d=ggx&g=v-cavity", s.addr),
            1400,
            1050,
        )
        .unwrap();
    ready(&mut b, &named);
    assert_eq!(b.eval(&named, g).unwrap(), "v-cavity");
}

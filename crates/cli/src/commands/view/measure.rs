//! `fastbrdf view --measure-frames N`: how fast the page redraws when a control moves, in
//! headless Chromium with WebGPU on its software adapter (SwiftShader), as the README states
//! it. The page itself measures (`fastbrdf:frame`: from a control's input event to the frame
//! drawn with every picture of that state; `fastbrdf:settle`: the full size after a drag drawn
//! at the preview size); this drives the first numeric slider with N mouse moves, each after
//! the previous frame, and also times frames drawn back to back with no control (the GPU's
//! share) at the preview and the full size.

use super::cdp::{Browser, find_browser};
use serde_json::{Value, json};
use std::path::Path;
use std::time::Duration;

/// Median, 90th percentile, least, most and count of `ms`.
fn summary(ms: &[f64]) -> Value {
    if ms.is_empty() {
        return Value::Null;
    }
    let mut v = ms.to_vec();
    v.sort_by(f64::total_cmp);
    let at = |q: f64| v[((v.len() - 1) as f64 * q).round() as usize];
    json!({"median": at(0.5), "p90": at(0.9), "min": v[0], "max": v[v.len() - 1], "n": v.len()})
}

fn numbers(b: &mut Browser, s: &str, js: &str) -> Result<Vec<f64>, String> {
    serde_json::from_value(b.eval(s, js)?).map_err(|e| format!("{js}: {e}"))
}

/// Loads `url` with WebGPU, drags its first numeric slider `moves` times and returns the
/// measures as JSON (see the module's documentation).
pub fn measure(browser: Option<&Path>, url: &str, moves: u32) -> Result<Value, String> {
    let mut b = Browser::start_with(&find_browser(browser)?, true)?;
    let s = b.open(url, 1400, 1050)?;
    let long = Duration::from_secs(300);
    b.wait_for(
        &s,
        "document.body.dataset.ready === '1' && !!document.body.dataset.renderer && (document.body.dataset.renderer === 'server' || !!GPU.scene)",
        long,
    )?;
    if b.eval(&s, "document.body.dataset.renderer")? != "webgpu" {
        let why = b.eval(&s, "document.getElementById('render-info').dataset.why || document.getElementById('status').textContent")?;
        return Err(format!("the page draws with the server, not WebGPU: {why}"));
    }
    let status = b.eval(&s, "document.getElementById('status').className")?;
    if status == "err" {
        let text = b.eval(&s, "document.getElementById('status').textContent")?;
        return Err(format!("the page shows an error: {text}"));
    }
    let (full, preview) = (
        b.eval(&s, "GPU.size")?.as_u64().unwrap_or(0),
        b.eval(&s, "GPU.preview")?.as_u64().unwrap_or(0),
    );
    let pictures = b.eval(&s, "document.querySelectorAll('#pictures canvas').length")?;
    let alone_full = numbers(
        &mut b,
        &s,
        &format!("window.fastbrdfFramesAlone({full}, 5)"),
    )?;
    let alone_preview = numbers(
        &mut b,
        &s,
        &format!("window.fastbrdfFramesAlone({preview}, 5)"),
    )?;
    let rect = numbers(
        &mut b,
        &s,
        "(() => { const e = document.querySelector('#params input[type=range]'); if (!e) throw new Error('no numeric parameter to drag'); e.scrollIntoView(); const r = e.getBoundingClientRect(); return [r.left, r.top, r.width, r.height]; })()",
    )?;
    let (x0, x1, y) = (
        rect[0] + 0.3 * rect[2],
        rect[0] + 0.7 * rect[2],
        rect[1] + rect[3] / 2.0,
    );
    const COUNT: &str = "performance.getEntriesByName('fastbrdf:frame').length";
    b.mouse(&s, "mousePressed", x0, y)?;
    for k in 1..=moves {
        let seen = b.eval(&s, COUNT)?.as_u64().unwrap_or(0);
        b.mouse(
            &s,
            "mouseMoved",
            x0 + (x1 - x0) * f64::from(k) / f64::from(moves),
            y,
        )?;
        b.wait_for(&s, &format!("{COUNT} > {seen}"), long)?;
    }
    b.mouse(&s, "mouseReleased", x1, y)?;
    b.wait_for(
        &s,
        "document.body.dataset.ready === '1' && !GPU.busy && GPU.settleSince === null && GPU.scene.s.width === GPU.size",
        long,
    )?;
    let frames = numbers(
        &mut b,
        &s,
        "performance.getEntriesByName('fastbrdf:frame').map(e => e.duration)",
    )?;
    let sizes = numbers(
        &mut b,
        &s,
        "performance.getEntriesByName('fastbrdf:frame').map(e => e.detail.size)",
    )?;
    let settle = numbers(
        &mut b,
        &s,
        "performance.getEntriesByName('fastbrdf:settle').map(e => e.duration)",
    )?;
    // The GPU's part of each frame (submission to read-back), the rest being the page's.
    let gpu = numbers(
        &mut b,
        &s,
        "performance.getEntriesByName('fastbrdf:frame').map(e => e.detail.gpu)",
    )?;
    let at = |size: u64| -> Vec<f64> {
        frames
            .iter()
            .zip(&sizes)
            .filter(|(_, s)| **s as u64 == size)
            .map(|(f, _)| *f)
            .collect()
    };
    Ok(json!({
        "url": url,
        "renderer": "webgpu",
        "adapter": b.eval(&s, "window.fastbrdfAdapter()")?,
        "pictures": pictures,
        "size": full, "preview_size": preview,
        "moves": moves,
        "frame_ms": summary(&frames),
        "frame_ms_at_size": summary(&at(full)),
        "frame_ms_at_preview": summary(&at(preview)),
        "settle_ms": summary(&settle),
        "frame_gpu_ms": summary(&gpu),
        "alone_ms": {"size": summary(&alone_full), "preview": summary(&alone_preview)},
    }))
}

//! The explorer's pictures drawn by WebGPU in headless Chromium (SwiftShader, issue 32): the
//! same picture as `fastbrdf render`, slider moves redrawn without a request to the server
//! and measured as `fastbrdf:frame`, and the server's pictures where the browser has no
//! WebGPU. Without Chromium these tests are skipped with a message, unless CI is set: then
//! they fail.

mod common;
mod explorer;
mod served;

use common::fastbrdf;
use explorer::{browser, cdp};
use serde_json::Value;
use served::serve;
use std::time::Duration;

const SIZE: u32 = 512;

fn wait_drawn(b: &mut cdp::Browser, s: &str) {
    b.wait_for(
        s,
        "document.getElementById('status').className === 'err' || (document.body.dataset.ready === '1' \
         && document.body.dataset.renderer === 'webgpu' \
         && document.querySelectorAll('#pictures canvas.render').length > 0)",
        Duration::from_secs(180),
    )
    .unwrap_or_else(|e| {
        let why = b
            .eval(s, "document.getElementById('status').textContent + ' / ' + document.body.dataset.renderer + ' / ' + (document.getElementById('render-info').dataset.why || '')")
            .unwrap_or_default();
        panic!("{e}: {why}")
    });
    let status = b
        .eval(s, "document.getElementById('status').className + ':' + document.getElementById('status').textContent + ' ' + (document.body.dataset.gpuError || '')")
        .unwrap();
    assert!(
        status.as_str().unwrap().starts_with(':'),
        "the page shows an error: {status}"
    );
}

/// The page's last picture of `id`, 8-bit RGB.
fn pixels(b: &mut cdp::Browser, s: &str, id: &str) -> Vec<u8> {
    let v = b
        .eval(s, &format!("window.fastbrdfPixels('{id}')"))
        .unwrap();
    cdp::base64_decode(v.as_str().unwrap()).unwrap()
}

/// `fastbrdf render` of the explorer's scene, 8-bit RGB.
fn cli_render(args: &[&str]) -> Vec<u8> {
    let dir = std::env::temp_dir().join(format!("fastbrdf-webgpu-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join(format!(
        "{}.png",
        args.join("_").replace(['/', ':', ','], "-")
    ));
    let size = format!("{SIZE}x{SIZE}");
    let out_text = out.to_str().unwrap();
    let mut all = vec!["render", "--size", &size, "--spp", "1", "--out", out_text];
    all.extend(args);
    let o = fastbrdf(&all, "");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let img = image::open(&out).unwrap().to_rgb8();
    let _ = std::fs::remove_file(&out);
    img.into_raw()
}

/// Largest channel difference (of 255) and PSNR (dB) of two 8-bit pictures.
fn compare(a: &[u8], b: &[u8]) -> (u8, f64) {
    assert_eq!(a.len(), b.len());
    let max = a.iter().zip(b).map(|(x, y)| x.abs_diff(*y)).max().unwrap();
    let se: f64 = a
        .iter()
        .zip(b)
        .map(|(&x, &y)| ((f64::from(x) - f64::from(y)) / 255.0).powi(2))
        .sum();
    let rmse = (se / a.len() as f64).sqrt();
    (max, 20.0 * (1.0 / rmse.max(1e-12)).log10())
}

#[test]
fn webgpu_pictures_equal_fastbrdf_render() {
    let Some(path) = browser() else { return };
    let s = serve(&[]);
    let mut b = cdp::Browser::start_with(&path, true).unwrap();
    let url = format!(
        "http://{}/#models=flog,cook-torrance&ref=pow&n=100&alpha=0.3&light=0.3,0.8,0.5",
        s.addr
    );
    let page = b.open(&url, 1400, 1050).unwrap();
    wait_drawn(&mut b, &page);
    for (id, args) in [
        ("pow", vec!["--model", "pow"]),
        ("flog", vec!["--model", "flog"]),
        ("cook-torrance", vec!["--model", "cook-torrance"]),
    ] {
        let mut all = args.clone();
        all.extend(["--param", "n=100", "--light", "dir:0.3,0.8,0.5"]);
        if id == "cook-torrance" {
            all.truncate(2);
            all.extend(["--param", "alpha=0.3", "--light", "dir:0.3,0.8,0.5"]);
        }
        let cpu = cli_render(&all);
        let gpu = pixels(&mut b, &page, id);
        if let Ok(d) = std::env::var("FASTBRDF_WEBGPU_DUMP") {
            for (name, px) in [("cpu", &cpu), ("webgpu", &gpu)] {
                image::save_buffer(
                    format!("{d}/{id}-{name}.png"),
                    px,
                    SIZE,
                    SIZE,
                    image::ColorType::Rgb8,
                )
                .unwrap();
            }
        }
        let (max, psnr) = compare(&cpu, &gpu);
        eprintln!(
            "{id}: WebGPU (SwiftShader) against fastbrdf render: max {max}/255, PSNR {psnr:.1} dB"
        );
        assert!(
            max <= 2,
            "{id}: max difference {max}/255 (PSNR {psnr:.1} dB)"
        );
    }
}

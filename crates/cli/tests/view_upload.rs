//! Users' models sent to a running `fastbrdf view` (issue 32): `POST /api/user?name=FILE` with
//! the file as the body compiles a `.brdf`, `.wgsl` or `.glsl` file as `--model file:FILE`
//! does at start-up (its plots, errors and pictures equal the same file's given at start-up),
//! a compile error is 400 with the line and column `fastbrdf eval --model file:...` prints,
//! bodies are bounded (413), uploads are bounded (16 kept), a cross-site POST is refused, and
//! `/api/conform` answers `fastbrdf conform file:PATH --json`'s record. Then the page: a WGSL
//! function pasted into "Your model" in headless Chromium is listed with its conform verdicts,
//! and a compile error shows its line; with WebGPU (SwiftShader) the browser's own compiler
//! names the same line and column first. The GPU tests skip without a GPU unless CI is set;
//! lavapipe serves in CI.

mod common;
mod explorer;
mod served;

use common::{fastbrdf, gpu_data as data, have_gpu, stderr};
use explorer::{browser, cdp, get_json, ok_json, request};
use serde_json::{Value, json};
use served::serve;
use std::io::{Read, Write};
use std::net::TcpStream;
use std::time::Duration;

/// One raw HTTP request with `headers` (each ending in CRLF) and `body` (a Content-Length is
/// added): status, head, body.
fn send(
    addr: &str,
    method: &str,
    target: &str,
    headers: &str,
    body: &[u8],
) -> (u16, String, Vec<u8>) {
    let mut s = TcpStream::connect(addr).unwrap();
    s.set_read_timeout(Some(Duration::from_secs(120))).unwrap();
    write!(
        s,
        "{method} {target} HTTP/1.1\r\nHost: {addr}\r\n{headers}Content-Length: {}\r\nConnection: close\r\n\r\n",
        body.len()
    )
    .unwrap();
    // The server may answer (413, 403) before reading it all: a failed write is fine.
    let _ = s.write_all(body);
    let mut buf = vec![];
    let _ = s.read_to_end(&mut buf);
    let split = buf
        .windows(4)
        .position(|w| w == b"\r\n\r\n")
        .expect("an answer");
    let head = String::from_utf8_lossy(&buf[..split]).to_string();
    let status = head.split(' ').nth(1).unwrap().parse().unwrap();
    (status, head, buf[split + 4..].to_vec())
}

/// `POST /api/user?name=NAME` with the file `text`: status and JSON.
fn upload(addr: &str, name: &str, text: &str) -> (u16, Value) {
    let (status, head, body) = send(
        addr,
        "POST",
        &format!("/api/user?name={name}"),
        "",
        text.as_bytes(),
    );
    let v = serde_json::from_slice(&body).unwrap_or_else(|_| panic!("{head}"));
    (status, v)
}

fn read(rel: &str) -> String {
    std::fs::read_to_string(data(rel)).unwrap()
}

/// `v` without its fields `keys` (the model's name and file, which differ between an upload
/// and the same file given at start-up).
fn without(v: &Value, keys: &[&str]) -> Value {
    let mut v = v.clone();
    for k in keys {
        v.as_object_mut().unwrap().remove(*k);
    }
    v
}

#[test]
fn an_uploaded_file_is_the_model_it_would_be_at_start_up() {
    if !have_gpu() {
        return;
    }
    let files = [
        ("user/ggx_sampled.wgsl", "ggx_sampled.wgsl"),
        ("user/blinn_phong.glsl", "blinn_phong.glsl"),
        ("brdf-explorer/walter.brdf", "walter.brdf"),
    ];
    let given: Vec<String> = files
        .iter()
        .map(|(f, _)| format!("file:{}", data(f)))
        .collect();
    let mut args = vec![];
    for g in &given {
        args.extend(["--model", g.as_str()]);
    }
    let s = serve(&args);
    let t = std::time::Instant::now();
    for (file, name) in files {
        let (status, entry) = upload(&s.addr, name, &read(file));
        assert_eq!(status, 200, "{name}: {entry}");
        let id = format!("file:{name}");
        // The entry /api/models lists, the start-up one's but for the name, file and source.
        let info = ok_json(&s.addr, "/api/models");
        let listed = info["models"].as_array().unwrap();
        let at_start = listed.iter().find(|m| m["id"] == name).unwrap();
        assert_eq!(listed.iter().find(|m| m["id"] == id.as_str()), Some(&entry));
        // The page's WebGPU pictures take the upload's module, the start-up file's.
        let module = |m: &str| ok_json(&s.addr, &format!("/api/gpu/shader?model={m}"));
        let (up, start) = (module(&id), module(name));
        assert_eq!(up["block"], "user");
        assert_eq!(
            up["wgsl"], start["wgsl"],
            "{name}: the upload's WebGPU module"
        );
        let strip = |e: &Value| {
            let mut e = without(e, &["id", "file", "source", "uploaded"]);
            // The declared-at notes name the file as given.
            for p in e["params"].as_array_mut().unwrap() {
                p.as_object_mut().unwrap().remove("doc");
            }
            e
        };
        assert_eq!(strip(&entry), strip(at_start), "{name}");
        assert_eq!(
            (entry["uploaded"].clone(), at_start["uploaded"].clone()),
            (json!(true), json!(false))
        );

        // Plots and errors against a registry reference, equal to the start-up model's.
        let q = format!("/api/plots?models={id},{name}&ref=cook-torrance&theta=40");
        let plots = ok_json(&s.addr, &q);
        let row = |m: &str| {
            plots["models"]
                .as_array()
                .unwrap()
                .iter()
                .find(|r| r["id"] == m)
                .unwrap()
                .clone()
        };
        let plot_keys = ["id", "file"];
        assert_eq!(
            without(&row(&id), &plot_keys),
            without(&row(name), &plot_keys),
            "{name}"
        );
        assert!(row(&id)["against"]["max_abs"].as_f64().unwrap() > 0.0);
        let errors = |m: &str| {
            without(
                &ok_json(&s.addr, &format!("/api/errors?model={m}&ref=cook-torrance")),
                &["model"],
            )
        };
        assert_eq!(errors(&id), errors(name), "{name}");

        // The same pictures.
        let r = ok_json(
            &s.addr,
            &format!("/api/render?models={id},{name}&size=24&spp=1&flip=none"),
        );
        let png = |m: &str| {
            r["images"]
                .as_array()
                .unwrap()
                .iter()
                .find(|i| i["id"] == m)
                .unwrap()["png"]
                .clone()
        };
        assert_eq!(png(&id), png(name), "{name}");
    }
    eprintln!(
        "3 uploads, each plotted, compared and rendered: {:?}",
        t.elapsed()
    );

    // conform: the CLI's record, number for number (the start-up model is named as the CLI
    // names the file; the upload differs in its name only), with a parameter's value.
    let ggx = &given[0];
    let cli = fastbrdf(&["conform", ggx, "--param", "alpha=0.5", "--json"], "");
    let cli: Value =
        serde_json::from_slice(&cli.stdout).unwrap_or_else(|_| panic!("{}", stderr(&cli)));
    let t = std::time::Instant::now();
    let served = ok_json(&s.addr, "/api/conform?model=ggx_sampled.wgsl&alpha=0.5");
    eprintln!("/api/conform of ggx_sampled.wgsl: {:?}", t.elapsed());
    assert_eq!(served, cli);
    let up = ok_json(
        &s.addr,
        "/api/conform?model=file:ggx_sampled.wgsl&alpha=0.5",
    );
    assert_eq!(up["model"], "file:ggx_sampled.wgsl");
    assert_eq!(without(&up, &["model"]), without(&cli, &["model"]));
    assert_eq!(cli["checks"].as_array().unwrap().len(), 11);
    // A failing model's record too (blinn_phong gains energy: conform exits 1, the page's 200).
    let cli = fastbrdf(&["conform", &given[1], "--json"], "");
    assert_eq!(cli.status.code(), Some(1));
    let cli: Value = serde_json::from_slice(&cli.stdout).unwrap();
    assert_eq!(cli["passed"], false);
    let up = ok_json(&s.addr, "/api/conform?model=file:blinn_phong.glsl");
    assert_eq!(without(&up, &["model"]), without(&cli, &["model"]));
    // A registry model as `fastbrdf conform ID`.
    let cli = fastbrdf(
        &["conform", "cook-torrance", "--param", "alpha=0.3", "--json"],
        "",
    );
    let cli: Value = serde_json::from_slice(&cli.stdout).unwrap();
    assert_eq!(
        ok_json(&s.addr, "/api/conform?model=cook-torrance&alpha=0.3"),
        cli
    );
    // Bad values are 400 naming them.
    let (status, v) = get_json(&s.addr, "/api/conform?model=file:ggx_sampled.wgsl&alpha=7");
    assert_eq!(status, 400, "{v}");
    assert!(v["error"].as_str().unwrap().contains("alpha"), "{v}");
    let (status, v) = get_json(&s.addr, "/api/conform?model=no-such-model");
    assert_eq!(status, 400, "{v}");
}

#[test]
fn compile_errors_are_400_with_the_clis_line_and_column() {
    if !have_gpu() {
        return;
    }
    let s = serve(&[]);
    for ext in ["wgsl", "glsl", "brdf"] {
        let rel = format!("user/compile_error.{ext}");
        let path = data(&rel);
        let o = fastbrdf(&["eval", "--model", &format!("file:{path}")], "");
        assert_eq!(o.status.code(), Some(2));
        // error: PATH:LINE:COL: MESSAGE
        let cli = stderr(&o);
        let after = cli
            .trim()
            .strip_prefix(&format!("error: {path}:"))
            .unwrap_or_else(|| panic!("{cli}"));
        let mut it = after.splitn(3, ':');
        let (line, column) = (it.next().unwrap(), it.next().unwrap());
        let name = format!("compile_error.{ext}");
        let (status, v) = upload(&s.addr, &name, &read(&rel));
        assert_eq!(status, 400, "{v}");
        assert_eq!(v["error"], format!("{name}:{after}"), "{ext}");
        assert_eq!(v["line"].to_string(), line, "{ext}");
        assert_eq!(v["column"].to_string(), column, "{ext}");
    }
    // Nothing was added.
    assert_eq!(ok_json(&s.addr, "/api/models")["users"], json!([]));
}

#[test]
fn uploads_are_bounded_and_same_origin_only() {
    if !have_gpu() {
        return;
    }
    let s = serve(&[]);
    let ggx = read("user/ggx_sampled.wgsl");
    // A body over 256 KiB: 413, declared (nothing read) or sent chunked (read up to the cap).
    let big = format!("{ggx}{}", " ".repeat(256 * 1024));
    let mut c = TcpStream::connect(&s.addr).unwrap();
    c.set_read_timeout(Some(Duration::from_secs(60))).unwrap();
    write!(
        c,
        "POST /api/user?name=big.wgsl HTTP/1.1\r\nHost: {}\r\nContent-Length: {}\r\n\r\n",
        s.addr,
        big.len()
    )
    .unwrap();
    let mut buf = vec![];
    let _ = c.read_to_end(&mut buf);
    let answer = String::from_utf8_lossy(&buf);
    assert!(answer.starts_with("HTTP/1.1 413"), "{answer}");
    assert!(answer.contains("at most 262144 bytes"), "{answer}");
    let mut chunked = format!("{:x}\r\n{big}\r\n0\r\n\r\n", big.len()).into_bytes();
    let mut c = TcpStream::connect(&s.addr).unwrap();
    c.set_read_timeout(Some(Duration::from_secs(60))).unwrap();
    let mut req = format!(
        "POST /api/user?name=big.wgsl HTTP/1.1\r\nHost: {}\r\nTransfer-Encoding: chunked\r\nConnection: close\r\n\r\n",
        s.addr
    )
    .into_bytes();
    req.append(&mut chunked);
    let _ = c.write_all(&req);
    let mut buf = vec![];
    let _ = c.read_to_end(&mut buf);
    assert!(
        String::from_utf8_lossy(&buf).starts_with("HTTP/1.1 413"),
        "{}",
        String::from_utf8_lossy(&buf[..buf.len().min(300)])
    );

    // Another site's page cannot upload (a browser marks its request), nor can a request for
    // another name; GET is 405; other paths still take no body; names are checked.
    for headers in [
        "Origin: http://evil.example\r\n",
        "Sec-Fetch-Site: cross-site\r\n",
        "Sec-Fetch-Site: same-site\r\n",
    ] {
        let (status, _, body) = send(
            &s.addr,
            "POST",
            "/api/user?name=x.wgsl",
            headers,
            ggx.as_bytes(),
        );
        assert_eq!(status, 403, "{headers}");
        assert!(String::from_utf8_lossy(&body).contains("cross-site"));
    }
    let (status, _, body) = request(&s.addr, "GET", "/api/user?name=x.wgsl");
    assert_eq!(status, 405, "{}", String::from_utf8_lossy(&body));
    let (status, _, _) = send(&s.addr, "POST", "/api/models", "", b"x");
    assert_eq!(status, 413);
    for (name, why) in [
        ("x.txt", "unknown shader language"),
        ("../x.wgsl", "letters, digits"),
        ("a,b.wgsl", "letters, digits"),
    ] {
        let (status, v) = upload(&s.addr, name, &ggx);
        assert_eq!(status, 400, "{name}: {v}");
        assert!(v["error"].as_str().unwrap().contains(why), "{name}: {v}");
    }
    let (status, v) = upload(&s.addr, "empty.wgsl", " \n");
    assert_eq!(
        (status, v["error"].as_str().unwrap()),
        (400, "empty.wgsl: the file is empty")
    );
    assert_eq!(ok_json(&s.addr, "/api/models")["users"], json!([]));

    // 17 uploads keep the newest 16; an upload of a name replaces that model.
    let t = std::time::Instant::now();
    for k in 0..17 {
        let (status, v) = upload(&s.addr, &format!("m{k}.wgsl"), &ggx);
        assert_eq!(status, 200, "{v}");
    }
    eprintln!("17 uploads: {:?}", t.elapsed());
    let (status, v) = upload(&s.addr, "m5.wgsl", &ggx.replace("0.01 1 0.3", "0.01 1 0.4"));
    assert_eq!(status, 200, "{v}");
    assert_eq!(v["params"][0]["default"], 0.4);
    let users = ok_json(&s.addr, "/api/models")["users"].clone();
    let mut want: Vec<String> = (1..17)
        .filter(|k| *k != 5)
        .map(|k| format!("file:m{k}.wgsl"))
        .collect();
    want.push("file:m5.wgsl".into());
    assert_eq!(users, json!(want));
    let (status, v) = get_json(&s.addr, "/api/plots?models=file:m0.wgsl");
    assert_eq!(status, 400, "{v}");
}

/// The page's state for the tests: the models listed, "Your model"'s status, errors and
/// conform rows.
const USER_SNAPSHOT: &str = r##"JSON.stringify({
  ready: document.body.dataset.ready,
  models: [...document.querySelectorAll("#models b")].map(b => b.textContent),
  status: document.getElementById("user-status").textContent,
  errors: document.getElementById("user-errors").textContent,
  verdict: (document.getElementById("user-verdict") || {}).textContent || "",
  checks: [...document.querySelectorAll("#user-checks tr[data-check]")].map(r => [...r.children].map(c => c.textContent)),
  page_status: document.getElementById("status").textContent,
})"##;

fn paste_and_compile(b: &mut cdp::Browser, page: &str, name: &str, text: &str) -> Value {
    let js = format!(
        "(() => {{ document.getElementById('user-name').value = {}; document.getElementById('user-text').value = {}; document.getElementById('user-compile').click(); return 1; }})()",
        json!(name),
        json!(text)
    );
    b.eval(page, &js).unwrap();
    // The compile's task starts at once: wait for it and everything it started.
    std::thread::sleep(Duration::from_millis(200));
    b.wait_for(
        page,
        "document.body.dataset.ready === '1'",
        Duration::from_secs(60),
    )
    .unwrap();
    serde_json::from_str(b.eval(page, USER_SNAPSHOT).unwrap().as_str().unwrap()).unwrap()
}

#[test]
fn a_function_pasted_into_the_page_is_listed_with_its_conform_verdicts() {
    let Some(path) = browser() else { return };
    if !have_gpu() {
        return;
    }
    let s = serve(&[]);
    let mut b = cdp::Browser::start(&path).unwrap();
    let page = b
        .open(
            &format!("http://{}/#models=flog&ref=pow", s.addr),
            1400,
            1050,
        )
        .unwrap();
    b.wait_for(
        &page,
        "document.body.dataset.ready === '1'",
        Duration::from_secs(60),
    )
    .unwrap();
    let v = paste_and_compile(
        &mut b,
        &page,
        "pasted_ggx.wgsl",
        &read("user/ggx_sampled.wgsl"),
    );
    assert!(
        v["models"]
            .as_array()
            .unwrap()
            .contains(&json!("file:pasted_ggx.wgsl")),
        "{v}"
    );
    assert!(v["status"].as_str().unwrap().contains("compiled"), "{v}");
    assert_eq!(v["errors"], "", "{v}");
    // Its verdicts: the server's record, check by check.
    let want = ok_json(&s.addr, "/api/conform?model=file:pasted_ggx.wgsl");
    let checks = v["checks"].as_array().unwrap();
    assert_eq!(checks.len(), 11, "{v}");
    for (shown, c) in checks.iter().zip(want["checks"].as_array().unwrap()) {
        assert_eq!(shown[0], c["check"]);
        assert_eq!(shown[1], c["status"].as_str().unwrap().to_uppercase());
    }
    let verdict = v["verdict"].as_str().unwrap();
    assert!(
        verdict.contains(if want["passed"] == true {
            "PASS"
        } else {
            "FAIL"
        }),
        "{v}"
    );
    // The page's plots include it (no error in the page's status line).
    assert!(!v["page_status"].as_str().unwrap().contains("error"), "{v}");

    // A compile error: its line and column, as text, and nothing added.
    let v = paste_and_compile(&mut b, &page, "typo.wgsl", &read("user/compile_error.wgsl"));
    assert!(
        v["status"].as_str().unwrap().contains("line 7, column 23"),
        "{v}"
    );
    assert!(
        v["errors"]
            .as_str()
            .unwrap()
            .contains("typo.wgsl:7:23: error: no definition in scope for identifier: `alpah`"),
        "{v}"
    );
    assert!(
        !v["models"]
            .as_array()
            .unwrap()
            .contains(&json!("file:typo.wgsl")),
        "{v}"
    );
    assert_eq!(v["checks"], json!([]), "{v}");
}

#[test]
fn a_browser_with_webgpu_shows_its_own_compile_messages_with_the_files_lines() {
    let Some(path) = browser() else { return };
    if !have_gpu() {
        return;
    }
    let s = serve(&[]);
    let mut b = cdp::Browser::start_with(&path, true).unwrap();
    let page = b
        .open(
            &format!("http://{}/#models=flog&ref=pow", s.addr),
            1400,
            1050,
        )
        .unwrap();
    b.wait_for(
        &page,
        "document.body.dataset.ready === '1'",
        Duration::from_secs(60),
    )
    .unwrap();
    let v = paste_and_compile(&mut b, &page, "typo.wgsl", &read("user/compile_error.wgsl"));
    // The browser's compiler (Tint) and the server's (naga) find the same line and column.
    let errors = v["errors"].as_str().unwrap();
    assert!(errors.contains("browser: typo.wgsl:7:23: "), "{v}");
    assert!(
        errors.contains("\ntypo.wgsl:7:23: error: no definition in scope"),
        "{v}"
    );
    // A correct function: no message from either.
    let v = paste_and_compile(&mut b, &page, "ok.wgsl", &read("user/ggx_sampled.wgsl"));
    assert_eq!(v["errors"], "", "{v}");
    assert!(
        v["models"]
            .as_array()
            .unwrap()
            .contains(&json!("file:ok.wgsl")),
        "{v}"
    );
}

//! What `--out` names decides how it is written (issue 27): a symbolic link is followed and the
//! file it names is replaced beside itself (the link stays a link, a dangling link's target is
//! created), a FIFO, a character device and `/dev/stdout` are written in place and never
//! replaced, a socket is refused with exit 2, a full device is exit 3 and stays a device.
#![cfg(unix)]

mod common;

use common::{fastbrdf, listing, stderr, temp_dir};
use std::os::unix::fs::{FileTypeExt, symlink};
use std::path::Path;
use std::sync::mpsc;
use std::time::Duration;

/// `fastbrdf lut --size 4 --format csv --out OUT`.
fn lut_to(out: &Path) -> std::process::Output {
    fastbrdf(
        &[
            "lut",
            "--size",
            "4",
            "--format",
            "csv",
            "--out",
            out.to_str().unwrap(),
        ],
        "",
    )
}

/// The CSV the command writes to a plain file (what every other destination must receive).
fn expected_csv(d: &Path) -> Vec<u8> {
    let plain = d.join("plain.csv");
    let o = lut_to(&plain);
    assert!(o.status.success(), "{}", stderr(&o));
    let bytes = std::fs::read(&plain).unwrap();
    std::fs::remove_file(&plain).unwrap();
    assert!(bytes.starts_with(b"cos_v,roughness,alpha,scale,bias\n"));
    bytes
}

fn ok(o: &std::process::Output) {
    assert!(o.status.success(), "{}", stderr(o));
    assert!(o.stdout.is_empty(), "nothing on stdout");
}

fn is_link(p: &Path) -> bool {
    std::fs::symlink_metadata(p)
        .unwrap()
        .file_type()
        .is_symlink()
}

fn file_type(p: &Path) -> std::fs::FileType {
    std::fs::symlink_metadata(p).unwrap().file_type()
}

#[test]
fn a_symlink_is_followed_and_stays_a_link() {
    let d = temp_dir("outputs-links");
    let want = expected_csv(&d);
    std::fs::create_dir_all(d.join("real")).unwrap();
    std::fs::create_dir_all(d.join("out")).unwrap();
    let target = d.join("real/dfg.csv");
    std::fs::write(&target, b"old content\n").unwrap();
    let link = d.join("out/dfg.csv");
    symlink("../real/dfg.csv", &link).unwrap();
    ok(&lut_to(&link));
    assert!(is_link(&link), "the link was replaced by a regular file");
    assert_eq!(
        std::fs::read(&target).unwrap(),
        want,
        "the target is updated"
    );
    // No temporary left beside the link or the target.
    assert_eq!(listing(&d.join("out")), vec!["dfg.csv"]);
    assert_eq!(listing(&d.join("real")), vec!["dfg.csv"]);

    // A chain: chain -> out/dfg.csv -> real/dfg.csv.
    std::fs::write(&target, b"old again\n").unwrap();
    let chain = d.join("chain.csv");
    symlink(&link, &chain).unwrap();
    ok(&lut_to(&chain));
    assert!(is_link(&chain) && is_link(&link));
    assert_eq!(std::fs::read(&target).unwrap(), want);

    // A dangling link: the file it names is created, the link stays.
    let dangling = d.join("dangling.csv");
    symlink("real/new.csv", &dangling).unwrap();
    ok(&lut_to(&dangling));
    assert!(is_link(&dangling));
    assert_eq!(std::fs::read(d.join("real/new.csv")).unwrap(), want);

    // A loop is bad usage: exit 2, and the links stay.
    symlink("loop-b.csv", d.join("loop-a.csv")).unwrap();
    symlink("loop-a.csv", d.join("loop-b.csv")).unwrap();
    let o = lut_to(&d.join("loop-a.csv"));
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("loop-a.csv"), "{}", stderr(&o));
    assert!(is_link(&d.join("loop-a.csv")) && is_link(&d.join("loop-b.csv")));
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn a_fifo_with_a_reader_receives_the_bytes_and_stays_a_fifo() {
    let d = temp_dir("outputs-fifo");
    let want = expected_csv(&d);
    let fifo = d.join("pipe.csv");
    let made = std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap();
    assert!(made.success());
    // The reader reports through a channel: a regression (the FIFO replaced while the reader
    // waits in open) fails after a bounded wait instead of hanging the suite.
    let (tx, rx) = mpsc::channel();
    {
        let fifo = fifo.clone();
        std::thread::spawn(move || tx.send(std::fs::read(fifo).unwrap()));
    }
    ok(&lut_to(&fifo));
    assert!(file_type(&fifo).is_fifo(), "the FIFO was replaced");
    let got = rx
        .recv_timeout(Duration::from_secs(60))
        .expect("the reader received the table");
    assert_eq!(got, want);
    assert_eq!(listing(&d), vec!["pipe.csv"], "no temporary left");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn a_full_device_is_an_output_error_and_stays_a_device() {
    let full = Path::new("/dev/full");
    if std::fs::OpenOptions::new().write(true).open(full).is_err() {
        assert!(
            std::env::var_os("CI").is_none(),
            "/dev/full is not writable under CI"
        );
        eprintln!("skipped: /dev/full is not writable here");
        return;
    }
    // As root, the old rename replaced /dev/full by a CSV file; as anyone, the write must
    // fail with ENOSPC.
    let o = lut_to(full);
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    assert!(o.stdout.is_empty());
    let e = stderr(&o);
    assert!(e.contains("/dev/full") && e.contains("space"), "{e}");
    assert!(
        file_type(full).is_char_device(),
        "/dev/full is no longer a character device"
    );
    // /dev/null takes it all, and stays.
    ok(&lut_to(Path::new("/dev/null")));
    assert!(file_type(Path::new("/dev/null")).is_char_device());
}

#[test]
fn dev_stdout_is_the_process_standard_output() {
    let d = temp_dir("outputs-stdout");
    let want = expected_csv(&d);
    let o = lut_to(Path::new("/dev/stdout"));
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(o.stdout, want, "the table arrives on stdout (a pipe here)");
    // Through a link to /dev/stdout too.
    let link = d.join("to-stdout.csv");
    symlink("/dev/stdout", &link).unwrap();
    let o = lut_to(&link);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(o.stdout, want);
    assert!(is_link(&link));
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn a_socket_is_refused_with_exit_2() {
    let d = temp_dir("outputs-socket");
    let sock = d.join("s.csv");
    let _listener = std::os::unix::net::UnixListener::bind(&sock).unwrap();
    let o = lut_to(&sock);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(o.stdout.is_empty());
    let e = stderr(&o);
    assert!(e.contains("s.csv") && e.contains("socket"), "{e}");
    assert!(file_type(&sock).is_socket(), "the socket was replaced");
    assert_eq!(listing(&d), vec!["s.csv"]);
    let _ = std::fs::remove_dir_all(&d);
}

/// Every string leaf of `v` that reads as a number, with its JSON pointer. `denominator` is a
/// choice whose options are named "4", "seed-000", "seed-001": a name, not a number.
fn numbers_as_strings(v: &serde_json::Value, at: &str, out: &mut Vec<String>) {
    match v {
        serde_json::Value::Object(m) => {
            for (k, x) in m {
                if k != "denominator" {
                    numbers_as_strings(x, &format!("{at}/{k}"), out);
                }
            }
        }
        serde_json::Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                numbers_as_strings(x, &format!("{at}/{i}"), out);
            }
        }
        serde_json::Value::String(s) if s.trim().parse::<f64>().is_ok() => {
            out.push(format!("{at} = {s:?}"))
        }
        _ => {}
    }
}

/// Issue 27: `chi2 --json` and `albedo --ms-compare --json` echoed parameters as strings
/// (`"alpha": "0.5"`), and `pareto --brdf --json` its configurations' (`["eta", "1.5"]`).
/// Every machine output that echoes parameters carries numbers: no string anywhere in these
/// documents reads as a number.
#[test]
fn json_outputs_carry_numbers_not_strings() {
    let d = temp_dir("outputs-json");
    let merl = d.join("ct.binary");
    {
        use fastbrdf::measured::{from_half_diff, write_merl};
        let fastbrdf::Model::Brdf(b) = fastbrdf::ModelSpec::parse(
            "cook-torrance",
            &[("f", "schlick"), ("alpha", "0.3"), ("f0", "0.04")],
        )
        .and_then(|s| s.model::<f64>())
        .unwrap() else {
            panic!("a BRDF")
        };
        write_merl(&merl, |th, td, pd| {
            let (wi, wo) = from_half_diff(th, td, pd);
            if wi[2] <= 0.0 || wo[2] <= 0.0 {
                return [-1.0; 3];
            }
            let s = b.eval(wi, wo);
            [0.1, 0.05, 0.02].map(|kd| kd / std::f64::consts::PI + s)
        })
        .unwrap();
    }
    let merl = merl.to_str().unwrap();
    let pic = d.join("p.png");
    let pic = pic.to_str().unwrap();
    let runs: Vec<Vec<&str>> = vec![
        vec!["chi2", "--model", "cook-torrance", "--param", "alpha=0.5"],
        vec!["chi2", "--model", "phong", "--param", "n=100"],
        vec![
            "albedo",
            "--model",
            "cook-torrance",
            "--param",
            "alpha=0.5",
            "--ms-compare",
        ],
        vec!["albedo", "--model", "cook-torrance", "--param", "alpha=0.5"],
        vec![
            "errors",
            "--model",
            "flog",
            "--reference",
            "pow",
            "--n",
            "10,20",
        ],
        vec!["pareto", "--brdf", "--quick", "--size", "0"],
        vec![
            "fit-measured",
            "--data",
            merl,
            "--model",
            "cook-torrance",
            "--param",
            "f=schlick",
            "--param",
            "alpha=0.3",
            "--samples",
            "300",
            "--restarts",
            "1",
            "--size",
            "8x8",
            "--spp",
            "1",
            "--out",
            pic,
        ],
        vec![
            "errors",
            "--model",
            "ward",
            "--measured",
            merl,
            "--m",
            "0.3",
        ],
        vec!["measured", "info", merl],
    ];
    for args in runs {
        let mut args = args.clone();
        if args[0] == "chi2" {
            args.extend(["--res", "8", "--samples", "2000"]);
        }
        if args[0] == "albedo" {
            args.extend(["--angles", "0,60"]);
        }
        args.push("--json");
        let o = fastbrdf(&args, "");
        assert!(o.status.success(), "{args:?}: {}", stderr(&o));
        let v: serde_json::Value = serde_json::from_slice(&o.stdout)
            .unwrap_or_else(|e| panic!("{args:?}: not JSON ({e})"));
        let mut bad = Vec::new();
        numbers_as_strings(&v, "", &mut bad);
        assert!(bad.is_empty(), "{args:?}: numbers as strings: {bad:?}");
        // The echoed parameters are numbers (a discriminating check, besides the scan).
        if let Some(p) = v.get("params").and_then(|p| p.as_object()) {
            for k in ["alpha", "n"] {
                if let Some(x) = p.get(k) {
                    assert!(x.is_number(), "{args:?}: params.{k} = {x}");
                }
            }
        }
    }
    let _ = std::fs::remove_dir_all(&d);
}

/// Review of issue 27: user B's `/tmp/out.csv -> ~A/.bashrc` had A's file replaced by
/// `--out /tmp/out.csv` (the link is read by fastbrdf, so the kernel's protected_symlinks never
/// ran). Another user's link in a sticky, world-writable folder is now refused: exit 2, naming
/// it, the file it points at untouched. Needs root to give the link away (CI runs as root).
#[test]
fn another_users_link_in_a_sticky_folder_is_refused() {
    use std::os::unix::fs::{PermissionsExt, lchown};
    // SAFETY: geteuid has no preconditions and cannot fail.
    if unsafe { libc::geteuid() } != 0 {
        assert!(
            std::env::var_os("CI").is_none(),
            "CI is set and the test is not root"
        );
        eprintln!("skipped: not root, cannot make a link another user's");
        return;
    }
    let d = temp_dir("outputs-sticky");
    let tmp = d.join("tmp");
    std::fs::create_dir_all(&tmp).unwrap();
    std::fs::set_permissions(&tmp, std::fs::Permissions::from_mode(0o1777)).unwrap();
    let victim = d.join("bashrc");
    std::fs::write(&victim, b"export PATH\n").unwrap();
    let link = tmp.join("out.csv");
    symlink(&victim, &link).unwrap();
    lchown(&link, Some(12345), Some(12345)).unwrap();
    let o = lut_to(&link);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(e.contains("out.csv") && e.contains("another user"), "{e}");
    assert!(o.stdout.is_empty());
    assert_eq!(std::fs::read(&victim).unwrap(), b"export PATH\n");
    assert!(is_link(&link));
    assert_eq!(listing(&d), vec!["bashrc", "tmp"]);
    let _ = std::fs::remove_dir_all(&d);
}

//! Renderer inputs and outputs (issue 11): every OBJ rejection names its line and column, all
//! valid OBJ loads, textures are size-checked before decoding, options that cannot render
//! finitely are refused, no NaN or inf reaches a file, EXR is scanline ZIP and linear, PNG has
//! an sRGB chunk, comparisons are capped as a whole, and the linear metrics see highlights.

use fastbrdf::ModelSpec;
use fastbrdf_render::compare;
use fastbrdf_render::film::Film;
use fastbrdf_render::mesh::{load_obj, parse_obj, validate_obj};
use fastbrdf_render::render::{Options, Shading, render};
use fastbrdf_render::scene::{Light, LightKind, Specular};
use fastbrdf_render::setup::{self, SceneSpec};
use fastbrdf_render::texture::Texture;
use glam::Vec3;
use std::path::{Path, PathBuf};
use std::sync::Arc;

const TRI: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";

/// The path `name` in a fresh folder of its own (tests run side by side), the folder removed
/// when the guard is dropped unless the test is failing (then kept for a look).
fn tmp(name: &str) -> Tmp {
    let d = std::env::temp_dir().join(format!(
        "fastbrdf-render-inputs-{}-{name}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    Tmp(d.join(name))
}

/// A path of [`tmp`]; derefs to it.
struct Tmp(PathBuf);

impl std::ops::Deref for Tmp {
    type Target = PathBuf;
    fn deref(&self) -> &PathBuf {
        &self.0
    }
}

impl AsRef<Path> for Tmp {
    fn as_ref(&self) -> &Path {
        &self.0
    }
}

impl Drop for Tmp {
    fn drop(&mut self) {
        let dir = self.0.parent().expect("a folder");
        if std::thread::panicking() {
            eprintln!("kept for a look: {}", dir.display());
        } else {
            let _ = std::fs::remove_dir_all(dir);
        }
    }
}

/// Bad OBJ texts, each with the line and column its error must name and a fragment of it.
/// Many of these passed the old validator and were then refused by tobj without a line, or
/// were accepted with NaN texture coordinates.
pub const BAD_OBJ: &[(&str, &str, &str)] = &[
    (
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n",
        "4: column 7",
        "vertex index 4 is out of range",
    ),
    (
        "v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n",
        "2: column 5",
        "'nan' is not a finite number",
    ),
    (
        "v 0 0 0\nv 1 0\n",
        "2:",
        "vertex needs 3, 4, 6 or 7 numbers, found 2",
    ),
    (
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n",
        "4:",
        "a face needs at least 3 vertices",
    ),
    (
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/5 2/1 3/1\nvt 0 0\n",
        "4: column 3",
        "texture coordinate index 5 is out of range",
    ),
    (
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n",
        "4: column 7",
        "non-integer vertex index",
    ),
    (
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3.5\n",
        "4: column 7",
        "non-integer vertex index",
    ),
    (
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.5 nan\nf 1/1 2/1 3/1\n",
        "4: column 8",
        "'nan' is not a finite number",
    ),
    (
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.5 0.5 inf\nf 1/1 2/1 3/1\n",
        "4: column 12",
        "'inf' is not a finite number",
    ),
    (
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.5 0.5 0 1\n",
        "4:",
        "texture coordinate needs 1, 2 or 3 numbers, found 4",
    ),
    (
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 nan\n",
        "4: column 8",
        "'nan' is not a finite number",
    ),
    (
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 1\n",
        "4:",
        "normal needs 3 numbers, found 2",
    ),
    (
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n",
        "4: column 3",
        "indices start at 1",
    ),
    (
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -4 -2 -1\n",
        "4: column 3",
        "vertex index -4 is out of range",
    ),
    (
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1 2/1 3\n",
        "5: column 5",
        "mixes forms",
    ),
    (
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf 1/1 2//1 3/1\n",
        "6: column 7",
        "mixes forms",
    ),
    (
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//1 2//1 3//1\n",
        "4: column 3",
        "normal index 1 is out of range",
    ),
    (
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/ 2/ 3/\n",
        "4: column 3",
        "empty texture coordinate index",
    ),
    (
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1// 2// 3//\n",
        "4: column 3",
        "empty normal index",
    ),
    (
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1/1/1 2 3\n",
        "4: column 3",
        "is not v, v/vt, v//vn or v/vt/vn",
    ),
    (
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf /1 2 3\n",
        "4: column 3",
        "is not v, v/vt, v//vn or v/vt/vn",
    ),
    (
        "v 0 0 0\nv 1e10 0 0\nv 0 1 0\nf 1 2 3\n",
        "2: column 3",
        "of magnitude at most 1e9",
    ),
    ("v 0 0 0\nv 1 0 0 1 1\n", "2:", "found 5"),
    (
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nfoo 1 2 3\nf 1 2 3\n",
        "4: column 1",
        "'foo' is not an OBJ statement",
    ),
    (
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999999999999\n",
        "4: column 7",
        "non-integer vertex index",
    ),
    (
        "v 0 0 0\nv 1 0 0\nv 0 x 0\nf 1 2 3\n",
        "3: column 5",
        "'x' is not a number",
    ),
];

#[test]
fn every_bad_obj_is_refused_with_its_file_line_and_column() {
    let f = Path::new("bad.obj");
    for (text, at, fragment) in BAD_OBJ {
        let e = validate_obj(f, text).unwrap_err().to_string();
        // `at` is "LINE:" or "LINE: column COL".
        let (line, col) = at.split_once(" column ").unwrap_or((at, ""));
        let line = line.trim_end_matches(':');
        assert!(
            e.starts_with(&format!("bad.obj:{line}: ")),
            "{text:?}: {e:?} should start with bad.obj:{line}: "
        );
        if !col.is_empty() {
            assert!(
                e.contains(&format!("(column {col})")),
                "{text:?}: {e:?} should name column {col}"
            );
        }
        assert!(
            e.contains(fragment),
            "{text:?}: {e:?} should say {fragment:?}"
        );
        // The loader is the same parser: it refuses the same way.
        assert_eq!(parse_obj(f, text).unwrap_err().to_string(), e);
    }
    let e = validate_obj(f, TRI).unwrap_err().to_string();
    assert_eq!(e, "bad.obj: no faces (3 vertices): nothing to render");
    let e = validate_obj(f, "v 1 1 1\nv 1 1 1\nv 1 1 1\nf 1 2 3\n")
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("bad.obj: every face's vertices are at one point"),
        "{e}"
    );
    let e = validate_obj(f, "v 1 2 3 4 5 6 7 8 9 10 11\n")
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("bad.obj:1: vertex needs 3, 4, 6 or 7 numbers, found 11"),
        "{e}"
    );
    let e = load_obj(Path::new("/nonexistent/face.obj"))
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("/nonexistent/face.obj: cannot read"), "{e}");
}

/// Valid OBJ texts and (triangles, has uvs) they load to.
pub const GOOD_OBJ: &[(&str, usize, bool)] = &[
    // A UTF-8 byte-order mark before the first statement (refused before; review of issue 11).
    ("\u{feff}v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", 1, false),
    (
        "v 0.1 0.2 0.3 # note\nv 1 0 0 #\nv 0 1 0\nf 1 2 3 # a face\n",
        1,
        false,
    ),
    (
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0 0\nvt 1 0 0\nvt 0 1 0\nf 1/1 2/2 3/3\n",
        1,
        true,
    ),
    (
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.5\nf 1/1 2/1 3/1\n",
        1,
        true,
    ),
    (
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\n",
        1,
        false,
    ),
    (
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf 1/1/1 2/1/1 3/1/1\n",
        1,
        true,
    ),
    ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\n", 1, false),
    (
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf -3/-1/-1 -2/-1/-1 -1/-1/-1\n",
        1,
        true,
    ),
    (
        "mtllib /dev/zero\no thing\ng group\ns 1\nusemtl skin\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\ns off\nl 1 2\np 1\n",
        1,
        false,
    ),
    (
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv -0.5 0.5 0\nf 1 2 3 4 5\n",
        3,
        false,
    ),
    ("v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nf 1 2 3\r\n", 1, false),
    ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 \\\n 2 3\n", 1, false),
    (
        "v 0 0 0 1\nv 1 0 0 1 0.5 0.5 0.5\nv 0 1 0 0.2 0.3 0.4\nf 1 2 3\n",
        1,
        false,
    ),
    (
        "\n\n# only a comment\n   \nv 0 0 0\n\tv 1 0 0\nv 0 1 0\nf\t1 2  3\n",
        1,
        false,
    ),
    (
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 0\nf 1//1 2//1 3//1\n",
        1,
        false,
    ),
];

#[test]
fn every_valid_obj_form_loads() {
    let f = Path::new("good.obj");
    for (text, triangles, uvs) in GOOD_OBJ {
        let m = parse_obj(f, text).unwrap_or_else(|e| panic!("{text:?}: {e}"));
        assert_eq!(m.triangles.len(), *triangles, "{text:?}");
        assert_eq!(!m.uvs.is_empty(), *uvs, "{text:?}");
        assert!(m.positions.iter().all(|p| p.is_finite()), "{text:?}");
        assert!(
            m.normals
                .iter()
                .all(|n| n.is_finite() && (n.length() - 1.0).abs() < 1e-4),
            "{text:?}: every normal is a unit vector"
        );
    }
}

#[test]
fn a_mesh_is_read_once_so_a_named_pipe_works() {
    let fifo = tmp("face.fifo");
    let _ = std::fs::remove_file(&fifo);
    let ok = std::process::Command::new("mkfifo")
        .arg(&*fifo)
        .status()
        .unwrap();
    assert!(ok.success());
    // Read the text before anything can block: a missing file fails here, not in a writer
    // thread that never opens the FIFO (which left the reader below waiting forever).
    let text = std::fs::read_to_string(face_path()).unwrap();
    let writer = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::write(&fifo, text).unwrap())
    };
    // The read runs on its own thread with a bounded wait: a reader stuck on the FIFO fails
    // the test instead of hanging the suite (the blocked thread ends with the test process).
    let (tx, rx) = std::sync::mpsc::channel();
    {
        let fifo = fifo.clone();
        std::thread::spawn(move || tx.send(load_obj(&fifo)).unwrap());
    }
    let m = rx
        .recv_timeout(std::time::Duration::from_secs(120))
        .expect("reading the FIFO finishes within 120 s")
        .expect("a FIFO is read once");
    writer.join().unwrap();
    std::fs::remove_file(&fifo).unwrap();
    let direct = load_obj(&face_path()).unwrap();
    assert_eq!(m.triangles.len(), direct.triangles.len());
    assert!(m.triangles.len() > 800);
}

fn face_path() -> PathBuf {
    PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/data/canonical_face_model.obj"
    ))
}

fn crc32(bytes: &[u8]) -> u32 {
    let mut c = !0u32;
    for &b in bytes {
        c ^= u32::from(b);
        for _ in 0..8 {
            c = if c & 1 != 0 {
                0xedb8_8320 ^ (c >> 1)
            } else {
                c >> 1
            };
        }
    }
    !c
}

/// A tiny PNG whose header declares `w` x `h` pixels (RGB, 8-bit) and whose data is short.
fn png_declaring(w: u32, h: u32) -> Vec<u8> {
    let mut out = b"\x89PNG\r\n\x1a\n".to_vec();
    let mut chunk = |kind: &[u8], data: &[u8]| {
        out.extend((data.len() as u32).to_be_bytes());
        let mut body = kind.to_vec();
        body.extend(data);
        out.extend(&body);
        out.extend(crc32(&body).to_be_bytes());
    };
    let mut ihdr = w.to_be_bytes().to_vec();
    ihdr.extend(h.to_be_bytes());
    ihdr.extend([8, 2, 0, 0, 0]);
    chunk(b"IHDR", &ihdr);
    chunk(b"IDAT", &[0x78, 0x9c, 0x03, 0x00, 0x00, 0x00, 0x00, 0x01]);
    chunk(b"IEND", &[]);
    out
}

#[test]
fn a_texture_declaring_huge_dimensions_is_refused_before_decoding() {
    let path = tmp("huge.png");
    std::fs::write(&path, png_declaring(20000, 20000)).unwrap();
    let e = Texture::load(&path).unwrap_err().to_string();
    assert!(e.starts_with(&path.display().to_string()), "{e}");
    assert!(e.contains("declares 20000x20000 pixels"), "{e}");
    // The CLI tests use the same file, checked in.
    let fixture = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/declares-20000x20000.png"
    );
    assert_eq!(std::fs::read(fixture).unwrap(), png_declaring(20000, 20000));
    // Within the caps, the same kind of file is decoded (and fails on its short data, with
    // the texture's name).
    std::fs::write(&path, png_declaring(4, 4)).unwrap();
    let e = Texture::load(&path).unwrap_err().to_string();
    assert!(e.contains("cannot read the texture"), "{e}");
    std::fs::remove_file(&path).unwrap();
}

#[test]
fn lights_that_cannot_render_finitely_are_refused() {
    for bad in [
        "dir:0,0,1:3e38,3e38,3e38:3e38",
        "dir:0,0,1:1,1,1:3e38",
        "dir:0,0,1:1e4,1,1:1e3",
        "point:1e30,0,0",
        "dir:0,0,1:nan,1,1",
    ] {
        let e = Light::parse(bad).unwrap_err().to_string();
        assert!(
            e.contains("at most 1e6") || e.contains("not a number"),
            "{bad}: {e}"
        );
    }
    // Tiny but non-zero directions are fine (scale-safe normalisation).
    let l = Light::parse("dir:1e-30,0,1e-30").unwrap();
    let LightKind::Directional { to_light } = l.kind else {
        panic!("a directional light")
    };
    assert!((to_light - Vec3::new(1.0, 0.0, 1.0).normalize()).length() < 1e-6);
    assert!(Light::parse("dir:0,0,1:1,1,1:1e6").is_ok());
}

#[test]
fn no_nan_or_inf_reaches_a_file() {
    let mut film = Film::new(4, 4);
    film.pixels[5] = Vec3::new(f32::NAN, 0.0, 0.0);
    film.pixels[9] = Vec3::splat(f32::INFINITY);
    for ext in ["png", "exr"] {
        let out = tmp(&format!("nan.{ext}"));
        let e = film.save(&out, 1.0).unwrap_err().to_string();
        assert!(
            e.contains("2 non-finite pixels") && e.contains("x = 1, y = 1"),
            "{e}"
        );
        assert!(!out.exists());
    }
    // The largest accepted light on a sharp highlight still renders finitely.
    let mut spec = SceneSpec::new();
    spec.lights = vec![Light::parse("dir:0,0,1:1,1,1:1e6").unwrap()];
    spec.ks = 1e3;
    let loaded = setup::load(&spec).unwrap();
    let sharp = ModelSpec::parse("cook-torrance", &[("alpha", "0.01")]).unwrap();
    let specular = Arc::new(Specular::new(&sharp).unwrap());
    let scene = setup::scene(&spec, &loaded, specular);
    let film = render(&scene, &opts(32, 32, 1), &|_, _| {}).unwrap();
    film.check_finite().unwrap();
}

fn opts(w: u32, h: u32, spp: u32) -> Options {
    Options {
        width: w,
        height: h,
        spp,
        shading: Shading::Batch,
        sampler: fastbrdf_render::render::Sampler::default(),
        aa: fastbrdf_render::render::Antialias::default(),
    }
}

#[test]
fn exr_is_scanline_zip_linear_and_unscaled_by_exposure() {
    let mut film = Film::new(5, 3);
    for (i, p) in film.pixels.iter_mut().enumerate() {
        *p = Vec3::new(i as f32 * 0.25, 3.5, 1e3);
    }
    let out = tmp("film.exr");
    film.save(&out, 4.0).unwrap();
    let meta = exr::meta::MetaData::read_from_file(&out, true).unwrap();
    let header = &meta.headers[0];
    assert_eq!(header.compression, exr::compression::Compression::ZIP16);
    assert_eq!(header.blocks, exr::meta::BlockDescription::ScanLines);
    let img = exr::prelude::read_first_rgba_layer_from_file(
        &out,
        |res, _| vec![[0f32; 3]; res.width() * res.height()],
        |px: &mut Vec<[f32; 3]>, pos, (r, g, b, _a): (f32, f32, f32, f32)| {
            px[pos.y() * 5 + pos.x()] = [r, g, b]
        },
    )
    .unwrap();
    let px = &img.layer_data.channel_data.pixels;
    for (i, p) in film.pixels.iter().enumerate() {
        assert_eq!(
            px[i],
            p.to_array(),
            "pixel {i}: linear radiance, exposure not applied"
        );
    }
    std::fs::remove_file(&out).unwrap();
}

#[test]
fn png_carries_an_srgb_chunk() {
    let film = Film::new(3, 2);
    let out = tmp("film.png");
    film.save(&out, 1.0).unwrap();
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&out).unwrap()));
    let reader = decoder.read_info().unwrap();
    assert!(reader.info().srgb.is_some(), "an sRGB chunk");
    std::fs::remove_file(&out).unwrap();
}

#[test]
fn a_comparison_is_capped_as_a_whole_before_rendering() {
    // Each cell is within the film caps; the grid or the work is not.
    let e = compare::check_compare(40, 8192, 1, 1)
        .unwrap_err()
        .to_string();
    assert!(e.contains("the comparison picture would be"), "{e}");
    let e = compare::check_compare(2, 2048, 2048, 16)
        .unwrap_err()
        .to_string();
    assert!(e.contains("samples"), "{e}");
    let e = compare::check_compare(1000, 16, 16, 1)
        .unwrap_err()
        .to_string();
    assert!(e.contains("1 to 64"), "{e}");
    compare::check_compare(4, 384, 384, 3).unwrap();
    // grid() refuses rather than overflowing u32.
    let rows = vec![Vec::new(), Vec::new()];
    let e = compare::grid(&rows, u32::MAX, u32::MAX, None)
        .unwrap_err()
        .to_string();
    assert!(e.contains("too large"), "{e}");
}

#[test]
fn the_linear_metrics_see_the_highlight_that_clipping_hides() {
    // rational overshoots the highlight (above 1.0, clipped in 8-bit); cubic-rational does not.
    let spec = SceneSpec::new();
    let loaded = setup::load(&spec).unwrap();
    let film = |id: &str| {
        let s = Arc::new(Specular::new(&ModelSpec::parse(id, &[("n", "100")]).unwrap()).unwrap());
        render(
            &setup::scene(&spec, &loaded, s),
            &opts(96, 96, 1),
            &|_, _| {},
        )
        .unwrap()
    };
    let (r, a, b) = (film("pow"), film("rational"), film("cubic-rational"));
    let s = |f: &Film| compare::metrics("m", &r.to_srgb8(1.0), &f.to_srgb8(1.0), 96, 96);
    let (la, lb) = (
        compare::linear_metrics(&r, &a, 1.0),
        compare::linear_metrics(&r, &b, 1.0),
    );
    // On 8-bit sRGB the two score the same (to 1%); on the linear film rational is worse by
    // more than 10%.
    assert!(
        (s(&a).rmse - s(&b).rmse).abs() <= 0.01 * s(&b).rmse,
        "{} {}",
        s(&a).rmse,
        s(&b).rmse
    );
    assert!(
        la.rmse > 1.1 * lb.rmse,
        "linear RMSE: rational {} cubic-rational {}",
        la.rmse,
        lb.rmse
    );
    assert!(la.psnr < lb.psnr);
    assert_eq!(la.peak, lb.peak);
    assert!(
        la.peak > 1.0,
        "the reference's highlight exceeds 1.0: {}",
        la.peak
    );
    let same = compare::linear_metrics(&r, &r, 1.0);
    assert!(same.rmse == 0.0 && same.psnr.is_infinite() && same.flip_reinhard == 0.0);
}

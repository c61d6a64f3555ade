//! Charts, PNG and SVG at 1200x800 (plotters): line charts with a title, axis labels and a
//! legend, on a linear or logarithmic y axis, and equal-aspect "polar" lobe plots.
//!
//! Text uses an embedded DejaVu Sans (plotters' `ab_glyph`), so plots render on machines
//! without fonts. Files are written to a temporary name and renamed: an error never leaves a
//! half-written picture.

use plotters::prelude::*;
use std::path::{Path, PathBuf};
use std::sync::Once;

/// Width and height of every chart, in pixels.
pub const SIZE: (u32, u32) = (1200, 800);

static FONT: Once = Once::new();

fn register_font() {
    FONT.call_once(|| {
        let bytes: &'static [u8] = include_bytes!("../assets/DejaVuSans.ttf");
        // A failure here would be a corrupt embedded file: the charts would lack text only.
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, bytes);
    });
}

/// One named curve.
#[derive(Clone, Debug)]
pub struct Series {
    pub name: String,
    pub points: Vec<(f64, f64)>,
}

impl Series {
    /// A curve from a name and points.
    pub fn new(name: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self {
            name: name.into(),
            points,
        }
    }
}

/// A line chart.
#[derive(Clone, Debug)]
pub struct Chart {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub series: Vec<Series>,
    /// Logarithmic y axis (non-positive values are dropped).
    pub log_y: bool,
    /// Logarithmic x axis (non-positive values are dropped): sweeps over n to 1e5.
    pub log_x: bool,
    /// Equal scales on both axes (polar lobe plots).
    pub equal_aspect: bool,
}

const COLORS: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(23, 190, 207),
];

fn bounds(c: &Chart) -> ((f64, f64), (f64, f64)) {
    let pts = c
        .series
        .iter()
        .flat_map(|s| s.points.iter())
        .filter(|(x, y)| {
            x.is_finite() && y.is_finite() && (!c.log_y || *y > 0.0) && (!c.log_x || *x > 0.0)
        });
    let (mut x0, mut x1, mut y0, mut y1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for &(x, y) in pts {
        (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
    }
    if !x0.is_finite() {
        return ((0.0, 1.0), (if c.log_y { 1e-3 } else { 0.0 }, 1.0));
    }
    if x1 <= x0 {
        x1 = if c.log_x { x0 * 10.0 } else { x0 + 1.0 };
    }
    if c.log_y {
        y0 = y0.max(y1 * 1e-12);
        if y1 <= y0 {
            y1 = y0 * 10.0;
        }
        return ((x0, x1), (y0 / 1.5, y1 * 1.5));
    }
    if y1 <= y0 {
        y1 = y0 + 1.0;
    }
    let pad = 0.05 * (y1 - y0);
    if c.equal_aspect {
        // Make the data ranges match the plot area's aspect.
        let (w, h) = (x1 - x0, y1 - y0 + 2.0 * pad);
        let aspect = 1060.0 / 640.0;
        if w / h < aspect {
            let extra = (h * aspect - w) / 2.0;
            return ((x0 - extra, x1 + extra), (y0 - pad, y1 + pad));
        }
        let extra = (w / aspect - h) / 2.0;
        return ((x0, x1), (y0 - pad - extra, y1 + pad + extra));
    }
    (
        (x0, x1),
        (
            y0.min(0.0)
                .min(y0 - pad)
                .max(if y0 >= 0.0 { 0.0 } else { f64::NEG_INFINITY }),
            y1 + pad,
        ),
    )
}

macro_rules! draw_chart {
    ($root:expr, $c:expr, $xr:expr, $yr:expr) => {{
        let mut chart = ChartBuilder::on(&$root)
            .caption(&$c.title, ("sans-serif", 30))
            .margin(24)
            .x_label_area_size(60)
            .y_label_area_size(90)
            .build_cartesian_2d($xr, $yr)
            .map_err(|e| e.to_string())?;
        chart
            .configure_mesh()
            .x_desc($c.x_label.as_str())
            .y_desc($c.y_label.as_str())
            .label_style(("sans-serif", 18))
            .axis_desc_style(("sans-serif", 22))
            .draw()
            .map_err(|e| e.to_string())?;
        for (i, s) in $c.series.iter().enumerate() {
            let color = COLORS[i % COLORS.len()];
            let pts: Vec<(f64, f64)> = s
                .points
                .iter()
                .copied()
                .filter(|(x, y)| {
                    x.is_finite()
                        && y.is_finite()
                        && (!$c.log_y || *y > 0.0)
                        && (!$c.log_x || *x > 0.0)
                })
                .collect();
            chart
                .draw_series(LineSeries::new(pts, color.stroke_width(3)))
                .map_err(|e| e.to_string())?
                .label(s.name.as_str())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 30, y)], color.stroke_width(3))
                });
        }
        chart
            .configure_series_labels()
            .label_font(("sans-serif", 20))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .position(SeriesLabelPosition::UpperRight)
            .draw()
            .map_err(|e| e.to_string())?;
    }};
}

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    c: &Chart,
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let ((x0, x1), (y0, y1)) = bounds(c);
    match (c.log_x, c.log_y) {
        (false, true) => draw_chart!(root, c, x0..x1, (y0..y1).log_scale()),
        (false, false) => draw_chart!(root, c, x0..x1, y0..y1),
        (true, true) => draw_chart!(root, c, (x0..x1).log_scale(), (y0..y1).log_scale()),
        (true, false) => draw_chart!(root, c, (x0..x1).log_scale(), y0..y1),
    }
    root.present().map_err(|e| e.to_string())?;
    Ok(())
}

/// Why a chart could not be saved: drawing it failed, or writing a file failed.
#[derive(Debug)]
pub enum SaveError {
    /// Drawing or encoding the picture failed (nothing was written).
    Draw(String),
    /// A file could not be written (nothing was left behind).
    Io(fastbrdf_io::IoError),
}

impl std::fmt::Display for SaveError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SaveError::Draw(e) => write!(f, "cannot draw the chart: {e}"),
            SaveError::Io(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for SaveError {}

impl From<fastbrdf_io::IoError> for SaveError {
    fn from(e: fastbrdf_io::IoError) -> Self {
        SaveError::Io(e)
    }
}

/// A chart drawn in memory: the PNG bytes and the SVG text.
pub struct Drawn {
    pub png: Vec<u8>,
    pub svg: String,
}

/// Draws `c` as PNG and SVG in memory (nothing is written).
pub fn render(c: &Chart) -> Result<Drawn, String> {
    render_both(|root| draw(root, c), |root| draw(root, c))
}

/// The folder and file stem of `base` (a path without extension).
fn split_base(base: &Path) -> (PathBuf, String) {
    let dir = base
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .map_or_else(|| PathBuf::from("."), Path::to_path_buf);
    let stem = base
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "plot".into());
    (dir, stem)
}

/// Stages a drawn chart as `stem.png` and `stem.svg` in `set`; returns both destination paths.
pub fn stage(
    set: &mut fastbrdf_io::OutputSet,
    d: &Drawn,
    stem: &str,
) -> Result<[PathBuf; 2], fastbrdf_io::IoError> {
    let (png, svg) = (format!("{stem}.png"), format!("{stem}.svg"));
    set.write(&png, &d.png)?;
    set.write(&svg, d.svg.as_bytes())?;
    Ok([set.dir().join(png), set.dir().join(svg)])
}

/// Writes drawn charts, each `(base, drawing)` as `base.png` and `base.svg`, all or nothing:
/// every file is staged first and moved into place only when all were written, so a failure
/// leaves no file and no temporary behind. All bases must share one folder.
pub fn write_all(items: &[(&Path, &Drawn)]) -> Result<Vec<PathBuf>, fastbrdf_io::IoError> {
    let Some((first, _)) = items.first() else {
        return Ok(vec![]);
    };
    let (dir, _) = split_base(first);
    let mut set = fastbrdf_io::OutputSet::new(&dir)?;
    for (base, d) in items {
        let (_, stem) = split_base(base);
        stage(&mut set, d, &stem)?;
    }
    set.commit()
}

/// Draws a picture twice, on a bitmap and on an SVG string, in memory (the drawing code is
/// passed once per backend type).
fn render_both(
    bitmap: impl FnOnce(DrawingArea<BitMapBackend<'_>, plotters::coord::Shift>) -> Result<(), String>,
    svg_draw: impl FnOnce(DrawingArea<SVGBackend<'_>, plotters::coord::Shift>) -> Result<(), String>,
) -> Result<Drawn, String> {
    register_font();
    let (w, h) = SIZE;
    let mut rgb = vec![255u8; (w * h * 3) as usize];
    bitmap(BitMapBackend::with_buffer(&mut rgb, SIZE).into_drawing_area())?;
    let mut png = Vec::new();
    image::codecs::png::PngEncoder::new(&mut png)
        .write_image_impl(&rgb, w, h)
        .map_err(|e| format!("PNG encoding: {e}"))?;
    let mut svg = String::new();
    svg_draw(SVGBackend::with_string(&mut svg, SIZE).into_drawing_area())?;
    Ok(Drawn { png, svg })
}

trait WritePng {
    fn write_image_impl(self, rgb: &[u8], w: u32, h: u32) -> image::ImageResult<()>;
}

impl<W: std::io::Write> WritePng for image::codecs::png::PngEncoder<W> {
    fn write_image_impl(self, rgb: &[u8], w: u32, h: u32) -> image::ImageResult<()> {
        use image::ImageEncoder;
        self.write_image(rgb, w, h, image::ExtendedColorType::Rgb8)
    }
}

/// A labelled point of a scatter plot; `highlight` draws it filled and larger.
#[derive(Clone, Debug)]
pub struct Point {
    pub label: String,
    pub x: f64,
    pub y: f64,
    pub highlight: bool,
}

/// A scatter plot on log-log axes with labelled points and a line through `front` (sorted by
/// x), written as `base.png` and `base.svg` (both or neither).
pub fn save_scatter(
    title: &str,
    x_label: &str,
    y_label: &str,
    front: &[(f64, f64)],
    points: &[Point],
    base: &Path,
) -> Result<[PathBuf; 2], SaveError> {
    let d = render_scatter(title, x_label, y_label, front, points).map_err(SaveError::Draw)?;
    let files = write_all(&[(base, &d)])?;
    Ok([files[0].clone(), files[1].clone()])
}

/// [`save_scatter`] drawn in memory.
pub fn render_scatter(
    title: &str,
    x_label: &str,
    y_label: &str,
    front: &[(f64, f64)],
    points: &[Point],
) -> Result<Drawn, String> {
    let finite: Vec<&Point> = points
        .iter()
        .filter(|p| p.x > 0.0 && p.y > 0.0 && p.x.is_finite() && p.y.is_finite())
        .collect();
    let (x0, x1) = finite.iter().fold((f64::INFINITY, 0.0f64), |(a, b), p| {
        (a.min(p.x), b.max(p.x))
    });
    let (y0, y1) = finite.iter().fold((f64::INFINITY, 0.0f64), |(a, b), p| {
        (a.min(p.y), b.max(p.y))
    });
    let (x0, x1, y0, y1) = if finite.is_empty() {
        (0.1, 1.0, 1e-3, 1.0)
    } else {
        (x0 / 1.3, x1 * 2.5, y0 / 1.6, y1 * 1.6)
    };
    fn draw<DB: DrawingBackend>(
        root: DrawingArea<DB, plotters::coord::Shift>,
        t: &str,
        xl: &str,
        yl: &str,
        front: &[(f64, f64)],
        pts: &[&Point],
        r: (f64, f64, f64, f64),
    ) -> Result<(), String>
    where
        DB::ErrorType: 'static,
    {
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let mut chart = ChartBuilder::on(&root)
            .caption(t, ("sans-serif", 28))
            .margin(24)
            .x_label_area_size(60)
            .y_label_area_size(90)
            .build_cartesian_2d((r.0..r.1).log_scale(), (r.2..r.3).log_scale())
            .map_err(|e| e.to_string())?;
        chart
            .configure_mesh()
            .x_desc(xl)
            .y_desc(yl)
            .x_labels(8)
            .y_labels(8)
            .x_label_formatter(&|v| tick(*v))
            .y_label_formatter(&|v| tick(*v))
            .label_style(("sans-serif", 18))
            .axis_desc_style(("sans-serif", 22))
            .draw()
            .map_err(|e| e.to_string())?;
        chart
            .draw_series(LineSeries::new(front.to_vec(), COLORS[1].stroke_width(3)))
            .map_err(|e| e.to_string())?
            .label("Pareto front")
            .legend(|(x, y)| {
                PathElement::new(vec![(x, y), (x + 30, y)], COLORS[1].stroke_width(3))
            });
        for p in pts {
            let style = if p.highlight {
                COLORS[1].filled()
            } else {
                COLORS[0].filled()
            };
            chart
                .draw_series(std::iter::once(Circle::new(
                    (p.x, p.y),
                    if p.highlight { 7 } else { 5 },
                    style,
                )))
                .map_err(|e| e.to_string())?;
            chart
                .draw_series(std::iter::once(Text::new(
                    p.label.clone(),
                    (p.x * 1.04, p.y * 1.05),
                    ("sans-serif", 15).into_font(),
                )))
                .map_err(|e| e.to_string())?;
        }
        chart
            .configure_series_labels()
            .label_font(("sans-serif", 20))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(|e| e.to_string())?;
        root.present().map_err(|e| e.to_string())?;
        Ok(())
    }
    let r = (x0, x1, y0, y1);
    render_both(
        |root| draw(root, title, x_label, y_label, front, &finite, r),
        |root| draw(root, title, x_label, y_label, front, &finite, r),
    )
}

/// A log axis's tick value with at most three significant digits (plotters prints the f64
/// it computes, `0.30000000000000004`).
fn tick(v: f64) -> String {
    if !(v.is_finite() && v > 0.0) {
        return format!("{v}");
    }
    let decimals = (2 - v.log10().floor() as i32).max(0) as usize;
    let s = format!("{v:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

#[cfg(test)]
mod tests {
    use super::tick;

    /// Log-axis ticks print as people write them, not as the f64 plotters computes.
    #[test]
    fn ticks_have_at_most_three_significant_digits() {
        assert_eq!(tick(0.300_000_000_000_000_04), "0.3");
        assert_eq!(tick(0.7000000000000001), "0.7");
        assert_eq!(tick(1.0), "1");
        assert_eq!(tick(0.01), "0.01");
        assert_eq!(tick(0.012_345_6), "0.0123");
        assert_eq!(tick(2500.0), "2500");
        assert_eq!(tick(12.5), "12.5");
    }
}

//! BRDF Explorer `.brdf` files: sliders (linear, or `log10_<name>` for wide ranges, each grid
//! through the export's value), the `n` slider's top for lobes, and the file itself.

use super::{Lang, call_of, exported_name, glsl_functions};
use crate::context::GpuError;
use crate::spec::Instance;
use fastbrdf::model::{Kind, Metric, Zone};
use fastbrdf::params::ParamKind;
use std::fmt::Write as _;

/// One BRDF Explorer slider: the `::begin parameters` line and the GLSL that turns the
/// slider's value into the model parameter.
#[derive(Clone, Debug, PartialEq)]
pub struct Slider {
    /// The uniform BRDF Explorer declares: the parameter's name, or `log10_<name>`.
    pub uniform: String,
    /// The slider's ends as written (f32 values, printed so that they parse back exactly).
    pub lo: f32,
    pub hi: f32,
    /// The default as written: already what BRDF Explorer's text field shows (6 significant
    /// digits), so the value it starts with is the value of one slider position exactly.
    pub default_text: String,
    /// The GLSL expression of the parameter (a name, or a clamped mapping of the uniform).
    pub param: String,
    /// Whether the slider is logarithmic.
    pub log: bool,
}

/// How far a lobe's argument (its cosine) may lie from the CPU's in a shader, in units of
/// 2^-24 (the f32 spacing just below 1): the parity rule of `tests/parity.rs` for Phong and
/// Blinn-Phong, whose lobe argument goes through three normalisations in f32. Near its peak a
/// lobe of exponent n moves by about n times this, so BRDF Explorer's `n` slider stops where
/// that stays within the lobe's documented error ([`lobe_n_max`]).
pub const LOBE_ARG_ULPS: f64 = 32.0;

/// The largest change of lobe `lobe`'s value at exponent `n`, relative to its peak, when its
/// cosine moves by [`LOBE_ARG_ULPS`] units of 2^-24 (on cosines 1 - 2^-24 .. 0, log-spaced,
/// away from its cuts and kinks, where a jump is a jump whatever the precision).
pub fn lobe_argument_error(lobe: &str, n: f64) -> Result<f64, GpuError> {
    let l = fastbrdf::registry::lobe::<f64>(lobe, n)?;
    let peak = l.eval(1.0).abs().max(f64::MIN_POSITIVE);
    let u = LOBE_ARG_ULPS * 2f64.powi(-24);
    let mut marks = l.kinks();
    marks.push(l.zero_below());
    let mut worst = 0.0f64;
    for i in 0..=1200 {
        let c = 1.0 - 2f64.powf(-24.0 + 24.0 * i as f64 / 1200.0);
        if marks.iter().any(|&m| m > 0.0 && (c - m).abs() <= 2.0 * u) {
            continue;
        }
        let v = l.eval(c);
        for d in [(c + u).min(1.0), (c - u).max(0.0)] {
            worst = worst.max((l.eval(d) - v).abs() / peak);
        }
    }
    Ok(worst)
}

/// The error lobe `lobe` documents at exponent `n`: the tightest of its max-abs bounds against
/// its reference on the whole lobe whose `n` range holds `n`; for a lobe that documents none
/// (the reference `pow` itself) the tightest such bound any lobe documents at `n`.
pub fn lobe_tolerance(lobe: &str, n: f64) -> Result<f64, GpuError> {
    let documented = |info: &fastbrdf::ModelInfo| {
        info.bounds
            .iter()
            .filter(|b| b.metric == Metric::MaxAbs && b.zone == Zone::All)
            .filter(|b| b.param.0 == "n" && b.param.1 <= n && n <= b.param.2)
            .map(|b| b.bound)
            .reduce(f64::min)
    };
    let info = &fastbrdf::registry::find(lobe)?.info;
    Ok(documented(info).unwrap_or_else(|| {
        fastbrdf::registry::all()
            .iter()
            .filter(|e| e.info.kind == Kind::Lobe)
            .filter_map(|e| documented(&e.info))
            .fold(f64::INFINITY, f64::min)
    }))
}

/// Where BRDF Explorer's `n` slider of lobe `lobe` stops, in `[min, max]`: the largest n
/// (two significant digits, rounded down) at which [`lobe_argument_error`] stays within
/// [`lobe_tolerance`], so that the f32 shader's lobe stays within the lobe's documented error
/// on the whole slider. Issue 27: `power4-tuned` at n = 1e5 was off by 0.82 of its peak in
/// BRDF Explorer.
pub fn lobe_n_max(lobe: &str, min: f64, max: f64) -> Result<f64, GpuError> {
    let holds =
        |n: f64| Ok::<_, GpuError>(lobe_argument_error(lobe, n)? <= lobe_tolerance(lobe, n)?);
    if holds(max)? {
        return Ok(max);
    }
    // The error grows with n: bisect on log n.
    let (mut lo, mut hi) = (min.ln(), max.ln());
    if !holds(min)? {
        return Ok(min);
    }
    for _ in 0..40 {
        let mid = 0.5 * (lo + hi);
        if holds(mid.exp())? {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let n = lo.exp();
    let scale = 10f64.powf(n.log10().floor() - 1.0);
    Ok(((n / scale).floor() * scale).max(min))
}

/// The largest value BRDF Explorer's slider of parameter `name` reaches in the export of
/// `target` (the shaded instance) at `value`: the documented maximum, or for the exponent of a
/// lobe [`lobe_n_max`] (at least `value`, so that the export's own value stays reachable).
pub fn slider_max(target: &Instance, name: &str, max: f64, value: f64) -> Result<f64, GpuError> {
    let lobe = target
        .params
        .iter()
        .find(|(k, _)| k == "lobe")
        .map(|(_, v)| v.as_str());
    let min = match target
        .info
        .params
        .iter()
        .find(|p| p.name == name)
        .map(|p| p.kind)
    {
        Some(ParamKind::Number { min, .. }) => min,
        _ => return Ok(max),
    };
    match lobe {
        Some(lobe) if name == "n" => Ok(lobe_n_max(lobe, min, max)?.max(value).min(max)),
        _ => Ok(max),
    }
}

/// Parameters spanning at least this ratio (two decades) get a logarithmic slider.
pub const LOG_SLIDER_RATIO: f64 = 100.0;

/// BRDF Explorer's slider positions (`FloatVarWidget`: an integer 0..=1000).
pub const SLIDER_STEPS: u32 = 1000;

/// What BRDF Explorer's text field shows for `x` (`QString::setNum(float)`: 6 significant
/// digits), as text.
pub fn g6(x: f64) -> String {
    let r: f64 = format!("{x:.5e}").parse().unwrap_or(x);
    if r == 0.0 { "0".into() } else { format!("{r}") }
}

/// The value BRDF Explorer uses at slider position `x` of a slider `lo..hi`:
/// `FloatVarWidget::sliderToFloat` (f32: lo + (x / 1000) (hi - lo)), shown in the text field
/// with 6 significant digits and read back from it (`getValue` parses the text).
pub fn slider_value(lo: f32, hi: f32, x: u32) -> f32 {
    let raw = lo + (x as f32 / SLIDER_STEPS as f32) * (hi - lo);
    g6(raw as f64).parse().unwrap_or(raw)
}

/// The f32 nearest to `x` on its side: rounded down (`up` false) or up.
fn f32_toward(x: f64, up: bool) -> f32 {
    let f = x as f32;
    let (fx, bits) = (f as f64, f.to_bits());
    let step = |b: u32| f32::from_bits(b);
    match (up, fx > x, fx < x) {
        (false, true, _) => step(if f > 0.0 { bits - 1 } else { bits + 1 }),
        (true, _, true) => step(if f >= 0.0 { bits + 1 } else { bits - 1 }),
        _ => f,
    }
}

/// A shortest decimal that parses back to `x` (f32).
fn f32_text(x: f32) -> String {
    let t = format!("{x:?}");
    t.strip_suffix(".0").map(str::to_string).unwrap_or(t)
}

/// The slider of parameter `name` in `[min, max]` at this export's `value`.
///
/// BRDF Explorer's sliders are linear with 1001 positions and no other option (its parser
/// reads `float name min max default`; `FloatVarWidget` maps position x to
/// `min + x / 1000 (max - min)`). So a parameter spanning two decades or more gets the slider
/// `log10_<name>` and the shader computes the parameter from it. Every slider's grid is
/// anchored at the export's value: the grid steps by span / 998, with position k at the value,
/// so the ends lie half a step to a step and a half beyond the documented range (the shader
/// clamps to it), and the
/// default text is the value BRDF Explorer computes at position k, so that the default is a
/// slider position and, at that position, the parameter is exactly `value`.
pub fn slider(name: &str, min: f64, max: f64, value: f64) -> Slider {
    let log = min > 0.0 && max / min >= LOG_SLIDER_RATIO;
    let (t, tmin, tmax) = if log {
        (value.log10(), min.log10(), max.log10())
    } else {
        (value, min, max)
    };
    let k_of =
        |step: f64| -> u32 { (((t - tmin) / step + 0.5).ceil().max(0.0) as u32).min(SLIDER_STEPS) };
    // A linear parameter whose value is a position of the plain slider keeps it.
    if !log {
        let (lo, hi) = (min as f32, max as f32);
        let k = ((t - tmin) / (tmax - tmin) * SLIDER_STEPS as f64).round();
        if (0.0..=SLIDER_STEPS as f64).contains(&k)
            && lo as f64 == min
            && hi as f64 == max
            && slider_value(lo, hi, k as u32) as f64 == value
        {
            return Slider {
                uniform: name.into(),
                lo,
                hi,
                default_text: g6(value),
                param: name.into(),
                log,
            };
        }
    }
    // 998 steps span the range: with position k half a step or more above the low end,
    // both ends of the slider lie half a step or more beyond the range, so that the clamp, not
    // the rounding of the mapping, decides that the ends reach min and max.
    let step = (tmax - tmin) / (SLIDER_STEPS - 2) as f64;
    let k = k_of(step);
    let lo = f32_toward(t - k as f64 * step, false);
    let hi = f32_toward(lo as f64 + SLIDER_STEPS as f64 * step, true);
    let anchor = slider_value(lo, hi, k);
    let s0 = g6(anchor as f64);
    // GLSL float literals (`{:?}` keeps the `.0`), parsing to the same f32.
    let v = format!("{:?}", value as f32);
    let (a, b) = (format!("{:?}", min as f32), format!("{:?}", max as f32));
    // `u - s0`, written `u + 0.86` for s0 = -0.86: exactly 0 at the default either way.
    let minus_s0 = match s0.strip_prefix('-') {
        Some(pos) => format!("+ {pos}"),
        None => format!("- {s0}"),
    };
    let uniform = if log {
        format!("log10_{name}")
    } else {
        format!("{name}_slider")
    };
    let param = if log {
        format!("clamp({v} * exp2(({uniform} {minus_s0}) * 3.321928), {a}, {b})")
    } else {
        format!("clamp({v} + ({uniform} {minus_s0}), {a}, {b})")
    };
    Slider {
        uniform,
        lo,
        hi,
        default_text: s0,
        param,
        log,
    }
}

impl Slider {
    /// Its line in BRDF Explorer's parameter block: `float <uniform> <lo> <hi> <default>`.
    fn declaration(&self) -> String {
        format!(
            "float {} {} {} {}",
            self.uniform,
            f32_text(self.lo),
            f32_text(self.hi),
            self.default_text
        )
    }
}

/// The `.brdf` file of `target` (the BRDF, Fresnel or shadowing instance BRDF Explorer
/// evaluates): `header`, a slider per parameter its coefficients are computed from (see
/// `slider`), the GLSL functions and `BRDF(L, V, N, X, Y)`.
pub(super) fn brdf_explorer(target: &Instance, header: &str) -> Result<String, GpuError> {
    let f = &exported_name(&target.function, Lang::Glsl);
    let mut sliders = String::new();
    let mut params = String::new();
    let mut extra = String::new();
    let mut capped = String::new();
    for (name, value) in &target.sliders {
        let spec = target
            .info
            .params
            .iter()
            .find(|p| p.name == name)
            .expect("sliders are parameters");
        if let ParamKind::Number { min, max, .. } = spec.kind {
            let top = slider_max(target, name, max, *value)?;
            if top < max {
                let _ = writeln!(
                    capped,
                    "# The {name} slider stops at {top} (the model allows {max}): beyond it a few \
                     f32 roundings of the lobe's cosine move the lobe by more than its documented \
                     error (fastbrdf_gpu::export::lobe_n_max)."
                );
            }
            let s = slider(name, min, top, *value);
            let _ = writeln!(sliders, "{}", s.declaration());
            if s.param == *name {
                let _ = write!(extra, ", {name}");
            } else {
                let _ = writeln!(params, "    float p_{name} = {};", s.param);
                let _ = write!(extra, ", p_{name}");
            }
        }
    }
    // A split-sum term's roughness is an input, not a parameter: one more slider for it.
    if target.info.kind == Kind::Env {
        let (lo, hi) = fastbrdf::params::ALPHA.range();
        let s = slider("alpha", lo, hi, 0.3);
        let _ = writeln!(sliders, "{}", s.declaration());
        let _ = writeln!(params, "    float p_alpha = {};", s.param);
    }
    let body = match target.info.kind {
        Kind::Brdf => format!(
            "{params}    vec3 wi = vec3(dot(L, X), dot(L, Y), dot(L, N));\n    vec3 wo = vec3(dot(V, X), dot(V, Y), dot(V, N));\n    return vec3({f}(wi, wo{extra}));"
        ),
        Kind::Fresnel => {
            format!(
                "{params}    vec3 H = normalize(L + V);\n    return vec3({f}(dot(V, H){extra}));"
            )
        }
        Kind::Shadowing => format!(
            "{params}    vec3 H = normalize(L + V);\n    return vec3({f}(dot(N, V), dot(N, L), dot(N, H), dot(V, H){extra}));"
        ),
        // A split-sum term is a function of the view and the roughness: plotted against the
        // view angle at the `alpha` slider's value.
        Kind::Env => format!("{params}    return vec3({f}(dot(N, V), p_alpha{extra}));"),
        _ => unreachable!("lobes and distributions are shaded through a BRDF"),
    };
    let functions = glsl_functions(&target.module_source(), &call_of(target), target.info.id)?;
    let mut s = String::new();
    s.push_str("analytic\n\n");
    s.push_str(header);
    s.push_str(&capped);
    let _ = write!(
        s,
        "\n::begin parameters\n{sliders}::end parameters\n\n::begin shader\n\n{functions}"
    );
    let _ = write!(
        s,
        "\nvec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y)\n{{\n{body}\n}}\n\n::end shader\n"
    );
    Ok(s)
}

//! The sampling checks: `chi2`, `weight`, `pdf-integral`, `pdf-coverage`, `pdf-sample`.
//!
//! At each angle of `Config::sample_angles_deg`, one `sample` call (in chunks) draws
//! `chi2.samples` directions; `fastbrdf::chi2::bin` histograms them; the pdf is integrated over
//! every bin as `fastbrdf::chi2::expected` does (`sub x sub` cells of Gauss-Legendre 5 x 5
//! points on `pdf sin theta`, the cells doubled until two values agree to 1e-4 relative plus
//! 1e-9), but in rounds: each round evaluates the pdf at every point of every bin not yet
//! settled in one batch. The expected counts are those of the pdf divided by
//! `max(1, integral)`, the no-sample cell against `samples (1 - integral / max(1, integral))`:
//! a pdf whose mass exceeds 1 fails `pdf-integral` alone, and a sampler that draws the wrong
//! shape fails `chi2`.

use super::grid::Pairs;
use super::values::Values;
use super::{At, Batched, Check, Config, dir, num, wo_at};
use fastbrdf::chi2::{bin, gamma_q};
use fastbrdf::sample::Rng;
use std::f64::consts::{FRAC_PI_2, TAU};

/// What one angle found.
struct Angle {
    deg: f64,
    wo: [f64; 3],
    p_value: f64,
    chi2: f64,
    dof: usize,
    integral: f64,
    /// Max relative deviation of the weight, and where (wi, channel).
    weight: (f64, [f64; 3], usize),
    /// Max relative deviation of `pdf(wo, wi)` from the reported pdf, and where.
    pdf: (f64, [f64; 3]),
    samples: usize,
}

pub fn checks(
    m: &Batched,
    set: &Pairs,
    v: &Values,
    cfg: &Config,
    progress: &(dyn Fn(&str) + Sync),
) -> Result<Vec<Check>, String> {
    progress("chi2");
    let tests = cfg.sample_angles_deg.len().max(1);
    let mut angles = Vec::new();
    for (i, &deg) in cfg.sample_angles_deg.iter().enumerate() {
        angles.push(angle(m, deg, i as u64, cfg)?);
    }
    let threshold = cfg.chi2.significance / tests as f64;
    let mut out = vec![chi2_check(&angles, threshold, cfg)];
    progress("weight");
    out.push(weight_check(&angles, cfg));
    progress("pdf-integral");
    out.push(integral_check(&angles, cfg));
    progress("pdf-coverage");
    out.push(coverage(m, set, v, cfg)?);
    progress("pdf-sample");
    out.push(pdf_sample_check(&angles, cfg));
    Ok(out)
}

fn angle(m: &Batched, deg: f64, index: u64, cfg: &Config) -> Result<Angle, String> {
    let c = m.channels;
    let wo = wo_at(deg);
    let n = cfg.chi2.samples;
    let (rt, rp) = (cfg.chi2.res_theta, cfg.chi2.res_phi);
    let mut rng = Rng::new(cfg.chi2.seed ^ (index.wrapping_mul(0x9E37_79B9) << 8));
    let u: Vec<[f64; 2]> = (0..n).map(|_| rng.pair()).collect();
    let s = m.sample_at(wo, &u)?;
    let mut observed = vec![0.0; rt * rp];
    let mut missing = 0.0;
    for k in 0..n {
        match s.valid[k].then(|| bin(s.wi[k], rt, rp)).flatten() {
            Some(b) => observed[b] += 1.0,
            None => missing += 1.0,
        }
    }
    let e = expected(m, wo, cfg)?;
    let integral: f64 = e.iter().sum();
    let scale = n as f64 / integral.max(1.0);
    let mut cells: Vec<(f64, f64)> = observed
        .iter()
        .zip(&e)
        .map(|(&o, &x)| (o, x * scale))
        .collect();
    cells.push((missing, (n as f64 - integral * scale).max(0.0)));
    let (chi2, dof, _, impossible) = fastbrdf::chi2::statistic(&mut cells);
    let p_value = if impossible {
        0.0
    } else if dof == 0 || !chi2.is_finite() {
        if chi2.is_finite() { 1.0 } else { 0.0 }
    } else {
        gamma_q(dof as f64 / 2.0, chi2 / 2.0)
    };

    // The valid draws: weight against f cos / pdf, pdf(wo, wi) against the reported pdf.
    let idx: Vec<usize> = (0..n)
        .filter(|&k| s.valid[k] && s.wi[k].iter().all(|x| x.is_finite()))
        .collect();
    let wi: Vec<[f64; 3]> = idx.iter().map(|&k| s.wi[k]).collect();
    let f = m.eval_at(&wi, wo)?;
    let q = m.pdf_at(wo, &wi)?;
    let mut weight = (0.0, [0.0; 3], 0);
    let mut pdf = (0.0, [0.0; 3]);
    for (r, &k) in idx.iter().enumerate() {
        let p = s.pdf[k];
        let d = if p > 0.0 && p.is_finite() {
            (p - q[r]).abs() / p.max(q[r].abs())
        } else {
            f64::INFINITY
        };
        let d = if d.is_nan() { f64::INFINITY } else { d };
        if d > pdf.0 {
            pdf = (d, s.wi[k]);
        }
        if !(p > 0.0 && p.is_finite()) {
            continue;
        }
        for j in 0..c {
            let want = f[r * c + j] * s.wi[k][2].max(0.0) / p;
            if !want.is_finite() {
                continue;
            }
            let got = s.weight[k * c + j];
            let d = (got - want).abs() / want.abs().max(got.abs());
            let d = if d.is_nan() {
                if got == want { 0.0 } else { f64::INFINITY }
            } else {
                d
            };
            if d > weight.0 {
                weight = (d, s.wi[k], j);
            }
        }
    }
    // A valid draw with a non-finite direction is a reported sample with no direction.
    if let Some(k) = (0..n).find(|&k| s.valid[k] && !s.wi[k].iter().all(|x| x.is_finite())) {
        pdf = (f64::INFINITY, s.wi[k]);
    }
    Ok(Angle {
        deg,
        wo,
        p_value,
        chi2,
        dof,
        integral,
        weight,
        pdf,
        samples: idx.len(),
    })
}

/// The pdf's integral over every bin (row-major in theta), in batched rounds.
fn expected(m: &Batched, wo: [f64; 3], cfg: &Config) -> Result<Vec<f64>, String> {
    let (rt, rp) = (cfg.chi2.res_theta, cfg.chi2.res_phi);
    let mut value = vec![f64::NAN; rt * rp];
    let mut active: Vec<usize> = (0..rt * rp).collect();
    let mut sub = cfg.chi2.sub.max(1);
    let mut first = true;
    while !active.is_empty() {
        let per = sub * sub * 25;
        let mut dirs = Vec::with_capacity(active.len() * per);
        let mut weights = Vec::with_capacity(active.len() * per);
        for &b in &active {
            cells(b / rp, b % rp, rt, rp, sub, &mut dirs, &mut weights);
        }
        let p = m.pdf_at(wo, &dirs)?;
        let mut next = vec![];
        for (a, &b) in active.iter().enumerate() {
            let v: f64 = (a * per..(a + 1) * per).map(|k| weights[k] * p[k]).sum();
            let settled = !first && (v - value[b]).abs() <= 1e-4 * v.abs() + 1e-9;
            value[b] = v;
            if !settled && !(v.is_nan()) {
                next.push(b);
            }
        }
        first = false;
        if sub * 2 > cfg.chi2_max_sub {
            break;
        }
        sub *= 2;
        active = next;
    }
    Ok(value)
}

/// The points and weights of bin `(i, j)` on `sub x sub` cells (`fastbrdf chi2`'s nodes).
fn cells(
    i: usize,
    j: usize,
    rt: usize,
    rp: usize,
    sub: usize,
    dirs: &mut Vec<[f64; 3]>,
    weights: &mut Vec<f64>,
) {
    let dt = FRAC_PI_2 / (rt * sub) as f64;
    let dp = TAU / (rp * sub) as f64;
    fastbrdf::chi2::bin_nodes((i, j), (rt, rp), sub, |w, wtp, st| {
        dirs.push(w);
        weights.push(wtp * st * 0.25 * dt * dp);
    });
}

fn chi2_check(angles: &[Angle], threshold: f64, cfg: &Config) -> Check {
    let w = angles
        .iter()
        .min_by(|a, b| a.p_value.total_cmp(&b.p_value))
        .expect("at least one angle");
    let pass = angles.iter().all(|a| a.p_value > threshold);
    Check::new(
        "chi2",
        pass,
        w.p_value,
        threshold,
        format!(
            "least p-value {} at theta_o = {} deg (chi2 = {}, dof = {}; limit {} = {} / {} angles, Bonferroni; {} samples, {} x {} bins, the pdf divided by max(1, its integral))",
            num(w.p_value),
            num(w.deg),
            num(w.chi2),
            w.dof,
            num(threshold),
            num(cfg.chi2.significance),
            angles.len(),
            cfg.chi2.samples,
            cfg.chi2.res_theta,
            cfg.chi2.res_phi
        ),
    )
    .at(Some(theta_at(w.deg)))
}

fn theta_at(deg: f64) -> At {
    At {
        theta_o_deg: Some(deg),
        ..At::default()
    }
}

fn weight_check(angles: &[Angle], cfg: &Config) -> Check {
    let w = angles
        .iter()
        .max_by(|a, b| a.weight.0.total_cmp(&b.weight.0))
        .expect("at least one angle");
    let n: usize = angles.iter().map(|a| a.samples).sum();
    let pass = angles.iter().all(|a| a.weight.0 <= cfg.weight_tol);
    let (text, at) = located(w.weight.0, w.weight.1, w);
    Check::new(
        "weight",
        pass,
        w.weight.0,
        cfg.weight_tol,
        format!(
            "max |weight - f cos / pdf| = {} relative (limit {}) over {n} samples{text}",
            num(w.weight.0),
            num(cfg.weight_tol),
        ),
    )
    .at(at)
}

/// ` at wi=(..) wo=(..)` and its place, where `value` is not 0.
fn located(value: f64, wi: [f64; 3], a: &Angle) -> (String, Option<At>) {
    if value == 0.0 {
        return (String::new(), None);
    }
    (
        format!(" at wi={} wo={}", dir(wi), dir(a.wo)),
        Some(At {
            wi: Some(wi),
            wo: Some(a.wo),
            theta_o_deg: Some(a.deg),
            channel: None,
        }),
    )
}

fn integral_check(angles: &[Angle], cfg: &Config) -> Check {
    let w = angles
        .iter()
        .max_by(|a, b| a.integral.total_cmp(&b.integral))
        .expect("at least one angle");
    let limit = 1.0 + cfg.pdf_integral_tol;
    let pass = angles.iter().all(|a| a.integral <= limit);
    let per: Vec<String> = angles
        .iter()
        .map(|a| {
            let covers = (a.integral - 1.0).abs() <= cfg.pdf_integral_tol;
            format!(
                "{} deg: {}{}",
                num(a.deg),
                num(a.integral),
                if covers {
                    " (= 1, covers the hemisphere)"
                } else {
                    ""
                }
            )
        })
        .collect();
    Check::new(
        "pdf-integral",
        pass,
        w.integral,
        limit,
        format!(
            "max pdf integral over the hemisphere {} at theta_o = {} deg (limit 1 + {}); {}",
            num(w.integral),
            num(w.deg),
            num(cfg.pdf_integral_tol),
            per.join(", ")
        ),
    )
    .at(Some(theta_at(w.deg)))
}

fn pdf_sample_check(angles: &[Angle], cfg: &Config) -> Check {
    let w = angles
        .iter()
        .max_by(|a, b| a.pdf.0.total_cmp(&b.pdf.0))
        .expect("at least one angle");
    let pass = angles.iter().all(|a| a.pdf.0 <= cfg.pdf_sample_tol);
    let (text, at) = located(w.pdf.0, w.pdf.1, w);
    Check::new(
        "pdf-sample",
        pass,
        w.pdf.0,
        cfg.pdf_sample_tol,
        format!(
            "max |pdf(wo, wi) - reported pdf| = {} relative (limit {}){text}",
            num(w.pdf.0),
            num(cfg.pdf_sample_tol),
        ),
    )
    .at(at)
}

/// Pairs of the value set above the horizon where `f cos` exceeds
/// `coverage_threshold` of its peak and the pdf is not positive.
fn coverage(m: &Batched, set: &Pairs, v: &Values, cfg: &Config) -> Result<Check, String> {
    let idx: Vec<usize> = (0..set.wi.len())
        .filter(|&k| set.wi[k][2] > 0.0 && set.wo[k][2] > 0.0)
        .collect();
    let wi: Vec<[f64; 3]> = idx.iter().map(|&k| set.wi[k]).collect();
    let wo: Vec<[f64; 3]> = idx.iter().map(|&k| set.wo[k]).collect();
    let p = m.pdf(&wo, &wi)?;
    let fc: Vec<f64> = idx.iter().map(|&k| v.max_at(k) * set.wi[k][2]).collect();
    let peak = fc
        .iter()
        .filter(|x| x.is_finite())
        .fold(0.0f64, |a, &b| a.max(b));
    let mut worst = (0.0, None);
    let mut count = 0;
    for (r, &k) in idx.iter().enumerate() {
        if fc[r].is_finite() && fc[r] > cfg.coverage_threshold * peak && !(p[r] > 0.0) {
            count += 1;
            if fc[r] / peak > worst.0 {
                worst = (fc[r] / peak, Some(k));
            }
        }
    }
    let pass = count == 0;
    let mut s = format!(
        "{count} of {} pairs with f cos > {} of its peak and pdf = 0",
        idx.len(),
        num(cfg.coverage_threshold)
    );
    let at = worst.1.map(|k| {
        s += &format!(
            "; the largest f cos there {} of the peak{}",
            num(worst.0),
            super::pair_text(set.wi[k], set.wo[k])
        );
        At {
            wi: Some(set.wi[k]),
            wo: Some(set.wo[k]),
            ..At::default()
        }
    });
    Ok(Check::new("pdf-coverage", pass, worst.0, cfg.coverage_threshold, s).at(at))
}

//! The value checks: `finite`, `non-negative`, `non-finite-input`, `reciprocity`,
//! `reference`.

use super::grid::Pairs;
use super::{At, Batched, Check, Config, num, pair_at, pair_text};

/// The model's values on the pair set, and their peak.
pub struct Values {
    pub f: Vec<f64>,
    pub channels: usize,
    /// The largest finite value (0 when none is).
    pub peak: f64,
}

/// The largest finite `|x|` (0 when none is).
fn peak(v: &[f64]) -> f64 {
    v.iter()
        .filter(|x| x.is_finite())
        .fold(0.0, |m: f64, x| m.max(x.abs()))
}

impl Values {
    pub fn eval(m: &Batched, set: &Pairs) -> Result<Self, String> {
        let f = m.eval(&set.wi, &set.wo)?;
        Ok(Self {
            peak: peak(&f),
            f,
            channels: m.channels,
        })
    }

    /// The largest value over channels of pair `k` (NaN when any is not finite).
    pub fn max_at(&self, k: usize) -> f64 {
        let c = self.channels;
        self.f[k * c..(k + 1) * c]
            .iter()
            .fold(f64::NEG_INFINITY, |m, &x| {
                if x.is_finite() { m.max(x) } else { f64::NAN }
            })
    }

    pub fn finite(&self, set: &Pairs) -> Check {
        let bad: Vec<usize> = (0..self.f.len())
            .filter(|&i| !self.f[i].is_finite())
            .collect();
        let n = set.wi.len();
        let Some(&first) = bad.first() else {
            return Check::new(
                "finite",
                true,
                0.0,
                0.0,
                format!(
                    "all {} values finite ({n} pairs, grazing and normal included)",
                    self.f.len()
                ),
            );
        };
        let k = first / self.channels;
        Check::new(
            "finite",
            false,
            bad.len() as f64,
            0.0,
            format!(
                "{} of {} values not finite, the first {}{}",
                bad.len(),
                self.f.len(),
                self.f[first],
                pair_text(set.wi[k], set.wo[k])
            ),
        )
        .at(pair_at(set.wi[k], set.wo[k]))
    }

    pub fn non_negative(&self, set: &Pairs) -> Check {
        let mut min = (f64::INFINITY, 0);
        for (i, &x) in self.f.iter().enumerate() {
            if x.is_finite() && x < min.0 {
                min = (x, i);
            }
        }
        let k = min.1 / self.channels;
        let pass = min.0 >= 0.0;
        let mut s = format!("least value {}", num(min.0));
        if !pass {
            s += &format!(
                " ({} of the peak {}){}",
                num(min.0 / self.peak),
                num(self.peak),
                pair_text(set.wi[k], set.wo[k])
            );
        }
        let at = if pass {
            None
        } else {
            pair_at(set.wi[k], set.wo[k])
        };
        Check::new("non-negative", pass, min.0, 0.0, s).at(at)
    }

    /// `f(wo, wi)` against `f(wi, wo)` on every pair where both are finite.
    pub fn reciprocity(&self, m: &Batched, set: &Pairs, cfg: &Config) -> Result<Check, String> {
        let g = m.eval(&set.wo, &set.wi)?;
        let c = self.channels;
        // Weighted by cos theta_i cos theta_o (symmetric, as f must be): the transport a
        // renderer sees, without the 1 / (cos cos) of grazing pairs swamping the peak.
        let cc = |i: usize| set.wi[i / c][2].max(0.0) * set.wo[i / c][2].max(0.0);
        let mut worst = (0.0, 0);
        let mut p: f64 = 0.0;
        for (i, (&a, &b)) in self.f.iter().zip(&g).enumerate() {
            if a.is_finite() && b.is_finite() {
                let w = cc(i);
                p = p.max(a.abs() * w).max(b.abs() * w);
                if (a - b).abs() * w > worst.0 {
                    worst = ((a - b).abs() * w, i);
                }
            }
        }
        let rel = if p > 0.0 { worst.0 / p } else { 0.0 };
        let k = worst.1 / c;
        let pass = rel <= cfg.reciprocity_tol;
        // Where: only where the two differ.
        let (text, at) = if worst.0 > 0.0 {
            (
                pair_text(set.wi[k], set.wo[k]),
                pair_at(set.wi[k], set.wo[k]),
            )
        } else {
            (String::new(), None)
        };
        Ok(Check::new(
            "reciprocity",
            pass,
            rel,
            cfg.reciprocity_tol,
            format!(
                "max |f(wi,wo)-f(wo,wi)| cos_i cos_o = {} of its peak {} (limit {}){text}",
                num(rel),
                num(p),
                num(cfg.reciprocity_tol),
            ),
        )
        .at(at))
    }

    /// The model against `r` on the pair set: the numbers of the `reference` check.
    pub fn agreement(&self, r: &Batched, set: &Pairs, cfg: &Config) -> Result<Agreement, String> {
        let (c, rc) = (self.channels, r.channels);
        if c != rc && c != 1 && rc != 1 {
            return Err(format!(
                "the model has {c} channels and the reference {rc}: they cannot be compared"
            ));
        }
        let rv = r.eval(&set.wi, &set.wo)?;
        let n = c.max(rc);
        let (mut abs, mut rel) = ((0.0, 0, 0), (0.0, 0, 0));
        let rpeak = peak(&rv);
        let (mut sq, mut count) = (0.0, 0usize);
        for k in 0..set.wi.len() {
            for j in 0..n {
                let a = self.f[k * c + j.min(c - 1)];
                let b = rv[k * rc + j.min(rc - 1)];
                if !(a.is_finite() && b.is_finite()) {
                    continue;
                }
                let d = (a - b).abs();
                if d > abs.0 {
                    abs = (d, k, j);
                }
                if b.abs() > cfg.reference_floor * rpeak && d / b.abs() > rel.0 {
                    rel = (d / b.abs(), k, j);
                }
                if k >= set.random_from {
                    sq += d * d;
                    count += 1;
                }
            }
        }
        let at = |(_, k, j): (f64, usize, usize)| At {
            channel: (n > 1).then_some(j),
            ..pair_at(set.wi[k], set.wo[k]).unwrap()
        };
        Ok(Agreement {
            max_abs: abs.0,
            reference_peak: rpeak,
            max_abs_of_peak: if rpeak > 0.0 { abs.0 / rpeak } else { abs.0 },
            max_abs_at: at(abs),
            max_rel: rel.0,
            max_rel_at: at(rel),
            rel_floor: cfg.reference_floor,
            rms: (sq / count.max(1) as f64).sqrt(),
            pairs: set.wi.len(),
            channels: n,
        })
    }

    /// The model against `r` on the pair set.
    pub fn reference(&self, r: &Batched, set: &Pairs, cfg: &Config) -> Result<Check, String> {
        let a = self.agreement(r, set, cfg)?;
        let pass = a.max_abs_of_peak <= cfg.reference_tol;
        let (wa, wr) = (&a.max_abs_at, &a.max_rel_at);
        let pair = |w: &At| pair_text(w.wi.unwrap(), w.wo.unwrap());
        Ok(Check::new(
            "reference",
            pass,
            a.max_abs_of_peak,
            cfg.reference_tol,
            format!(
                "max |f - ref| = {} ({} of the reference's peak {}, limit {}){}{}; max relative error {} (where ref > {} of its peak){}; RMS {} over solid angle",
                num(a.max_abs),
                num(a.max_abs_of_peak),
                num(a.reference_peak),
                num(cfg.reference_tol),
                pair(wa),
                channel_text(a.channels, wa.channel.unwrap_or(0)),
                num(a.max_rel),
                num(cfg.reference_floor),
                pair(wr),
                num(a.rms)
            ),
        )
        .at(Some(a.max_abs_at.clone())))
    }
}

/// How a model agrees with a reference on conform's pair set (the grid, grazing pairs
/// included, and the uniform random pairs): what `reference` holds to its limit and what
/// `fastbrdf errors --model file:PATH` prints.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Agreement {
    /// The largest `|f - ref|` over pairs and channels (non-finite values skipped).
    pub max_abs: f64,
    /// The reference's largest finite value.
    pub reference_peak: f64,
    /// `max_abs / reference_peak`: the check's number.
    pub max_abs_of_peak: f64,
    pub max_abs_at: At,
    /// The largest `|f - ref| / |ref|` where `|ref| > rel_floor * reference_peak`.
    pub max_rel: f64,
    pub max_rel_at: At,
    pub rel_floor: f64,
    /// The RMS of `f - ref` over the uniform random pairs (over solid angle).
    pub rms: f64,
    /// Direction pairs compared.
    pub pairs: usize,
    /// Channels compared (the larger of the two).
    pub channels: usize,
}

fn channel_text(n: usize, j: usize) -> String {
    if n > 1 {
        format!(" (channel {j})")
    } else {
        String::new()
    }
}

/// Directions with a NaN or infinite component give finite, non-negative values.
pub fn non_finite_input(m: &Batched) -> Result<Check, String> {
    // Off the horizon: what a model does exactly there is `finite`'s business.
    let good = [
        [0.0, 0.0, 1.0],
        [0.6, 0.0, 0.8],
        [-0.6, 0.0, 0.8],
        [0.0, 0.995, 0.0999],
    ];
    let mut wi = Vec::new();
    let mut wo = Vec::new();
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        for a in good {
            for b in good {
                for i in 0..3 {
                    let mut x = a;
                    x[i] = bad;
                    wi.push(x);
                    wo.push(b);
                    wi.push(b);
                    wo.push(x);
                }
                wi.push([bad; 3]);
                wo.push(b);
                wi.push(a);
                wo.push([bad; 3]);
            }
        }
        wi.push([bad; 3]);
        wo.push([bad; 3]);
    }
    let f = m.eval(&wi, &wo)?;
    let c = m.channels;
    let bad: Vec<usize> = (0..f.len())
        .filter(|&i| !(f[i].is_finite() && f[i] >= 0.0))
        .collect();
    let n = wi.len();
    Ok(match bad.first() {
        None => Check::new(
            "non-finite-input",
            true,
            0.0,
            0.0,
            format!("{n} pairs with NaN or infinite components: every value finite and >= 0"),
        ),
        Some(&i) => {
            let k = i / c;
            Check::new(
                "non-finite-input",
                false,
                bad.len() as f64,
                0.0,
                format!(
                    "{} of {} values from NaN or infinite inputs not finite or negative, the first {}{}",
                    bad.len(),
                    f.len(),
                    f[i],
                    pair_text(wi[k], wo[k])
                ),
            )
            .at(pair_at(wi[k], wo[k]))
        }
    })
}

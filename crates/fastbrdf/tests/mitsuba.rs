//! `cook-torrance` against stored values of Mitsuba 3's `roughconductor` (Beckmann, exact
//! conductor Fresnel, Walter's rational Smith G1), written by `tools/mitsuba_reference.py`.
//! Mitsuba's eval includes the cosine factor: `eval = f(wi, wo) cos theta_o`. Mitsuba runs in
//! single precision, so the tolerance is relative 2e-4 (its f32 exp and sqrt near narrow
//! lobes) plus 1e-6 of the row's magnitude scale.

mod common;

use common::build;
use fastbrdf::Model;

#[test]
fn cook_torrance_matches_mitsuba3_roughconductor() {
    let text = include_str!("data/mitsuba_roughconductor.csv");
    let mut rows = 0;
    let mut nonzero = 0;
    for line in text
        .lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with("alpha"))
    {
        let v: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        let (alpha, eta, k) = (v[0].to_string(), v[1].to_string(), v[2].to_string());
        let Model::Brdf(ct) = build::<f64>(
            "cook-torrance",
            &[
                ("alpha", &alpha),
                ("g", "smith-rational"),
                ("f", "conductor"),
                ("eta", &eta),
                ("k", &k),
            ],
        )
        .unwrap() else {
            panic!()
        };
        let (wi, wo) = ([v[3], v[4], v[5]], [v[6], v[7], v[8]]);
        let ours = ct.eval(wi, wo) * wo[2];
        let theirs = v[9];
        assert!(
            (ours - theirs).abs() <= 2e-4 * theirs.abs() + 1e-6,
            "{line}: ours {ours} vs mitsuba {theirs}"
        );
        rows += 1;
        if theirs > 1e-3 {
            nonzero += 1;
        }
    }
    assert!(
        rows >= 400 && nonzero >= 100,
        "{rows} rows, {nonzero} non-zero"
    );
}

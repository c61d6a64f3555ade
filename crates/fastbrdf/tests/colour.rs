//! The named metals (issue 14): the table equals the cited numbers, and each channel's
//! normal-incidence reflectance from the conductor Fresnel term equals the closed form.

use fastbrdf::colour::{METALS, metal};

/// The cited table (Chaos Group's RGB table of refractiveindex.info's data; ARCHITECTURE.md,
/// "Colour"), typed again here so that an edit of `colour::METALS` fails this test.
const CITED: [(&str, [f64; 3], [f64; 3]); 6] = [
    ("gold", [0.18299, 0.42108, 1.3734], [3.4242, 2.3459, 1.7704]),
    (
        "silver",
        [0.15943, 0.14512, 0.13547],
        [3.9291, 3.19, 2.3808],
    ),
    (
        "copper",
        [0.27105, 0.67693, 1.3164],
        [3.6092, 2.6248, 2.2921],
    ),
    (
        "aluminium",
        [1.3456, 0.96521, 0.61722],
        [7.4746, 6.3995, 5.3031],
    ),
    ("chromium", [3.1071, 3.1812, 2.323], [3.3314, 3.3291, 3.135]),
    ("iron", [2.9114, 2.9497, 2.5845], [3.0893, 2.9318, 2.767]),
];

#[test]
fn the_table_is_the_cited_one() {
    assert_eq!(METALS.len(), CITED.len());
    for (id, eta, k) in CITED {
        let m = metal(id).unwrap();
        assert_eq!(m.eta, eta, "{id} eta");
        assert_eq!(m.k, k, "{id} k");
        assert!(m.source.contains("19"), "{id}: a dated source");
    }
}

#[test]
fn f0_is_the_closed_form_per_channel() {
    for m in METALS {
        let f0 = m.f0();
        for (c, ((&f, &n), &k)) in f0.iter().zip(&m.eta).zip(&m.k).enumerate() {
            let exact = ((n - 1.0).powi(2) + k * k) / ((n + 1.0).powi(2) + k * k);
            assert!(
                (f - exact).abs() < 1e-12,
                "{} channel {c}: {f} vs {exact}",
                m.id
            );
        }
    }
    // Gold is yellow: red reflects most, blue least.
    let g = metal("gold").unwrap().f0();
    assert!(g[0] > g[1] && g[1] > g[2], "{g:?}");
}

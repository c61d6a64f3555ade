//! Colour: per-channel parameters and the named metals (issue 14).
//!
//! Every model returns one number. Colour is three of them: a parameter given as three
//! comma-separated numbers `R,G,B` (`eta=0.183,0.421,1.373`) makes the model coloured, and
//! `channels` splits such a parameter list into three ordinary (grey) lists, one per
//! channel, each an ordinary registry model (three plans, three kernels, three WGSL
//! functions). A list without such a value is grey (`channels` returns `None`): the
//! existing one-model path, untouched and no slower. The rule lives here once, applied by
//! [`crate::ModelSpec::parse`] where text becomes a spec, so the renderers, `eval` and the
//! exports split the same way (through [`crate::ModelSpec::channel_specs`]) and give the
//! same errors. A metal colours a spec through [`crate::ModelSpec::with_metal`].
//!
//! The channels are the wavelengths 650, 550 and 450 nm ([`WAVELENGTHS_NM`]), as in the
//! published RGB tables of metals' optical constants. [`METALS`] holds six named metals:
//! `eta` and `k` at those wavelengths, from refractiveindex.info's "3D: selected data for 3D
//! artists" shelf as tabulated by Chaos Group ("Understanding metalness", the Corona/V-Ray
//! knowledge base), with the measurement each shelf entry is commonly attributed to (the
//! shelf's pages and the papers were not reachable from here: the attribution is not
//! re-checked; the Corona knowledge base's "How to use Complex IOR" lists the same shelf's
//! values for Cu, Ag and Au at 550 and 450 nm, equal to these within 0.003):
//!
//! | id | metal | original measurement |
//! |---|---|---|
//! | `gold`, `silver`, `copper` | Au, Ag, Cu | P. B. Johnson and R. W. Christy, "Optical constants of the noble metals", Phys. Rev. B 6, 4370 (1972) |
//! | `aluminium` | Al | A. D. Rakić, "Algorithm for the determination of intrinsic optical constants of metal films: application to aluminum", Appl. Opt. 34, 4755 (1995) |
//! | `chromium`, `iron` | Cr, Fe | P. B. Johnson and R. W. Christy, "Optical constants of transition metals: Ti, V, Cr, Mn, Fe, Co, Ni, and Pd", Phys. Rev. B 9, 5056 (1974) |
//!
//! Cross-check (ARCHITECTURE.md, "Colour"): Mitsuba 0.5's spectral tables (`data/ior`,
//! from the luxpop database) interpolated linearly at 650/550/450 nm give normal-incidence
//! reflectances within 0.012 of these for Ag and Al in every channel and for Au at 650 and
//! 450 nm; they differ on the steep interband edges (Au at 550 nm: 0.85 against 0.78; Cu:
//! 0.015, 0.087, 0.049) and for Cr by 0.09 to 0.15 (Mitsuba's Cr is Palik's compilation,
//! another film); Mitsuba has no Fe. The original papers were not re-read here.

use crate::error::{Error, Result};
use crate::microfacet::fresnel::{Consts, conductor};
use crate::params::{ParamKind, ParamSpec, Params};
use crate::registry;

/// A parameter list as text pairs (`name`, `value`).
pub(crate) type ParamList = Vec<(String, String)>;

/// Parameters whose value is the largest channel of another's R,G,B value, set when that one
/// is split and the derived one is not given: `gltf-pbr`'s sheen albedo scaling uses
/// `max3(sheenColor)` in every channel (`KHR_materials_sheen`).
const MAX_OF: &[(&str, &str)] = &[("sheen_color", "sheen_max")];

/// The parameters of `params` that the colour rule may derive ([`MAX_OF`]).
pub(crate) fn derived(params: &'static [ParamSpec]) -> impl Iterator<Item = &'static str> {
    params
        .iter()
        .filter(|s| MAX_OF.iter().any(|(_, d)| *d == s.name))
        .map(|s| s.name)
}

/// The channel names, in order.
pub const CHANNELS: [&str; 3] = ["R", "G", "B"];
/// The wavelength of each channel, nm.
pub const WAVELENGTHS_NM: [f64; 3] = [650.0, 550.0, 450.0];

/// A named metal: its complex index `eta + i k` at the three channels' wavelengths.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct Metal {
    /// The preset's name (`--metal NAME`).
    pub id: &'static str,
    /// The chemical symbol.
    pub symbol: &'static str,
    /// Real part of the index at 650, 550, 450 nm.
    pub eta: [f64; 3],
    /// Extinction coefficient at 650, 550, 450 nm.
    pub k: [f64; 3],
    /// The original measurement.
    pub source: &'static str,
}

const JC1972: &str =
    "Johnson & Christy 1972, Phys. Rev. B 6, 4370 (attributed; via refractiveindex.info)";
const JC1974: &str =
    "Johnson & Christy 1974, Phys. Rev. B 9, 5056 (attributed; via refractiveindex.info)";
const RAKIC1995: &str = "Rakic 1995, Appl. Opt. 34, 4755 (attributed; via refractiveindex.info)";

/// The named metals (values as tabulated; see the module header for the sources).
pub const METALS: [Metal; 6] = [
    Metal {
        id: "gold",
        symbol: "Au",
        eta: [0.18299, 0.42108, 1.3734],
        k: [3.4242, 2.3459, 1.7704],
        source: JC1972,
    },
    Metal {
        id: "silver",
        symbol: "Ag",
        eta: [0.15943, 0.14512, 0.13547],
        k: [3.9291, 3.19, 2.3808],
        source: JC1972,
    },
    Metal {
        id: "copper",
        symbol: "Cu",
        eta: [0.27105, 0.67693, 1.3164],
        k: [3.6092, 2.6248, 2.2921],
        source: JC1972,
    },
    Metal {
        id: "aluminium",
        symbol: "Al",
        eta: [1.3456, 0.96521, 0.61722],
        k: [7.4746, 6.3995, 5.3031],
        source: RAKIC1995,
    },
    Metal {
        id: "chromium",
        symbol: "Cr",
        eta: [3.1071, 3.1812, 2.323],
        k: [3.3314, 3.3291, 3.135],
        source: JC1974,
    },
    Metal {
        id: "iron",
        symbol: "Fe",
        eta: [2.9114, 2.9497, 2.5845],
        k: [3.0893, 2.9318, 2.767],
        source: JC1974,
    },
];

/// The ids of [`METALS`], comma-separated (for messages and help).
pub fn metal_names() -> String {
    METALS.iter().map(|m| m.id).collect::<Vec<_>>().join(", ")
}

/// The metal named `name`, or an error listing the names.
pub fn metal(name: &str) -> Result<&'static Metal> {
    METALS
        .iter()
        .find(|m| m.id == name.trim())
        .ok_or_else(|| Error::UnknownMetal {
            name: name.into(),
            known: metal_names(),
        })
}

impl Metal {
    /// The reflectance at normal incidence per channel: the conductor Fresnel term at
    /// `cos = 1` (f64), which is `((eta - 1)^2 + k^2) / ((eta + 1)^2 + k^2)`.
    pub fn f0(&self) -> [f64; 3] {
        std::array::from_fn(|c| conductor(1.0f64, &Consts::new(self.eta[c], self.k[c])))
    }
}

/// The three channel parameter lists of `params` for model `id`, or `None` when no value has
/// a comma (a grey model: use `params` as they are). A value `a,b,c` of a numeric parameter
/// gives `a` to the R list, `b` to G and `c` to B; every other value goes to all three. Each
/// channel's list is then validated like any parameter list of `id`, so the errors name the
/// parameter and the channel: two or four numbers, text, a choice given per channel, or a
/// channel out of its parameter's range. Parameters that `id` does not take are an error,
/// as they are for a grey model.
pub(crate) fn channels(id: &str, params: &[(String, String)]) -> Result<Option<[ParamList; 3]>> {
    if !params.iter().any(|(_, v)| v.contains(',')) {
        return Ok(None);
    }
    let e = registry::find(id)?;
    let mut out: [ParamList; 3] = Default::default();
    let mut split: Vec<&str> = vec![];
    for (name, value) in params {
        if !value.contains(',') {
            for list in &mut out {
                list.push((name.clone(), value.clone()));
            }
            continue;
        }
        let Some(spec) = e.info.params.iter().find(|s| s.name == name) else {
            return Err(Error::UnknownParam {
                model: e.info.id.into(),
                param: name.clone(),
            });
        };
        let invalid = |expected: &str| Error::InvalidParam {
            model: e.info.id.into(),
            param: name.clone(),
            value: value.clone(),
            expected: expected.into(),
        };
        if let ParamKind::Choice { .. } = spec.kind {
            return Err(invalid(
                "one choice for all channels (only numeric parameters take R,G,B values)",
            ));
        }
        let parts: Vec<&str> = value.split(',').collect();
        if parts.len() != 3 {
            return Err(invalid(&format!(
                "one number, or three comma-separated numbers R,G,B (one per channel: 650, 550, 450 nm); {} given",
                parts.len()
            )));
        }
        for (list, part) in out.iter_mut().zip(&parts) {
            list.push((name.clone(), part.trim().to_string()));
        }
        split.push(spec.name);
        // A parameter that couples the channels gets its value from the whole colour.
        for (from, derived) in MAX_OF {
            let declared = e.info.params.iter().any(|s| s.name == *derived);
            let given = params.iter().any(|(n, _)| n == derived);
            if name == from && declared && !given {
                let max = parts
                    .iter()
                    .filter_map(|x| x.trim().parse::<f64>().ok())
                    .fold(f64::NEG_INFINITY, f64::max);
                if max.is_finite() {
                    for list in &mut out {
                        list.push((derived.to_string(), max.to_string()));
                    }
                }
            }
        }
    }
    for (c, list) in out.iter().enumerate() {
        let given: Vec<(&str, &str)> = list.iter().map(|(a, b)| (a.as_str(), b.as_str())).collect();
        Params::resolve(e.info.id, e.info.params, &given).map_err(|err| match err {
            Error::InvalidParam {
                model,
                param,
                value,
                expected,
            } if split.contains(&param.as_str()) => Error::InvalidParam {
                model,
                param: format!(
                    "{param} (channel {}, {} nm)",
                    CHANNELS[c], WAVELENGTHS_NM[c]
                ),
                value,
                expected,
            },
            other => other,
        })?;
    }
    Ok(Some(out))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(list: &[(&str, &str)]) -> Vec<(String, String)> {
        list.iter()
            .map(|(a, b)| (a.to_string(), b.to_string()))
            .collect()
    }

    #[test]
    fn grey_lists_are_not_split() {
        let given = p(&[("alpha", "0.2"), ("f", "conductor")]);
        assert!(channels("cook-torrance", &given).unwrap().is_none());
    }

    #[test]
    fn a_triple_goes_one_number_per_channel() {
        let given = p(&[
            ("alpha", "0.2"),
            ("eta", "0.1, 0.2,0.3"),
            ("f", "conductor"),
        ]);
        let [r, g, b] = channels("cook-torrance", &given).unwrap().unwrap();
        assert_eq!(
            r,
            p(&[("alpha", "0.2"), ("eta", "0.1"), ("f", "conductor")])
        );
        assert_eq!(g[1].1, "0.2");
        assert_eq!(b[1].1, "0.3");
    }

    #[test]
    fn errors_name_the_parameter_and_the_channel() {
        let msg = |v: &str| {
            channels("cook-torrance", &p(&[("eta", v)]))
                .unwrap_err()
                .to_string()
        };
        let two = msg("1,2");
        assert!(
            two.contains("parameter eta") && two.contains("2 given"),
            "{two}"
        );
        let text = msg("1,x,2");
        assert!(text.contains("eta (channel G, 550 nm)"), "{text}");
        let range = msg("1,2,11");
        assert!(range.contains("eta (channel B, 450 nm)"), "{range}");
        assert!(range.contains("[0.01, 10]"), "{range}");
        let choice = channels("cook-torrance", &p(&[("d", "ggx,ggx,ggx")]))
            .unwrap_err()
            .to_string();
        assert!(choice.contains("parameter d"), "{choice}");
        let unknown = channels("ward", &p(&[("eta", "1,1,1")])).unwrap_err();
        assert!(matches!(unknown, Error::UnknownParam { .. }), "{unknown}");
    }

    #[test]
    fn unknown_metals_list_the_names() {
        let e = metal("brass").unwrap_err().to_string();
        for m in METALS {
            assert!(e.contains(m.id), "{e}");
        }
        assert_eq!(metal("gold").unwrap().symbol, "Au");
    }

    #[test]
    fn metal_params_split_to_the_table() {
        use crate::spec::{Given, ModelSpec};
        let ct = ModelSpec::parse("cook-torrance", &[]).unwrap();
        for m in METALS {
            let coloured = ct.with_metal(&m).unwrap();
            // As text (what `fastbrdf metals` prints and `--param` takes), split again.
            let text = coloured.pairs();
            let given: Vec<(&str, &str)> =
                text.iter().map(|(a, b)| (a.as_str(), b.as_str())).collect();
            let [r, g, b] = channels("cook-torrance", &text).unwrap().unwrap();
            assert_eq!(ModelSpec::parse("cook-torrance", &given).unwrap(), coloured);
            for (c, (list, spec)) in [r, g, b].iter().zip(coloured.channel_specs()).enumerate() {
                let get = |n: &str| -> f64 {
                    list.iter()
                        .find(|(a, _)| a == n)
                        .unwrap()
                        .1
                        .parse()
                        .unwrap()
                };
                assert_eq!(get("eta"), m.eta[c]);
                assert_eq!(get("k"), m.k[c]);
                assert_eq!(spec.get("eta"), Some(&Given::Num(m.eta[c])));
                assert_eq!(spec.get("k"), Some(&Given::Num(m.k[c])));
            }
        }
    }
}

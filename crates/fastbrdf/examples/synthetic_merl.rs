//! Writes a synthetic MERL `.binary` file tabulating `kd/pi + ks * model` at the bin centres
//! (`fastbrdf::measured::write_merl`): for trying `fastbrdf measured` and `fit-measured`
//! without the real data.
//!
//! `cargo run -p fastbrdf --example synthetic_merl -- OUT.binary MODEL KD_R,KD_G,KD_B
//! KS_R,KS_G,KS_B [NAME=VALUE]...`, e.g.
//! `... -- ward.binary ward 0.3,0.1,0.05 0.05,0.05,0.05 alpha=0.29`.

use fastbrdf::measured::{from_half_diff, write_merl};
use fastbrdf::{Model, ModelSpec};
use std::f64::consts::PI;

fn rgb(s: &str) -> [f64; 3] {
    let v: Vec<f64> = s.split(',').map(|x| x.parse().expect("a number")).collect();
    [v[0], v[1], v[2]]
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.len() < 4 {
        eprintln!(
            "usage: synthetic_merl OUT.binary MODEL KD_R,KD_G,KD_B KS_R,KS_G,KS_B [NAME=VALUE]..."
        );
        std::process::exit(2);
    }
    let (kd, ks) = (rgb(&args[2]), rgb(&args[3]));
    let given: Vec<(&str, &str)> = args[4..]
        .iter()
        .map(|p| p.split_once('=').expect("NAME=VALUE"))
        .collect();
    let spec = ModelSpec::parse(&args[1], &given).expect("a valid model");
    let Model::Brdf(b) = spec.model::<f64>().expect("a grey model") else {
        panic!("{} is not a BRDF", args[1]);
    };
    write_merl(std::path::Path::new(&args[0]), |th, td, pd| {
        let (wi, wo) = from_half_diff(th, td, pd);
        if wi[2] <= 0.0 || wo[2] <= 0.0 {
            return [-1.0; 3];
        }
        let s = b.eval(wi, wo);
        [0, 1, 2].map(|c| kd[c] / PI + ks[c] * s)
    })
    .expect("written");
}

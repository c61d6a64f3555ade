//! The GPU the tests share. Without an adapter the tests skip, except when `CI` is set: there
//! a missing driver is a failure (the README's test command installs Mesa's lavapipe).

#![allow(dead_code)]

use fastbrdf_gpu::Gpu;
use std::sync::OnceLock;

pub fn gpu() -> Option<&'static Gpu> {
    static GPU: OnceLock<Option<Gpu>> = OnceLock::new();
    GPU.get_or_init(|| match Gpu::new() {
        Ok(g) => {
            eprintln!("GPU tests on {}", g.label());
            Some(g)
        }
        Err(e) => {
            if std::env::var_os("CI").is_some() {
                panic!("CI is set and there is no GPU adapter: {e}");
            }
            eprintln!("skipping GPU tests: {e}");
            None
        }
    })
    .as_ref()
}

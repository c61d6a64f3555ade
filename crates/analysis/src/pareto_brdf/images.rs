//! Image space: renders of the sphere (and a mesh) with a configuration, and the mean FLIP of
//! each against the reference's.

use super::Config;
use fastbrdf_render::compare;
use fastbrdf_render::render::{self, Shading};
use fastbrdf_render::scene::Specular;
use fastbrdf_render::setup::{self, SceneSpec};
use std::path::PathBuf;
use std::sync::Arc;

/// The renders compared in image space: the sphere, and a mesh when given.
pub struct Images {
    pub size: u32,
    sphere: (SceneSpec, setup::Loaded),
    mesh: Option<(SceneSpec, setup::Loaded)>,
}

impl Images {
    /// Loads the mesh (if any) once.
    pub fn new(size: u32, mesh: Option<PathBuf>) -> fastbrdf_render::Result<Self> {
        let spec = |mesh: Option<PathBuf>| SceneSpec {
            mesh,
            kd: 0.5,
            ks: 1.0,
            // Shadows (issue 15) only mask the same pixels in every configuration's picture;
            // off, the FLIP figures stay those of README's table (BRDF error alone).
            shadows: false,
            ..SceneSpec::new()
        };
        let sphere = spec(None);
        let sphere_loaded = setup::load(&sphere)?;
        let mesh = match mesh {
            Some(p) => {
                let s = spec(Some(p));
                let l = setup::load(&s)?;
                Some((s, l))
            }
            None => None,
        };
        Ok(Self {
            size,
            sphere: (sphere, sphere_loaded),
            mesh,
        })
    }

    /// The sRGB 8-bit renders of `config` at `alpha`: the sphere, then the mesh if any.
    pub fn render(&self, config: &Config, alpha: f64) -> fastbrdf_render::Result<Vec<Vec<u8>>> {
        let specular = Arc::new(Specular::new(&config.at(alpha)?)?);
        let opts = render::Options {
            width: self.size,
            height: self.size,
            spp: 1,
            shading: Shading::Batch,
            sampler: fastbrdf_render::render::Sampler::default(),
            aa: fastbrdf_render::render::Antialias::default(),
        };
        let mut out = Vec::new();
        for (spec, loaded) in std::iter::once(&self.sphere).chain(self.mesh.as_ref()) {
            let scene = setup::scene(spec, loaded, specular.clone());
            let film = render::render(&scene, &opts, &|_, _| {})?;
            film.check_finite()?;
            out.push(film.to_srgb8(1.0));
        }
        Ok(out)
    }

    /// Mean FLIP of each render against the reference's.
    pub fn flip(&self, reference: &[Vec<u8>], test: &[Vec<u8>]) -> Vec<f64> {
        reference
            .iter()
            .zip(test)
            .map(|(r, t)| compare::metrics("", r, t, self.size, self.size).flip)
            .collect()
    }
}

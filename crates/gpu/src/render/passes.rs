//! The render pipelines of one model or user's shader (visibility and shading, for analytic
//! shapes and meshes), the bind group layouts they share, and one pass over the scene's objects.

use super::env::GpuEnv;
use super::env::env_module_source;
use super::features::Features;
use super::layouts::Layouts;
use super::layouts::USER_PARAMS_BINDING;
use super::models::ModelShader;
use super::objects::GpuObject;
use super::{COLOR_FORMAT, DEPTH_FORMAT, ID_FORMAT, SHADER, Tile};
use crate::context::{GpuError, validated};
use crate::user::UserShader;
use std::collections::HashMap;

/// The pipelines of one specular model: the visibility pass (`_id`: depth and the nearest
/// hit's object and triangle) and the shading pass (radiance of the visible hit only).
pub(super) struct Pipelines {
    pub(super) analytic_id: wgpu::RenderPipeline,
    pub(super) mesh_id: wgpu::RenderPipeline,
    pub(super) analytic: wgpu::RenderPipeline,
    pub(super) mesh: wgpu::RenderPipeline,
}

/// One pass over the scene's objects into `target` (cleared to `clear`, depth cleared and
/// discarded): `pick` chooses each model's analytic and mesh pipelines; `ids` (the visibility
/// pass's result) is bound at group 2 when given; `env` (the shading pass under an
/// environment) at group 3, its background drawn before the objects.
pub(super) struct ScenePass<'a> {
    pub(super) label: &'static str,
    pub(super) target: &'a wgpu::TextureView,
    pub(super) clear: wgpu::Color,
    pub(super) ids: Option<&'a wgpu::BindGroup>,
    pub(super) env: Option<&'a GpuEnv>,
    pub(super) pick: fn(&Pipelines) -> (&wgpu::RenderPipeline, &wgpu::RenderPipeline),
}

impl ScenePass<'_> {
    pub(super) fn draw(
        &self,
        enc: &mut wgpu::CommandEncoder,
        depth_view: &wgpu::TextureView,
        tile: &Tile,
        frame_bind: &wgpu::BindGroup,
        objects: &[GpuObject],
        pipelines: &HashMap<String, Pipelines>,
    ) {
        let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(self.label),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: self.target,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(self.clear),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: depth_view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Discard,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_viewport(0.0, 0.0, tile.w as f32, tile.h as f32, 0.0, 1.0);
        pass.set_scissor_rect(0, 0, tile.w, tile.h);
        pass.set_bind_group(0, frame_bind, &[]);
        if let Some(ids) = self.ids {
            pass.set_bind_group(2, ids, &[]);
        }
        if let Some(env) = self.env {
            pass.set_bind_group(3, &env.bind, &[]);
            pass.set_bind_group(1, &env.empty, &[]);
            pass.set_pipeline(&env.background);
            pass.draw(0..3, 0..1);
        }
        for o in objects {
            let (analytic, mesh) = (self.pick)(&pipelines[&o.model]);
            pass.set_bind_group(1, &o.bind, &[]);
            match &o.corners {
                None => {
                    pass.set_pipeline(analytic);
                    pass.draw(0..3, 0..1);
                }
                Some((buf, count)) => {
                    pass.set_pipeline(mesh);
                    pass.set_vertex_buffer(0, buf.slice(..));
                    pass.draw(0..*count, 0..1);
                }
            }
        }
    }
}

impl Pipelines {
    /// Compiles the render shader with the scene's `features` and an object's specular model
    /// (`model`: its functions and `rd_brdf`, `models.rs`); with `env`, the shading pipelines
    /// are the environment's (`rd_fs_*_env`, `shaders/env.wgsl` spliced in).
    pub(super) fn new(
        device: &wgpu::Device,
        layouts: &Layouts,
        features: &Features,
        model: &ModelShader,
        env: Option<&GpuEnv>,
    ) -> Result<Self, GpuError> {
        let module = &model.source;
        let shader = features.apply(SHADER);
        let src = format!("{shader}\n{}{module}", env_source(env, module)?);
        let what = format!("render shader of {}", model.id);
        Self::compile(device, layouts, &what, src, env)
    }

    /// Compiles the render shader with a user's shader as `rd_brdf` (R, G, B: the whole
    /// BRDF), its parameters at group 1 binding [`USER_PARAMS_BINDING`], with the scene's
    /// `features`.
    pub(super) fn user(
        device: &wgpu::Device,
        layouts: &Layouts,
        features: &Features,
        shader: &UserShader,
        env: Option<&GpuEnv>,
    ) -> Result<Self, GpuError> {
        let user = shader
            .wgsl_at(1, USER_PARAMS_BINDING)
            .map_err(|e| GpuError::Input(e.message))?;
        let glue = USER_GLUE;
        let renderer = features.apply(SHADER);
        let src = format!("{user}\n{renderer}\n{}{glue}", env_source(env, &user)?);
        let what = format!("render shader of {}", shader.name());
        Self::compile(device, layouts, &what, src, env)
    }

    /// The four pipelines of the completed render shader `src`; `what` names it in errors.
    fn compile(
        device: &wgpu::Device,
        layouts: &Layouts,
        what: &str,
        src: String,
        env: Option<&GpuEnv>,
    ) -> Result<Self, GpuError> {
        let what = what.to_string();
        validated(device, &what, || {
            let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(&what),
                source: wgpu::ShaderSource::Wgsl(src.into()),
            });
            let pipeline = |vs: &str, fs: &str, buffers: &[Option<wgpu::VertexBufferLayout>]| {
                let visibility = fs.ends_with("_id");
                device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                    label: Some(&what),
                    layout: Some(match (visibility, env) {
                        (true, _) => &layouts.visibility,
                        (false, Some(e)) => &e.pipeline,
                        (false, None) => &layouts.pipeline,
                    }),
                    vertex: wgpu::VertexState {
                        module: &module,
                        entry_point: Some(vs),
                        compilation_options: Default::default(),
                        buffers,
                    },
                    primitive: wgpu::PrimitiveState {
                        topology: wgpu::PrimitiveTopology::TriangleList,
                        // Two-sided, like the CPU's ray tests.
                        cull_mode: None,
                        ..Default::default()
                    },
                    depth_stencil: Some(wgpu::DepthStencilState {
                        format: DEPTH_FORMAT,
                        depth_write_enabled: Some(true),
                        depth_compare: Some(wgpu::CompareFunction::Less),
                        stencil: Default::default(),
                        bias: Default::default(),
                    }),
                    multisample: Default::default(),
                    fragment: Some(wgpu::FragmentState {
                        module: &module,
                        entry_point: Some(fs),
                        compilation_options: Default::default(),
                        targets: &[Some(wgpu::ColorTargetState {
                            format: if visibility { ID_FORMAT } else { COLOR_FORMAT },
                            blend: None,
                            write_mask: wgpu::ColorWrites::ALL,
                        })],
                    }),
                    multiview_mask: None,
                    cache: None,
                })
            };
            let corners = wgpu::VertexBufferLayout {
                array_stride: 12,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &wgpu::vertex_attr_array![0 => Float32x3],
            };
            let (analytic, mesh) = match env {
                Some(_) => ("rd_fs_analytic_env", "rd_fs_mesh_env"),
                None => ("rd_fs_analytic", "rd_fs_mesh"),
            };
            Self {
                analytic_id: pipeline("rd_vs_full", "rd_fs_analytic_id", &[]),
                mesh_id: pipeline("rd_vs_mesh", "rd_fs_mesh_id", &[Some(corners.clone())]),
                analytic: pipeline("rd_vs_full", analytic, &[]),
                mesh: pipeline("rd_vs_mesh", mesh, &[Some(corners)]),
            }
        })
    }
}

/// `rd_brdf` of a user's shader: its `fb_user_brdf` (R, G, B: the whole BRDF), no tint.
pub(super) const USER_GLUE: &str = "fn rd_brdf(wi: vec3<f32>, wo: vec3<f32>, h: u32) -> RdSpec {\n    return RdSpec(fb_user_brdf(wi, wo), vec3<f32>(0.0));\n}\n";

/// The environment's shader and its `rd_dfg` (for a module whose other code is `module`)
/// when there is one, else nothing (the module of an environment-less scene is unchanged).
fn env_source(env: Option<&GpuEnv>, module: &str) -> Result<String, GpuError> {
    match env {
        Some(e) => env_module_source(module, e.split.as_ref().map(|(s, _)| &s.dfg)),
        None => Ok(String::new()),
    }
}

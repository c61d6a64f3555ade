//! The bind group and pipeline layouts shared by every pipeline and object: a leaf that
//! `passes` (the pipelines) and `objects` (the bind groups) both read.

/// The object group's binding of a user's parameters (`FbUserParams`, a uniform): bound for
/// every object, a zero block for those shaded with a model.
pub(super) const USER_PARAMS_BINDING: u32 = 5;

/// The bind group layouts shared by every pipeline.
pub(super) struct Layouts {
    pub(super) frame: wgpu::BindGroupLayout,
    pub(super) object: wgpu::BindGroupLayout,
    /// The visibility pass's ids, read by the shading pass.
    pub(super) ids: wgpu::BindGroupLayout,
    /// The shading pass: frame, object, ids.
    pub(super) pipeline: wgpu::PipelineLayout,
    /// The visibility pass: frame, object.
    pub(super) visibility: wgpu::PipelineLayout,
}

impl Layouts {
    pub(super) fn new(device: &wgpu::Device) -> Self {
        let entry = |binding, visibility, ty| wgpu::BindGroupLayoutEntry {
            binding,
            visibility,
            ty,
            count: None,
        };
        let uniform = wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: None,
        };
        let storage = wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only: true },
            has_dynamic_offset: false,
            min_binding_size: None,
        };
        let fragment = wgpu::ShaderStages::FRAGMENT;
        let frame = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("fastbrdf render frame"),
            entries: &[
                entry(0, wgpu::ShaderStages::VERTEX_FRAGMENT, uniform),
                entry(1, fragment, storage),
                entry(2, fragment, storage),
                entry(3, fragment, storage),
                entry(4, fragment, storage),
            ],
        });
        let object = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("fastbrdf render object"),
            entries: &[
                entry(0, fragment, uniform),
                entry(
                    1,
                    fragment,
                    wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: false },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                ),
                entry(2, fragment, storage),
                entry(3, fragment, storage),
                entry(4, fragment, storage),
                entry(USER_PARAMS_BINDING, fragment, uniform),
            ],
        });
        let ids = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("fastbrdf render ids"),
            entries: &[entry(
                0,
                fragment,
                wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Uint,
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
            )],
        });
        let pipeline = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("fastbrdf render"),
            bind_group_layouts: &[Some(&frame), Some(&object), Some(&ids)],
            immediate_size: 0,
        });
        let visibility = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("fastbrdf render visibility"),
            bind_group_layouts: &[Some(&frame), Some(&object)],
            immediate_size: 0,
        });
        Self {
            frame,
            object,
            ids,
            pipeline,
            visibility,
        }
    }
}

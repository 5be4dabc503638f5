//! The wgpu renderer: device, pipelines, and the one draw path shared by the window and
//! the headless screenshots.
//!
//! A frame is three steps: the sky (full-screen triangle) and the world triangles into a 4×
//! multisampled colour target with depth, resolved into the output; then the egui HUD on top
//! of the resolved image.

use bytemuck::{Pod, Zeroable};
use wgpu::util::DeviceExt;

use super::camera::Camera;
use super::hud::HudPainter;
use super::mesh::{MeshBuilder, Vertex, build_world};
use super::scene::Scene;
use super::{RenderError, palette};

/// WGSL of the world pass.
pub const WORLD_WGSL: &str = include_str!("shaders/world.wgsl");
/// WGSL of the sky pass.
pub const SKY_WGSL: &str = include_str!("shaders/sky.wgsl");

/// Multisample count of the 3D passes.
pub const MSAA_SAMPLES: u32 = 4;
const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// Format of the offscreen target and the PNG pixels.
pub const OFFSCREEN_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
/// Largest accepted width or height, px.
pub const MAX_SIZE_PX: u32 = 8192;
/// Distance where the haze starts, m.
const HAZE_START_M: f32 = 60.0;
/// Distance where the haze fully hides the world, m.
const HAZE_END_M: f32 = 400.0;
/// Ground checker cell, m.
const CHECKER_M: f32 = 8.0;

/// Uniforms shared by both shaders (the `Frame` struct in the WGSL).
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
struct FrameUniform {
    view_proj: [[f32; 4]; 4],
    camera_pos: [f32; 4],
    cam_forward: [f32; 4],
    cam_right: [f32; 4],
    cam_up: [f32; 4],
    sky_horizon: [f32; 4],
    sky_zenith: [f32; 4],
    grass_a: [f32; 4],
    grass_b: [f32; 4],
    params: [f32; 4],
}

/// Size of the uniform block shared by the shaders, bytes (checked against the WGSL in tests).
pub const FRAME_UNIFORM_BYTES: usize = size_of::<FrameUniform>();

impl FrameUniform {
    fn new(cam: &Camera) -> Self {
        let (f, r, u) = cam.basis();
        FrameUniform {
            view_proj: cam.view_projection(),
            camera_pos: [cam.eye[0], cam.eye[1], cam.eye[2], 0.0],
            cam_forward: [f[0], f[1], f[2], (cam.fov_y_rad / 2.0).tan()],
            cam_right: [r[0], r[1], r[2], cam.aspect],
            cam_up: [u[0], u[1], u[2], 0.0],
            sky_horizon: palette::SKY_HORIZON,
            sky_zenith: palette::SKY_ZENITH,
            grass_a: palette::GRASS_A,
            grass_b: palette::GRASS_B,
            params: [HAZE_START_M, HAZE_END_M, CHECKER_M, 0.0],
        }
    }
}

/// Which GPU (or software rasteriser) draws the frames.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct AdapterSummary {
    /// Adapter name, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)".
    pub name: String,
    /// Backend, e.g. "Vulkan" or "Gl".
    pub backend: String,
    /// Device type, e.g. "Cpu".
    pub device_type: String,
}

impl std::fmt::Display for AdapterSummary {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} ({}, {})", self.name, self.backend, self.device_type)
    }
}

impl From<&wgpu::AdapterInfo> for AdapterSummary {
    fn from(i: &wgpu::AdapterInfo) -> Self {
        AdapterSummary {
            name: i.name.clone(),
            backend: format!("{:?}", i.backend),
            device_type: format!("{:?}", i.device_type),
        }
    }
}

/// Size-dependent attachments.
struct Targets {
    width: u32,
    height: u32,
    msaa_view: wgpu::TextureView,
    depth_view: wgpu::TextureView,
}

/// Offscreen output texture plus the buffer its pixels are copied into.
struct Offscreen {
    texture: wgpu::Texture,
    view: wgpu::TextureView,
    readback: wgpu::Buffer,
    padded_row_bytes: u32,
}

/// Owns the wgpu device, queue, pipelines and the HUD; draws [`Scene`]s.
pub struct Renderer {
    device: wgpu::Device,
    queue: wgpu::Queue,
    adapter: AdapterSummary,
    format: wgpu::TextureFormat,
    world_pipeline: wgpu::RenderPipeline,
    sky_pipeline: wgpu::RenderPipeline,
    uniform_buffer: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
    vertex_buffer: wgpu::Buffer,
    mesh: MeshBuilder,
    egui: egui_wgpu::Renderer,
    hud: HudPainter,
    targets: Targets,
    offscreen: Option<Offscreen>,
}

/// The instance flags from the environment (`WGPU_VALIDATION`, …) and `WGPU_BACKEND`.
pub(crate) fn instance_descriptor(
    display: Option<Box<dyn wgpu::wgt::WgpuHasDisplayHandle>>,
) -> wgpu::InstanceDescriptor {
    match display {
        Some(d) => wgpu::InstanceDescriptor::new_with_display_handle_from_env(d),
        None => wgpu::InstanceDescriptor::new_without_display_handle_from_env(),
    }
}

/// Requests an adapter (compatible with `surface` when given) and maps failure to
/// [`RenderError::NoAdapter`] naming the backends that were tried.
pub(crate) fn request_adapter(
    instance: &wgpu::Instance,
    surface: Option<&wgpu::Surface<'_>>,
) -> Result<wgpu::Adapter, RenderError> {
    pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
        power_preference: wgpu::PowerPreference::from_env().unwrap_or_default(),
        force_fallback_adapter: false,
        compatible_surface: surface,
        ..Default::default()
    }))
    .map_err(|e| {
        let backends = wgpu::Backends::from_env().unwrap_or(wgpu::Backends::all());
        RenderError::NoAdapter(format!(
            "no GPU or software adapter found (backends tried: {backends:?}; {e}). \
             Install Mesa (lavapipe: mesa-vulkan-drivers, or llvmpipe: libgl1-mesa-dri) \
             or run the session headless"
        ))
    })
}

/// Which adapter a headless renderer would get, without creating a device (what
/// `telerehab doctor` reports); the same backends and errors as [`Renderer::new_headless`].
pub fn probe_adapter() -> Result<AdapterSummary, RenderError> {
    let instance = wgpu::Instance::new(instance_descriptor(None));
    let adapter = request_adapter(&instance, None)?;
    Ok(AdapterSummary::from(&adapter.get_info()))
}

fn check_size(width: u32, height: u32) -> Result<(), RenderError> {
    if width == 0 || height == 0 || width > MAX_SIZE_PX || height > MAX_SIZE_PX {
        return Err(RenderError::InvalidSize { width, height });
    }
    Ok(())
}

impl Renderer {
    /// A renderer drawing into an offscreen `width`×`height` texture (no window, no display).
    ///
    /// Honours `WGPU_BACKEND` (e.g. `vulkan` or `gl`). With no usable adapter it returns
    /// [`RenderError::NoAdapter`] with a message saying what to install.
    pub fn new_headless(width: u32, height: u32) -> Result<Self, RenderError> {
        check_size(width, height)?;
        let instance = wgpu::Instance::new(instance_descriptor(None));
        let adapter = request_adapter(&instance, None)?;
        let mut r = Self::with_adapter(&adapter, OFFSCREEN_FORMAT, width, height)?;
        r.offscreen = Some(r.create_offscreen(width, height));
        Ok(r)
    }

    /// A renderer on `adapter` whose output is `format`, sized `width`×`height`.
    pub(crate) fn with_adapter(
        adapter: &wgpu::Adapter,
        format: wgpu::TextureFormat,
        width: u32,
        height: u32,
    ) -> Result<Self, RenderError> {
        check_size(width, height)?;
        let summary = AdapterSummary::from(&adapter.get_info());
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("telerehab render"),
            required_features: wgpu::Features::empty(),
            required_limits:
                wgpu::Limits::downlevel_webgl2_defaults().using_resolution(adapter.limits()),
            ..Default::default()
        }))
        .map_err(|e| RenderError::Device(format!("request_device on {summary}: {e}")))?;

        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let uniform_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("frame uniforms"),
            contents: bytemuck::bytes_of(&FrameUniform::zeroed()),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        });
        let bgl = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("frame"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::VERTEX | wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            }],
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("frame"),
            layout: &bgl,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: uniform_buffer.as_entire_binding(),
            }],
        });
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("frame"),
            bind_group_layouts: &[Some(&bgl)],
            immediate_size: 0,
        });
        let world_pipeline = pipeline(&device, &layout, WORLD_WGSL, "world", format, true);
        let sky_pipeline = pipeline(&device, &layout, SKY_WGSL, "sky", format, false);
        let egui = egui_wgpu::Renderer::new(
            &device,
            format,
            egui_wgpu::RendererOptions {
                msaa_samples: 1,
                depth_stencil_format: None,
                dithering: false,
                predictable_texture_filtering: true,
            },
        );
        let vertex_buffer = vertex_buffer(&device, 4096);
        let targets = create_targets(&device, format, width, height);
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(RenderError::Device(format!(
                "creating pipelines on {summary}: {e}"
            )));
        }
        Ok(Renderer {
            device,
            queue,
            adapter: summary,
            format,
            world_pipeline,
            sky_pipeline,
            uniform_buffer,
            bind_group,
            vertex_buffer,
            mesh: MeshBuilder::default(),
            egui,
            hud: HudPainter::new(),
            targets,
            offscreen: None,
        })
    }

    /// The adapter drawing the frames.
    pub fn adapter(&self) -> &AdapterSummary {
        &self.adapter
    }

    /// Current output size, px.
    pub fn size(&self) -> (u32, u32) {
        (self.targets.width, self.targets.height)
    }

    /// The wgpu device (the window configures its surface with it).
    pub(crate) fn device(&self) -> &wgpu::Device {
        &self.device
    }

    /// The wgpu queue (the window presents with it).
    pub(crate) fn queue(&self) -> &wgpu::Queue {
        &self.queue
    }

    /// Resizes the attachments (and the offscreen target of a headless renderer).
    pub fn resize(&mut self, width: u32, height: u32) -> Result<(), RenderError> {
        check_size(width, height)?;
        if (width, height) == self.size() {
            return Ok(());
        }
        self.targets = create_targets(&self.device, self.format, width, height);
        if self.offscreen.is_some() {
            self.offscreen = Some(self.create_offscreen(width, height));
        }
        Ok(())
    }

    fn create_offscreen(&self, width: u32, height: u32) -> Offscreen {
        let texture = self.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("offscreen"),
            size: wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: OFFSCREEN_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let view = texture.create_view(&wgpu::TextureViewDescriptor::default());
        let padded_row_bytes = (width * 4).div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT)
            * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
        let readback = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size: u64::from(padded_row_bytes) * u64::from(height),
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        Offscreen {
            texture,
            view,
            readback,
            padded_row_bytes,
        }
    }

    /// Draws `scene` into `target` (a view of a texture of the renderer's size and format).
    /// The window and the headless path both call this.
    pub fn draw(&mut self, scene: &Scene, target: &wgpu::TextureView) -> Result<(), RenderError> {
        scene.validate()?;
        let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let (width, height) = self.size();
        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("frame"),
            });
        self.encode_world(scene, target, &mut encoder);
        let extra = self.encode_hud(scene, target, width, height, &mut encoder);
        self.queue
            .submit(extra.into_iter().chain([encoder.finish()]));
        match pollster::block_on(scope.pop()) {
            Some(e) => Err(RenderError::Device(format!("drawing a frame: {e}"))),
            None => Ok(()),
        }
    }

    fn encode_world(
        &mut self,
        scene: &Scene,
        target: &wgpu::TextureView,
        encoder: &mut wgpu::CommandEncoder,
    ) {
        let (width, height) = self.size();
        let road = scene.has_road();
        let clear = if road {
            palette::SKY_HORIZON
        } else {
            palette::DIAL_BACKGROUND
        };
        let mut n_vertices = 0;
        if road {
            let cam = Camera::follow(scene.camera, &scene.car, width as f32 / height as f32);
            self.queue.write_buffer(
                &self.uniform_buffer,
                0,
                bytemuck::bytes_of(&FrameUniform::new(&cam)),
            );
            build_world(&mut self.mesh, scene);
            let bytes: &[u8] = bytemuck::cast_slice(&self.mesh.vertices);
            if bytes.len() as u64 > self.vertex_buffer.size() {
                self.vertex_buffer =
                    vertex_buffer(&self.device, bytes.len().next_power_of_two() as u64);
            }
            self.queue.write_buffer(&self.vertex_buffer, 0, bytes);
            n_vertices = self.mesh.vertices.len() as u32;
        }
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("world"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &self.targets.msaa_view,
                depth_slice: None,
                resolve_target: Some(target),
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color {
                        r: f64::from(clear[0]),
                        g: f64::from(clear[1]),
                        b: f64::from(clear[2]),
                        a: 1.0,
                    }),
                    store: wgpu::StoreOp::Discard,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &self.targets.depth_view,
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
        if road {
            pass.set_bind_group(0, &self.bind_group, &[]);
            pass.set_pipeline(&self.sky_pipeline);
            pass.draw(0..3, 0..1);
            pass.set_pipeline(&self.world_pipeline);
            pass.set_vertex_buffer(0, self.vertex_buffer.slice(..));
            pass.draw(0..n_vertices, 0..1);
        }
    }

    fn encode_hud(
        &mut self,
        scene: &Scene,
        target: &wgpu::TextureView,
        width: u32,
        height: u32,
        encoder: &mut wgpu::CommandEncoder,
    ) -> Vec<wgpu::CommandBuffer> {
        let mut frame = self.hud.run(scene, width, height);
        for (id, deltas) in &frame.textures.set {
            for delta in deltas {
                self.egui
                    .update_texture(&self.device, &self.queue, *id, delta);
            }
        }
        let screen = egui_wgpu::ScreenDescriptor {
            size_in_pixels: [width, height],
            pixels_per_point: frame.pixels_per_point,
        };
        let extra = self.egui.update_buffers(
            &self.device,
            &self.queue,
            encoder,
            &frame.primitives,
            &screen,
        );
        {
            let mut pass = encoder
                .begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("hud"),
                    color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                        view: target,
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations {
                            load: wgpu::LoadOp::Load,
                            store: wgpu::StoreOp::Store,
                        },
                    })],
                    depth_stencil_attachment: None,
                    timestamp_writes: None,
                    occlusion_query_set: None,
                    multiview_mask: None,
                })
                .forget_lifetime();
            self.egui.render(&mut pass, &frame.primitives, &screen);
        }
        for id in &frame.textures.free {
            self.egui.free_texture(id);
        }
        // Every delta has been applied above; egui asserts that on drop.
        frame.textures.clear();
        extra
    }

    /// Draws `scene` offscreen and returns its pixels: RGBA8, rows top to bottom, no padding
    /// (`width × height × 4` bytes). Only for renderers made by [`Renderer::new_headless`].
    pub fn render_to_rgba(&mut self, scene: &Scene) -> Result<Vec<u8>, RenderError> {
        let off = self.offscreen.take().ok_or_else(|| {
            RenderError::Device("render_to_rgba needs a renderer made by new_headless".into())
        })?;
        let result = self
            .draw(scene, &off.view)
            .and_then(|()| self.read_back(&off));
        self.offscreen = Some(off);
        result
    }

    fn read_back(&self, off: &Offscreen) -> Result<Vec<u8>, RenderError> {
        let (width, height) = self.size();
        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("readback"),
            });
        encoder.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo {
                texture: &off.texture,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            wgpu::TexelCopyBufferInfo {
                buffer: &off.readback,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(off.padded_row_bytes),
                    rows_per_image: Some(height),
                },
            },
            wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
        );
        self.queue.submit([encoder.finish()]);
        let slice = off.readback.slice(..);
        let (tx, rx) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |r| {
            // The receiver lives until `recv` below returns; a failed send cannot happen.
            let _ = tx.send(r);
        });
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| RenderError::Readback(format!("waiting for the GPU: {e}")))?;
        rx.recv()
            .map_err(|e| RenderError::Readback(format!("map callback dropped: {e}")))?
            .map_err(|e| RenderError::Readback(format!("mapping the readback buffer: {e}")))?;
        let row = (width * 4) as usize;
        let mut rgba = Vec::with_capacity(row * height as usize);
        {
            let data = slice
                .get_mapped_range()
                .map_err(|e| RenderError::Readback(format!("reading the mapped buffer: {e}")))?;
            for chunk in data
                .chunks(off.padded_row_bytes as usize)
                .take(height as usize)
            {
                rgba.extend_from_slice(&chunk[..row]);
            }
        }
        off.readback.unmap();
        Ok(rgba)
    }
}

fn vertex_buffer(device: &wgpu::Device, bytes: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("world vertices"),
        size: bytes.max(4096),
        usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

fn create_targets(
    device: &wgpu::Device,
    format: wgpu::TextureFormat,
    width: u32,
    height: u32,
) -> Targets {
    let make = |label, format| {
        device
            .create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d {
                    width,
                    height,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: MSAA_SAMPLES,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
                view_formats: &[],
            })
            .create_view(&wgpu::TextureViewDescriptor::default())
    };
    Targets {
        width,
        height,
        msaa_view: make("msaa colour", format),
        depth_view: make("depth", DEPTH_FORMAT),
    }
}

/// A pipeline of the world (`with_vertices`) or sky shader.
fn pipeline(
    device: &wgpu::Device,
    layout: &wgpu::PipelineLayout,
    wgsl: &str,
    label: &str,
    format: wgpu::TextureFormat,
    with_vertices: bool,
) -> wgpu::RenderPipeline {
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(wgsl.into()),
    });
    let attributes = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32, 2 => Float32x4];
    let vertex_layout = wgpu::VertexBufferLayout {
        array_stride: size_of::<Vertex>() as u64,
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes: &attributes,
    };
    let with_layout = [Some(vertex_layout)];
    let buffers: &[Option<wgpu::VertexBufferLayout<'_>>] =
        if with_vertices { &with_layout } else { &[] };
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(label),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module: &module,
            entry_point: Some("vs_main"),
            compilation_options: Default::default(),
            buffers,
        },
        primitive: wgpu::PrimitiveState {
            topology: wgpu::PrimitiveTopology::TriangleList,
            cull_mode: None,
            ..Default::default()
        },
        depth_stencil: Some(wgpu::DepthStencilState {
            format: DEPTH_FORMAT,
            depth_write_enabled: Some(with_vertices),
            depth_compare: Some(if with_vertices {
                wgpu::CompareFunction::Less
            } else {
                wgpu::CompareFunction::LessEqual
            }),
            stencil: wgpu::StencilState::default(),
            bias: wgpu::DepthBiasState::default(),
        }),
        multisample: wgpu::MultisampleState {
            count: MSAA_SAMPLES,
            mask: !0,
            alpha_to_coverage_enabled: false,
        },
        fragment: Some(wgpu::FragmentState {
            module: &module,
            entry_point: Some("fs_main"),
            compilation_options: Default::default(),
            targets: &[Some(wgpu::ColorTargetState {
                format,
                blend: None,
                write_mask: wgpu::ColorWrites::ALL,
            })],
        }),
        multiview_mask: None,
        cache: None,
    })
}

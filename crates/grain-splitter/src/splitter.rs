//! The GPU splitter: pipelines and buffers built once, one frame encoded per call.

use crate::camera::SplitCamera;
use crate::error::SplitError;
use crate::hiz::{HIZ_WORKGROUP, HizParams, PyramidLevel, pyramid_levels, pyramid_texels};
use crate::lists::{COUNTER_WORDS, INDIRECT_WORDS, LIST_COUNT, MAX_GROUPS_PER_DIMENSION, SPLIT_WORKGROUP};
use crate::settings::{SplitParams, SplitSettings};
use crate::shaders::{hiz_shader, int64_capabilities, occluder_map_32_shader, occluder_map_64_shader, split_shader};

/// How the occluder map is built.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OccluderMapKind {
    /// The 64-bit map where the device has `SHADER_INT64_ATOMIC_MIN_MAX`, else the 32-bit one.
    Auto,
    /// One 64-bit `atomicMax` per pixel of `(~depth << 32) | ~index` (one pass).
    Atomic64,
    /// Two passes of 32-bit atomics (depth, then the index of the grains at that depth).
    TwoPass32,
}

/// The order of the elements within a list.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ListOrder {
    /// One atomic cursor per list (`GrainViewer`'s global atomic splitting): the order within a
    /// list changes from run to run.
    Atomic,
    /// Ascending grain index (block prefix sums and a workgroup scan): deterministic, one
    /// more dispatch.
    Stable,
}

/// What a splitter is built for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SplitterOptions {
    /// The most grains a frame may hold.
    pub capacity: u32,
    /// The occluder map's size in pixels (the cameras' viewport).
    pub size: (u32, u32),
    /// How the occluder map is built.
    pub occluder_map: OccluderMapKind,
    /// The order within the lists.
    pub order: ListOrder,
}

/// Timestamp queries: [`GrainSplitter::encode`] writes four slots from `first` (occluder map
/// begin and end, splitter begin and end); each of its two halves writes two.
#[derive(Clone, Copy, Debug)]
pub struct SplitTimestamps<'a> {
    /// The query set (of type `Timestamp`).
    pub query_set: &'a wgpu::QuerySet,
    /// The first of the four slots.
    pub first: u32,
}

struct MapResources {
    kind: OccluderMapKind,
    /// 64-bit: the map; 32-bit: the depth map.
    words: wgpu::Buffer,
    /// 32-bit only: the index map and the per-grain squares.
    ids_and_splats: Option<(wgpu::Buffer, wgpu::Buffer)>,
    pipelines: Vec<wgpu::ComputePipeline>,
    layout: wgpu::BindGroupLayout,
}

/// Occluder fusion's pyramid (sized for the viewport when the Hi-Z test is on, 16 bytes
/// otherwise) and its passes.
struct HizResources {
    pyramid: wgpu::Buffer,
    /// Two-phase culling's per-pixel cover (16 bytes when off).
    cover: wgpu::Buffer,
    params: wgpu::Buffer,
    /// `(k, 0, 0, 0)` for every level `k`, `stride` bytes apart (dynamic offsets).
    level_indices: wgpu::Buffer,
    stride: u32,
    levels: Vec<PyramidLevel>,
    layout: wgpu::BindGroupLayout,
    cover_pass: wgpu::ComputePipeline,
    bound: wgpu::ComputePipeline,
    reduce: wgpu::ComputePipeline,
}

/// The occluder map and the splitter of one grain type, for up to `capacity` grains seen at
/// one viewport size. Build it once; [`GrainSplitter::encode`] records a frame.
pub struct GrainSplitter {
    settings: SplitSettings,
    options: SplitterOptions,
    camera: wgpu::Buffer,
    params: wgpu::Buffer,
    map: MapResources,
    hiz: HizResources,
    state: wgpu::Buffer,
    counters: wgpu::Buffer,
    block_counts: wgpu::Buffer,
    elements: wgpu::Buffer,
    indirect: wgpu::Buffer,
    split_layout: wgpu::BindGroupLayout,
    count: wgpu::ComputePipeline,
    scan: wgpu::ComputePipeline,
    offsets: wgpu::ComputePipeline,
    write: wgpu::ComputePipeline,
}

/// The bind groups of one grain buffer (make them once per buffer with
/// [`GrainSplitter::bind`]).
pub struct SplitBindings {
    map: wgpu::BindGroup,
    hiz: wgpu::BindGroup,
    split: wgpu::BindGroup,
}

fn whole(binding: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry { binding, resource: buffer.as_entire_binding() }
}

/// The largest storage buffer the device binds.
fn storage_limit(device: &wgpu::Device) -> u64 {
    let limits = device.limits();
    limits.max_storage_buffer_binding_size.min(limits.max_buffer_size)
}

fn writes(timestamps: Option<SplitTimestamps<'_>>) -> Option<wgpu::ComputePassTimestampWrites<'_>> {
    timestamps.map(|t| wgpu::ComputePassTimestampWrites {
        query_set: t.query_set,
        beginning_of_pass_write_index: Some(t.first),
        end_of_pass_write_index: Some(t.first + 1),
    })
}

fn entry(binding: u32, ty: wgpu::BufferBindingType) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer { ty, has_dynamic_offset: false, min_binding_size: None },
        count: None,
    }
}

const UNIFORM: wgpu::BufferBindingType = wgpu::BufferBindingType::Uniform;
const READ: wgpu::BufferBindingType = wgpu::BufferBindingType::Storage { read_only: true };
const WRITE: wgpu::BufferBindingType = wgpu::BufferBindingType::Storage { read_only: false };

impl GrainSplitter {
    /// Validates the settings, the options against the device's limits and features, and
    /// the shaders with naga; builds the pipelines and the buffers.
    pub fn new(device: &wgpu::Device, settings: SplitSettings, options: SplitterOptions) -> Result<Self, SplitError> {
        settings.validate()?;
        let (width, height) = options.size;
        crate::camera::check_viewport(options.size)?;
        if options.capacity == 0 || options.capacity == u32::MAX {
            return Err(SplitError::InvalidSetting {
                field: "capacity",
                reason: format!("{}: must be in 1..{}", options.capacity, u32::MAX),
            });
        }
        let has_64 = Self::supports_atomic64(device);
        let kind = match options.occluder_map {
            OccluderMapKind::Auto if has_64 => OccluderMapKind::Atomic64,
            OccluderMapKind::Auto => OccluderMapKind::TwoPass32,
            OccluderMapKind::Atomic64 if !has_64 => {
                return Err(SplitError::MissingFeature("SHADER_INT64_ATOMIC_MIN_MAX (the 64-bit occluder map)"));
            }
            other => other,
        };
        let limits = device.limits();
        let blocks = options.capacity.div_ceil(SPLIT_WORKGROUP);
        let groups_limit = limits.max_compute_workgroups_per_dimension.min(MAX_GROUPS_PER_DIMENSION);
        if u64::from(blocks) > u64::from(groups_limit) * u64::from(groups_limit) {
            return Err(SplitError::TooLarge {
                what: "grain capacity in workgroups",
                requested: u64::from(blocks),
                limit: u64::from(groups_limit) * u64::from(groups_limit),
            });
        }
        let pixels = u64::from(width) * u64::from(height);
        let capacity = u64::from(options.capacity);
        let storage_limit = storage_limit(device);
        let sized = |what: &'static str, bytes: u64| {
            if bytes > storage_limit {
                Err(SplitError::TooLarge { what, requested: bytes, limit: storage_limit })
            } else {
                Ok(bytes.max(16))
            }
        };
        let map_bytes = sized("occluder map bytes", pixels * if kind == OccluderMapKind::Atomic64 { 8 } else { 4 })?;
        let grain_bytes = sized("grain buffer bytes", capacity * 16)?;
        let word_bytes = sized("per-grain word bytes", capacity * 4)?;
        let block_bytes = sized("block count bytes", u64::from(blocks) * 16)?;
        let usage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC;
        let buffer = |label: &str, size: u64, usage: wgpu::BufferUsages| {
            device.create_buffer(&wgpu::BufferDescriptor { label: Some(label), size, usage, mapped_at_creation: false })
        };
        let uniform_usage = wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST;

        let module = |shader: wgsl_gen::ComposedShader, capabilities| {
            shader.validate_with(capabilities).map_err(|e| SplitError::InvalidShader(e.to_string()))?;
            Ok::<_, SplitError>(device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(shader.name()),
                source: wgpu::ShaderSource::Wgsl(shader.source().to_owned().into()),
            }))
        };
        let pipelines = |module: &wgpu::ShaderModule, layout: &wgpu::BindGroupLayout, entries: &[&str]| {
            let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("grain splitter"),
                bind_group_layouts: &[Some(layout)],
                immediate_size: 0,
            });
            entries
                .iter()
                .map(|entry| {
                    device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                        label: Some(entry),
                        layout: Some(&pipeline_layout),
                        module,
                        entry_point: Some(entry),
                        compilation_options: Default::default(),
                        cache: None,
                    })
                })
                .collect::<Vec<_>>()
        };
        let shared = [entry(0, UNIFORM), entry(1, UNIFORM), entry(2, READ)];

        let map = if kind == OccluderMapKind::Atomic64 {
            let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("occluder map 64"),
                entries: &[shared[0], shared[1], shared[2], entry(3, WRITE)],
            });
            let module = module(occluder_map_64_shader(), int64_capabilities())?;
            MapResources {
                kind,
                words: buffer("occluder map (64-bit)", map_bytes, usage),
                ids_and_splats: None,
                pipelines: pipelines(&module, &layout, &["occluder_splat_64"]),
                layout,
            }
        } else {
            let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("occluder map 32"),
                entries: &[shared[0], shared[1], shared[2], entry(3, WRITE), entry(4, WRITE), entry(5, WRITE)],
            });
            let module = module(occluder_map_32_shader(), naga::valid::Capabilities::default())?;
            MapResources {
                kind,
                words: buffer("occluder map depths (32-bit)", map_bytes, usage),
                ids_and_splats: Some((
                    buffer("occluder map ids (32-bit)", map_bytes, usage),
                    buffer("occluder map squares", grain_bytes, usage),
                )),
                pipelines: pipelines(&module, &layout, &["occluder_depth_32", "occluder_id_32"]),
                layout,
            }
        };

        let hiz = {
            let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("occluder fusion"),
                entries: &[
                    shared[0],
                    shared[1],
                    shared[2],
                    entry(3, READ),
                    entry(4, WRITE),
                    entry(5, UNIFORM),
                    wgpu::BindGroupLayoutEntry {
                        binding: 6,
                        visibility: wgpu::ShaderStages::COMPUTE,
                        ty: wgpu::BindingType::Buffer {
                            ty: UNIFORM,
                            has_dynamic_offset: true,
                            min_binding_size: wgpu::BufferSize::new(16),
                        },
                        count: None,
                    },
                    entry(7, WRITE),
                    entry(8, READ),
                ],
            });
            let module = module(hiz_shader(), naga::valid::Capabilities::default())?;
            let mut passes = pipelines(&module, &layout, &["hiz_cover", "hiz_bound", "hiz_reduce"]).into_iter();
            let mut next = || passes.next().expect("three entry points were requested");
            let (cover_pass, bound, reduce) = (next(), next(), next());
            let cover_pixels = if settings.hiz_culling && settings.temporal_occluders { pixels } else { 4 };
            let levels = pyramid_levels(options.size);
            let texels = if settings.hiz_culling { pyramid_texels(options.size) } else { 4 };
            let stride = limits.min_uniform_buffer_offset_alignment.max(16);
            let mut indices = vec![0u8; levels.len() * stride as usize];
            for k in 0..levels.len() {
                indices[k * stride as usize..][..4].copy_from_slice(&(k as u32).to_le_bytes());
            }
            use wgpu::util::DeviceExt;
            HizResources {
                pyramid: buffer("occluder fusion pyramid", sized("pyramid bytes", texels * 4)?, usage),
                cover: buffer("two-phase cover", sized("cover bytes", cover_pixels * 4)?, usage),
                params: buffer("occluder fusion params", size_of::<HizParams>() as u64, uniform_usage),
                level_indices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("occluder fusion level indices"),
                    contents: &indices,
                    usage: wgpu::BufferUsages::UNIFORM,
                }),
                stride,
                levels,
                layout,
                cover_pass,
                bound,
                reduce,
            }
        };

        let split_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("grain splitter"),
            entries: &[
                shared[0],
                shared[1],
                shared[2],
                entry(3, READ),
                entry(4, WRITE),
                entry(5, WRITE),
                entry(6, WRITE),
                entry(7, WRITE),
                entry(8, WRITE),
                entry(9, READ),
                entry(10, UNIFORM),
            ],
        });
        let split_module = module(split_shader(), naga::valid::Capabilities::default())?;
        let write_entry = match options.order {
            ListOrder::Atomic => "split_write_atomic",
            ListOrder::Stable => "split_write_stable",
        };
        let mut split =
            pipelines(&split_module, &split_layout, &["split_count", "split_scan", "split_offsets", write_entry])
                .into_iter();
        let mut next = || split.next().expect("four entry points were requested");
        let (count, scan, offsets, write) = (next(), next(), next(), next());
        Ok(Self {
            settings,
            options: SplitterOptions { occluder_map: kind, ..options },
            camera: buffer("splitter camera", size_of::<SplitCamera>() as u64, uniform_usage),
            params: buffer("splitter params", size_of::<SplitParams>() as u64, uniform_usage),
            map,
            hiz,
            state: buffer("grain states", word_bytes, usage),
            counters: buffer("split counters", u64::from(COUNTER_WORDS) * 4, usage),
            block_counts: buffer("split block counts", block_bytes, usage),
            elements: buffer("split elements", word_bytes, usage),
            indirect: buffer(
                "split indirect arguments",
                u64::from(LIST_COUNT * INDIRECT_WORDS) * 4,
                usage | wgpu::BufferUsages::INDIRECT,
            ),
            split_layout,
            count,
            scan,
            offsets,
            write,
        })
    }

    /// Whether `device` can build the 64-bit occluder map ([`OccluderMapKind::Atomic64`]).
    pub fn supports_atomic64(device: &wgpu::Device) -> bool {
        device.features().contains(wgpu::Features::SHADER_INT64 | wgpu::Features::SHADER_INT64_ATOMIC_MIN_MAX)
    }

    /// Uploads `(centre, scale)` grains into a new storage buffer (usage `STORAGE |
    /// COPY_DST`, so that a frame loop rewrites it with `queue.write_buffer`); an error when
    /// it exceeds the device's storage-binding limit.
    pub fn upload_grains(device: &wgpu::Device, grains: &[glam::Vec4]) -> Result<wgpu::Buffer, SplitError> {
        use wgpu::util::DeviceExt;
        let bytes = size_of_val(grains) as u64;
        let limit = storage_limit(device);
        if bytes > limit {
            return Err(SplitError::TooLarge {
                what: "grain buffer bytes (max_storage_buffer_binding_size)",
                requested: bytes,
                limit,
            });
        }
        if grains.is_empty() {
            return Err(SplitError::InvalidBuffer("no grains to upload".into()));
        }
        Ok(device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("grains (centre, scale)"),
            contents: bytemuck::cast_slice(grains),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        }))
    }

    /// The bind groups for a grain buffer of `(centre, scale)` `vec4<f32>`s (usage
    /// `STORAGE`, at least 16 bytes).
    pub fn bind(&self, device: &wgpu::Device, grains: &wgpu::Buffer) -> Result<SplitBindings, SplitError> {
        if !grains.usage().contains(wgpu::BufferUsages::STORAGE) || grains.size() < 16 {
            return Err(SplitError::InvalidBuffer(format!(
                "the grain buffer ({} bytes, {:?}) needs STORAGE usage and at least one grain",
                grains.size(),
                grains.usage()
            )));
        }
        let shared = [whole(0, &self.camera), whole(1, &self.params), whole(2, grains)];
        let map = match &self.map.ids_and_splats {
            None => device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("occluder map 64"),
                layout: &self.map.layout,
                entries: &[shared[0].clone(), shared[1].clone(), shared[2].clone(), whole(3, &self.map.words)],
            }),
            Some((ids, splats)) => device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("occluder map 32"),
                layout: &self.map.layout,
                entries: &[
                    shared[0].clone(),
                    shared[1].clone(),
                    shared[2].clone(),
                    whole(3, &self.map.words),
                    whole(4, ids),
                    whole(5, splats),
                ],
            }),
        };
        let hiz = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("occluder fusion"),
            layout: &self.hiz.layout,
            entries: &[
                shared[0].clone(),
                shared[1].clone(),
                shared[2].clone(),
                whole(3, self.occluder_words().0),
                whole(4, &self.hiz.pyramid),
                whole(5, &self.hiz.params),
                wgpu::BindGroupEntry {
                    binding: 6,
                    resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                        buffer: &self.hiz.level_indices,
                        offset: 0,
                        size: wgpu::BufferSize::new(16),
                    }),
                },
                whole(7, &self.hiz.cover),
                whole(8, &self.state),
            ],
        });
        let split = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("grain splitter"),
            layout: &self.split_layout,
            entries: &[
                shared[0].clone(),
                shared[1].clone(),
                shared[2].clone(),
                whole(3, self.occluder_words().0),
                whole(4, &self.state),
                whole(5, &self.counters),
                whole(6, &self.block_counts),
                whole(7, &self.elements),
                whole(8, &self.indirect),
                whole(9, &self.hiz.pyramid),
                whole(10, &self.hiz.params),
            ],
        });
        Ok(SplitBindings { map, hiz, split })
    }

    /// Records one frame: [`GrainSplitter::encode_occluder_map`], then
    /// [`GrainSplitter::encode_split`]. The camera and settings are written through `queue`
    /// (so encode one frame per submission). Nothing is read back. `grain_count` must not
    /// exceed the capacity, nor the bound buffer's length.
    pub fn encode(
        &self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        bindings: &SplitBindings,
        camera: &SplitCamera,
        grain_count: u32,
        timestamps: Option<SplitTimestamps<'_>>,
    ) -> Result<(), SplitError> {
        self.encode_occluder_map(queue, encoder, bindings, camera, grain_count, timestamps)?;
        self.encode_split(
            encoder,
            bindings,
            grain_count,
            timestamps.map(|t| SplitTimestamps { first: t.first + 2, ..t }),
        )
    }

    /// Writes the camera and settings through `queue` and records the occluder map and,
    /// when the Hi-Z test applies ([`SplitSettings::hiz_applies`]), occluder fusion's
    /// pyramid (one compute pass; timestamps, when given, at slots `first` and `first + 1`).
    pub fn encode_occluder_map(
        &self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        bindings: &SplitBindings,
        camera: &SplitCamera,
        grain_count: u32,
        timestamps: Option<SplitTimestamps<'_>>,
    ) -> Result<(), SplitError> {
        if camera.size() != self.options.size {
            return Err(SplitError::InvalidCamera {
                field: "size",
                reason: format!("{:?} differs from the splitter's {:?}", camera.size(), self.options.size),
            });
        }
        let (x, y, blocks) = self.grid(grain_count)?;
        let stride = if self.map.kind == OccluderMapKind::Atomic64 { 2 } else { 1 };
        queue.write_buffer(&self.camera, 0, bytemuck::bytes_of(camera));
        let hiz = HizParams::new(camera).filter(|_| self.settings.hiz_applies(camera));
        let params = self.settings.params(grain_count, stride, blocks, hiz.is_some());
        queue.write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
        if let Some(hiz) = &hiz {
            queue.write_buffer(&self.hiz.params, 0, bytemuck::bytes_of(hiz));
        }
        encoder.clear_buffer(&self.map.words, 0, None);
        if let Some((ids, _)) = &self.map.ids_and_splats {
            encoder.clear_buffer(ids, 0, None);
        }
        let temporal = hiz.is_some() && self.settings.temporal_occluders;
        if temporal {
            encoder.clear_buffer(&self.hiz.cover, 0, None);
        }
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("occluder map"),
            timestamp_writes: writes(timestamps),
        });
        pass.set_bind_group(0, &bindings.map, &[]);
        for pipeline in &self.map.pipelines {
            pass.set_pipeline(pipeline);
            pass.dispatch_workgroups(x, y, 1);
        }
        if hiz.is_some() {
            let groups =
                |level: &PyramidLevel| (level.width.div_ceil(HIZ_WORKGROUP), level.height.div_ceil(HIZ_WORKGROUP));
            pass.set_bind_group(0, &bindings.hiz, &[0]);
            if temporal {
                pass.set_pipeline(&self.hiz.cover_pass);
                pass.dispatch_workgroups(x, y, 1);
            }
            pass.set_pipeline(&self.hiz.bound);
            let (gx, gy) = groups(&self.hiz.levels[0]);
            pass.dispatch_workgroups(gx, gy, 1);
            pass.set_pipeline(&self.hiz.reduce);
            for (k, level) in self.hiz.levels.iter().enumerate().skip(1) {
                pass.set_bind_group(0, &bindings.hiz, &[k as u32 * self.hiz.stride]);
                let (gx, gy) = groups(level);
                pass.dispatch_workgroups(gx, gy, 1);
            }
        }
        Ok(())
    }

    /// Records the splitter's passes (one compute pass; timestamps at `first` and
    /// `first + 1`), reading the occluder map, camera and settings of the last
    /// [`GrainSplitter::encode_occluder_map`] with the same `grain_count`.
    pub fn encode_split(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        bindings: &SplitBindings,
        grain_count: u32,
        timestamps: Option<SplitTimestamps<'_>>,
    ) -> Result<(), SplitError> {
        let (x, y, _) = self.grid(grain_count)?;
        encoder.clear_buffer(&self.counters, 0, None);
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("split"),
            timestamp_writes: writes(timestamps),
        });
        pass.set_bind_group(0, &bindings.split, &[]);
        pass.set_pipeline(&self.count);
        pass.dispatch_workgroups(x, y, 1);
        if self.options.order == ListOrder::Stable {
            pass.set_pipeline(&self.scan);
            pass.dispatch_workgroups(1, 1, 1);
        }
        pass.set_pipeline(&self.offsets);
        pass.dispatch_workgroups(1, 1, 1);
        pass.set_pipeline(&self.write);
        pass.dispatch_workgroups(x, y, 1);
        Ok(())
    }

    /// The `(x, y)` workgroup grid and the block count of `grain_count` grains.
    fn grid(&self, grain_count: u32) -> Result<(u32, u32, u32), SplitError> {
        if grain_count > self.options.capacity {
            return Err(SplitError::TooLarge {
                what: "grain count",
                requested: u64::from(grain_count),
                limit: u64::from(self.options.capacity),
            });
        }
        let blocks = grain_count.div_ceil(SPLIT_WORKGROUP);
        let x = blocks.clamp(1, MAX_GROUPS_PER_DIMENSION);
        Ok((x, blocks.div_ceil(x).max(1), blocks))
    }

    /// Forgets every grain's tier history (the next frame uses the plain thresholds).
    pub fn reset_history(&self, encoder: &mut wgpu::CommandEncoder) {
        encoder.clear_buffer(&self.state, 0, None);
    }

    /// The settings.
    pub fn settings(&self) -> &SplitSettings {
        &self.settings
    }

    /// The options, with the occluder map kind resolved (never `Auto`).
    pub fn options(&self) -> &SplitterOptions {
        &self.options
    }

    /// The element lists (`u32` grain indices, list `l` at `counters.offset[l]`).
    pub fn elements(&self) -> &wgpu::Buffer {
        &self.elements
    }

    /// The counters ([`crate::SplitCounters`]).
    pub fn counters(&self) -> &wgpu::Buffer {
        &self.counters
    }

    /// The indirect arguments ([`crate::ListIndirect`] per list; usage `INDIRECT`).
    pub fn indirect(&self) -> &wgpu::Buffer {
        &self.indirect
    }

    /// Byte offset of list `list`'s arguments in [`GrainSplitter::indirect`].
    pub fn indirect_offset(list: u32) -> u64 {
        u64::from(list * INDIRECT_WORDS) * 4
    }

    /// Occluder fusion's pyramid (`f32` texels, every level one after another: see
    /// [`GrainSplitter::pyramid_levels`]); meaningful after a frame the Hi-Z test applied to.
    pub fn pyramid(&self) -> &wgpu::Buffer {
        &self.hiz.pyramid
    }

    /// The pyramid's levels.
    pub fn pyramid_levels(&self) -> &[PyramidLevel] {
        &self.hiz.levels
    }

    /// The per-grain state words (tier code, model).
    pub fn state(&self) -> &wgpu::Buffer {
        &self.state
    }

    /// The occluder map's words and their stride per pixel: `~index` of the pixel's grain, 0
    /// for none (64-bit map: the low word of each pixel, stride 2).
    pub fn occluder_words(&self) -> (&wgpu::Buffer, u32) {
        match &self.map.ids_and_splats {
            None => (&self.map.words, 2),
            Some((ids, _)) => (ids, 1),
        }
    }

    /// Every buffer the splitter owns, named, with its usage. None can be mapped: a frame
    /// never waits on the CPU.
    pub fn buffers(&self) -> Vec<(&'static str, &wgpu::Buffer)> {
        let mut buffers = vec![
            ("camera", &self.camera),
            ("params", &self.params),
            ("occluder map", &self.map.words),
            ("state", &self.state),
            ("counters", &self.counters),
            ("block counts", &self.block_counts),
            ("elements", &self.elements),
            ("indirect", &self.indirect),
            ("fusion pyramid", &self.hiz.pyramid),
            ("two-phase cover", &self.hiz.cover),
            ("fusion params", &self.hiz.params),
            ("fusion level indices", &self.hiz.level_indices),
        ];
        if let Some((ids, splats)) = &self.map.ids_and_splats {
            buffers.push(("occluder ids", ids));
            buffers.push(("occluder squares", splats));
        }
        buffers
    }
}

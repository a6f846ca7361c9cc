//! What the tiers read: the grains and the splitter's lists, bound once.

/// The grains and the splitter's lists a tier reads (all `STORAGE`; the indirect arguments
/// also `INDIRECT`).
#[derive(Clone, Copy, Debug)]
pub struct ListInputs<'a> {
    /// `GrainInstance`s (centre and scale, rotation).
    pub instances: &'a wgpu::Buffer,
    /// The splitter's element lists (`GrainSplitter::elements`).
    pub elements: &'a wgpu::Buffer,
    /// The splitter's counters (`GrainSplitter::counters`).
    pub counters: &'a wgpu::Buffer,
    /// The splitter's indirect arguments (`GrainSplitter::indirect`). For the mesh tier, the
    /// mesh list's `draw_indexed` index count must be the mesh's
    /// (`SplitSettings::mesh_index_count`).
    pub indirect: &'a wgpu::Buffer,
}

// The mesh tier (crates/grain-renderer/src/mesh_tier.rs): the splitter's mesh list drawn with
// one draw_indexed_indirect into the screen G-buffer. Composed after grain-impostor's
// generated.wgsl and mesh_gbuffer.wgsl (camera at binding 0, instances at 1, MeshVertex,
// mesh_place, mesh_fragment) and this crate's generated declarations.

@group(0) @binding(2) var<storage, read> elements: array<u32>;
// The splitter's counters: first element of list l at COUNTER_OFFSET + l.
@group(0) @binding(3) var<storage, read> lists: array<u32>;
@group(0) @binding(4) var<uniform> mesh_tier: MeshTierUniforms;

// Instance i of the draw is element i of the mesh list; the mesh is modelled around
// mesh_tier.centre, which the grain's centre replaces (as the atlas does).
@vertex
fn mesh_tier_vertex(input: MeshVertex, @builtin(instance_index) instance_index: u32) -> MeshFragment {
    let g = elements[lists[COUNTER_OFFSET + mesh_tier.list.x] + instance_index];
    var shifted = input;
    shifted.position = input.position - mesh_tier.centre.xyz;
    return mesh_place(shifted, instances[g]);
}

//! Images through the CPU cone tracer: [`svo_tracer::trace_cone`] for every pixel's cone, on
//! every core.

use abuffer_mask::MaskTable;
use svo_brick::PackedTree;
use svo_tracer::{Camera, TraceSettings, trace_cone};

use crate::frame::Frame;
use crate::parallel::per_pixel;

/// Renders every pixel of `camera` with [`trace_cone`] (Algorithm 1 under `settings.model`)
/// on every core. Each pixel is a function of its cone alone, so the frame is the same bits
/// whatever the number of threads. [`Frame::elements`] counts the cone elements sampled.
pub fn render<const W: usize>(
    packed: &PackedTree,
    table: &MaskTable<W>,
    camera: &Camera,
    settings: &TraceSettings,
) -> Frame {
    let (width, height) = camera.size();
    let results = per_pixel(width, height, |x, y| trace_cone(packed, table, &camera.pixel_cone(x, y), settings));
    let mut frame = Frame {
        width,
        height,
        radiance: Vec::with_capacity(results.len()),
        coverage: Vec::with_capacity(results.len()),
        elements: Vec::with_capacity(results.len()),
    };
    for result in results {
        frame.radiance.push(result.radiance);
        frame.coverage.push(result.coverage);
        frame.elements.push(result.elements);
    }
    frame
}

//! PNG charts with plotters: the bundled font, an RGB buffer, and the PNG encoder of
//! `image` (plotters' own encoder would pull in a second `image` version).

use std::fmt::Debug;
use std::path::Path;

use plotters::coord::{CoordTranslate, Shift};
use plotters::prelude::*;

/// The drawing area charts draw into.
pub type Area<'a> = DrawingArea<BitMapBackend<'a>, Shift>;

/// Formats a plotters error.
pub fn drawing_error<E: Debug>(error: E) -> String {
    format!("chart drawing failed: {error:?}")
}

/// Renders `draw` into a white `size` image and writes it to `path` as PNG.
pub fn render_png(
    path: &Path,
    size: (u32, u32),
    draw: impl FnOnce(&Area<'_>) -> Result<(), String>,
) -> Result<(), String> {
    plotters::style::register_font("sans-serif", FontStyle::Normal, epaint_default_fonts::UBUNTU_LIGHT)
        .map_err(|_| "the bundled font is invalid".to_owned())?;
    let mut pixels = vec![0_u8; (size.0 * size.1 * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut pixels, size).into_drawing_area();
        root.fill(&WHITE).map_err(drawing_error)?;
        draw(&root)?;
        root.present().map_err(drawing_error)?;
    }
    let image = image::RgbImage::from_raw(size.0, size.1, pixels).ok_or("chart buffer has the wrong size")?;
    image.save(path).map_err(|e| format!("cannot write {}: {e}", path.display()))
}

/// A legend sample: a horizontal stroke `length` pixels long.
pub fn legend_stroke(color: RGBColor, width: u32, length: i32) -> impl Fn((i32, i32)) -> PathElement<(i32, i32)> {
    move |(x, y)| PathElement::new([(x, y), (x + length, y)], color.stroke_width(width))
}

/// Draws the legend of `chart` in the project's style (framed, translucent) at `position`.
pub fn draw_legend<'a, CT: CoordTranslate>(
    chart: &mut ChartContext<'a, BitMapBackend<'a>, CT>,
    font_size: u32,
    position: SeriesLabelPosition,
) -> Result<(), String> {
    chart
        .configure_series_labels()
        .label_font(("sans-serif", font_size))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .position(position)
        .draw()
        .map_err(drawing_error)
}

//! PNG charts with plotters: the bundled font, an RGB buffer, and the PNG encoder of
//! `image` (plotters' own encoder would pull in a second `image` version). Every chart
//! written is listed in its folder's [`CHART_LIST`], so that the report tells charts from
//! renders without guessing from file names.

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

/// The file in a folder that lists the charts written into it, one file name per line.
pub const CHART_LIST: &str = "charts.txt";

/// Renders `draw` into a white `size` image, writes it to `path` as PNG and lists it in
/// the folder's [`CHART_LIST`].
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
    image.save(path).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    list_chart(path)
}

/// Adds `path`'s file name to its folder's [`CHART_LIST`] unless it is there.
fn list_chart(path: &Path) -> Result<(), String> {
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).ok_or("a chart path has no file name")?;
    let list = path.with_file_name(CHART_LIST);
    let mut text = match std::fs::read_to_string(&list) {
        Ok(text) => text,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => String::new(),
        Err(e) => return Err(format!("cannot read {}: {e}", list.display())),
    };
    if !text.lines().any(|line| line == name) {
        text += &name;
        text.push('\n');
        std::fs::write(&list, text).map_err(|e| format!("cannot write {}: {e}", list.display()))?;
    }
    Ok(())
}

/// The charts listed in `dir`'s [`CHART_LIST`] that exist, sorted (none without a list).
pub fn charts_in(dir: &Path) -> Result<Vec<String>, String> {
    let list = dir.join(CHART_LIST);
    let text = match std::fs::read_to_string(&list) {
        Ok(text) => text,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => return Err(format!("cannot read {}: {e}", list.display())),
    };
    let mut charts: Vec<String> =
        text.lines().filter(|name| !name.is_empty() && dir.join(name).is_file()).map(str::to_owned).collect();
    charts.sort();
    charts.dedup();
    Ok(charts)
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn written_charts_are_listed_once_and_only_while_they_exist() {
        let dir = std::env::temp_dir().join(format!("xtask-chart-list-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let blank = |_: &Area<'_>| Ok(());
        render_png(&dir.join("b.png"), (4, 4), blank).unwrap();
        render_png(&dir.join("a.png"), (4, 4), blank).unwrap();
        render_png(&dir.join("b.png"), (4, 4), blank).unwrap();
        assert_eq!(std::fs::read_to_string(dir.join(CHART_LIST)).unwrap(), "b.png\na.png\n");
        assert_eq!(charts_in(&dir).unwrap(), ["a.png", "b.png"]);
        std::fs::remove_file(dir.join("a.png")).unwrap();
        assert_eq!(charts_in(&dir).unwrap(), ["b.png"]);
        assert!(charts_in(&dir.join("absent")).unwrap().is_empty());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}

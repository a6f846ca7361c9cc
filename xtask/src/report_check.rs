//! `cargo xtask showcase --check DIR`: the page opened in headless Chromium. It fails when
//! an image does not load (or loads at another size than its file's), when a chart is empty,
//! when a table has no row, or when a PNG of the folder is not on the page; then it saves a
//! full-page screenshot, `DIR/screenshot.png`.
//!
//! Chromium loads the page in an iframe of a small harness page (written to a temporary
//! folder; `--allow-file-access-from-files` lets it read the page's document), whose script
//! lists every image as the browser decoded it and every table's rows, and `--dump-dom`
//! prints that list. Emptiness is then judged on the chart's file ([`chart_is_empty`]).

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The screenshot's file name in the checked folder (not itself a figure of the page).
pub const SCREENSHOT: &str = "screenshot.png";
/// The screenshot's width in CSS pixels.
const SCREENSHOT_WIDTH: u32 = 1400;
/// The tallest screenshot taken: Chromium's software compositor refuses larger surfaces.
const SCREENSHOT_MAX_HEIGHT: u32 = 60_000;

/// The harness: lists the iframe's images and tables into `#result`, one per line.
const HARNESS: &str = r#"<!doctype html><html><head><meta charset="utf-8"></head><body>
<pre id="result">not loaded</pre>
<iframe id="page" style="width:1400px;height:900px" src="PAGE_URL"></iframe>
<script>
document.getElementById('page').onload = function () {
  const doc = this.contentDocument, lines = [];
  for (const img of doc.images) {
    lines.push(['image', img.complete ? 'complete' : 'incomplete', img.naturalWidth, img.naturalHeight,
                img.className, img.getAttribute('src')].join('\t'));
  }
  doc.querySelectorAll('table').forEach(function (table, i) {
    lines.push(['table', i, table.querySelectorAll('tr').length].join('\t'));
  });
  lines.push(['height', doc.documentElement.scrollHeight].join('\t'));
  document.getElementById('result').textContent = lines.join('\n');
};
</script></body></html>
"#;

/// An image as the browser decoded it.
#[derive(Debug, PartialEq, Eq)]
struct LoadedImage {
    src: String,
    class: String,
    size: Option<(u32, u32)>,
}

/// What the harness reported.
#[derive(Debug, Default, PartialEq, Eq)]
struct Report {
    images: Vec<LoadedImage>,
    table_rows: Vec<usize>,
    height: u32,
}

/// The browser: `$CHROMIUM`, else the first of Debian's and Google's names on `PATH`.
fn browser() -> Result<PathBuf, String> {
    if let Some(path) = std::env::var_os("CHROMIUM") {
        return Ok(PathBuf::from(path));
    }
    let path = std::env::var_os("PATH").unwrap_or_default();
    for name in ["chromium", "chromium-browser", "google-chrome", "chrome"] {
        for dir in std::env::split_paths(&path) {
            if dir.join(name).is_file() {
                return Ok(dir.join(name));
            }
        }
    }
    Err("no Chromium found: install Debian's `chromium` (`bash .ci/setup --report` does) or set CHROMIUM".into())
}

/// Runs headless Chromium on `url` with `args`, returning its standard output.
fn chromium(browser: &Path, args: &[String], url: &str) -> Result<String, String> {
    let output = Command::new(browser)
        .args(["--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars", "--allow-file-access-from-files"])
        .args(args)
        .arg(url)
        .output()
        .map_err(|e| format!("cannot run {}: {e}", browser.display()))?;
    if !output.status.success() {
        let stderr = String::from_utf8_lossy(&output.stderr);
        return Err(format!("{} failed ({}): {}", browser.display(), output.status, stderr.trim()));
    }
    Ok(String::from_utf8_lossy(&output.stdout).into_owned())
}

/// The text of `#result` in the dumped DOM, unescaped.
fn parse_report(dom: &str) -> Result<Report, String> {
    let start = dom.find("<pre id=\"result\">").ok_or("the harness's result is missing from the dumped page")?;
    let text = &dom[start + "<pre id=\"result\">".len()..];
    let text = &text[..text.find("</pre>").ok_or("the harness's result is not closed")?];
    let text = text.replace("&lt;", "<").replace("&gt;", ">").replace("&quot;", "\"").replace("&amp;", "&");
    if text == "not loaded" {
        return Err("the page did not finish loading in the browser".into());
    }
    let mut report = Report::default();
    for line in text.lines() {
        let fields: Vec<&str> = line.split('\t').collect();
        let number = |i: usize| fields.get(i).and_then(|f| f.parse::<u32>().ok());
        match fields.first() {
            Some(&"image") => {
                let (w, h) = (number(2).unwrap_or(0), number(3).unwrap_or(0));
                report.images.push(LoadedImage {
                    src: fields.get(5).unwrap_or(&"").to_string(),
                    class: fields.get(4).unwrap_or(&"").to_string(),
                    size: (fields.get(1) == Some(&"complete") && w > 0 && h > 0).then_some((w, h)),
                });
            }
            Some(&"table") => report.table_rows.push(number(2).unwrap_or(0) as usize),
            Some(&"height") => report.height = number(1).unwrap_or(0),
            _ => return Err(format!("unexpected line from the harness: {line}")),
        }
    }
    Ok(report)
}

/// The share of a chart's pixels that are coloured (saturation above ¼, not near black).
///
/// The project's charts draw axes, grids and text in black and greys on white; every
/// data series is coloured. A legend without data colours 24 × 3 px per entry, under
/// 0.01 % of a 1200 × 800 chart per entry; one data line across the plot colours ~0.3 %.
pub fn coloured_share(image: &image::RgbImage) -> f64 {
    let coloured = image
        .pixels()
        .filter(|p| {
            let (max, min) = (p.0.iter().max().copied().unwrap_or(0), p.0.iter().min().copied().unwrap_or(0));
            max > 40 && f64::from(max - min) > 0.25 * f64::from(max)
        })
        .count();
    coloured as f64 / (f64::from(image.width()) * f64::from(image.height())).max(1.0)
}

/// Below this [`coloured_share`] a chart is empty: ten legend entries without data stay
/// under it, a single data line across the plot is above it.
pub const EMPTY_CHART_SHARE: f64 = 0.001;

/// Whether the chart at `path` shows no data (see [`coloured_share`]).
pub fn chart_is_empty(path: &Path) -> Result<(bool, f64), String> {
    let image = image::open(path).map_err(|e| format!("cannot read {}: {e}", path.display()))?.to_rgb8();
    let share = coloured_share(&image);
    Ok((share < EMPTY_CHART_SHARE, share))
}

/// Every PNG under `dir`, relative to it, except the screenshot.
fn png_files(dir: &Path) -> Result<BTreeSet<String>, String> {
    let mut found = BTreeSet::new();
    let mut pending = vec![dir.to_path_buf()];
    while let Some(folder) = pending.pop() {
        let entries = std::fs::read_dir(&folder).map_err(|e| format!("cannot list {}: {e}", folder.display()))?;
        for entry in entries {
            let path = entry.map_err(|e| format!("cannot list {}: {e}", folder.display()))?.path();
            if path.is_dir() {
                pending.push(path);
            } else if path.extension().is_some_and(|e| e == "png") {
                let relative = path.strip_prefix(dir).map_err(|e| e.to_string())?;
                let relative = relative.to_string_lossy().replace('\\', "/");
                if relative != SCREENSHOT {
                    found.insert(relative);
                }
            }
        }
    }
    Ok(found)
}

/// What is wrong with the page, given the browser's report: one line per fault.
fn faults(dir: &Path, report: &Report) -> Result<(Vec<String>, usize, f64), String> {
    let mut faults = Vec::new();
    let mut shown = BTreeSet::new();
    let (mut charts, mut least_share) = (0, f64::INFINITY);
    for image in &report.images {
        let path = dir.join(&image.src);
        shown.insert(image.src.clone());
        let Some(size) = image.size else {
            faults.push(format!("{}: did not load", image.src));
            continue;
        };
        match image::image_dimensions(&path) {
            Ok(file) if file == size => {}
            Ok(file) => faults.push(format!("{}: loaded at {size:?}, the file is {file:?}", image.src)),
            Err(e) => faults.push(format!("{}: {e}", image.src)),
        }
        if image.class == "chart" {
            charts += 1;
            let (empty, share) = chart_is_empty(&path)?;
            least_share = least_share.min(share);
            if empty {
                faults.push(format!(
                    "{}: an empty chart ({:.4} % coloured pixels, under {:.2} %)",
                    image.src,
                    100.0 * share,
                    100.0 * EMPTY_CHART_SHARE
                ));
            }
        }
    }
    for (i, rows) in report.table_rows.iter().enumerate() {
        if *rows < 2 {
            faults.push(format!("table {i}: {rows} rows (a header and no data)"));
        }
    }
    for file in png_files(dir)?.difference(&shown) {
        faults.push(format!("{file}: in the folder but not on the page"));
    }
    if report.images.is_empty() {
        faults.push("the page shows no image".into());
    }
    Ok((faults, charts, least_share))
}

/// The gallery of failure modes, relative to the workspace root: its images are links into
/// the showcase's folder.
pub const FAILURE_MODES: &str = "docs/failure-modes.md";
/// How [`FAILURE_MODES`] links an image of the showcase: `../target/showcase/<stage>/<file>`.
const GALLERY_PREFIX: &str = "../target/showcase/";

/// The showcase images `markdown` links (`![alt](../target/showcase/<stage>/<file>)`), as
/// paths relative to the showcase's folder, in order.
pub fn gallery_images(markdown: &str) -> Vec<String> {
    markdown
        .split("](")
        .skip(1)
        .filter_map(|rest| rest.split(')').next())
        .filter_map(|link| link.strip_prefix(GALLERY_PREFIX))
        .map(str::to_owned)
        .collect()
}

/// The images of [`FAILURE_MODES`] that `dir` (a showcase run) lacks: the gallery must show
/// what the showcase writes. An error when the gallery cannot be read or links no image.
fn missing_gallery_images(dir: &Path) -> Result<(usize, Vec<String>), String> {
    let path = crate::workspace_root().join(FAILURE_MODES);
    let text = std::fs::read_to_string(&path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    let images = gallery_images(&text);
    if images.is_empty() {
        return Err(format!("{FAILURE_MODES} links no image under {GALLERY_PREFIX}"));
    }
    let missing = images
        .iter()
        .filter(|image| !dir.join(image).is_file())
        .map(|image| format!("{FAILURE_MODES}: {GALLERY_PREFIX}{image} is not written by the showcase"))
        .collect();
    Ok((images.len(), missing))
}

/// Checks `dir/index.html` and writes `dir/screenshot.png`; checks that every image
/// [`FAILURE_MODES`] links is in `dir`.
pub fn run(dir: &Path) -> Result<(), String> {
    let page = dir.join("index.html");
    let page = page.canonicalize().map_err(|e| format!("cannot open {}: {e}", page.display()))?;
    let dir = page.parent().ok_or("the page has no folder")?.to_path_buf();
    let browser = browser()?;
    let harness_dir = std::env::temp_dir().join(format!("showcase-check-{}", std::process::id()));
    std::fs::create_dir_all(&harness_dir).map_err(|e| format!("cannot create {}: {e}", harness_dir.display()))?;
    let harness = harness_dir.join("harness.html");
    let page_url = format!("file://{}", page.display());
    std::fs::write(&harness, HARNESS.replace("PAGE_URL", &page_url))
        .map_err(|e| format!("cannot write {}: {e}", harness.display()))?;
    let harness_url = format!("file://{}", harness.display());
    let dom = chromium(&browser, &["--virtual-time-budget=30000".into(), "--dump-dom".into()], &harness_url);
    let _ = std::fs::remove_dir_all(&harness_dir);
    let report = parse_report(&dom?)?;
    let (mut faults, charts, least_share) = faults(&dir, &report)?;
    let (gallery, missing) = missing_gallery_images(&dir)?;
    println!("{FAILURE_MODES}: {gallery} image links, {} missing from {}", missing.len(), dir.display());
    faults.extend(missing);
    println!(
        "{}: {} images ({charts} charts, the least coloured at {:.3} %), {} tables, {} px tall",
        page.display(),
        report.images.len(),
        100.0 * least_share,
        report.table_rows.len(),
        report.height
    );
    let height = report.height.clamp(1, SCREENSHOT_MAX_HEIGHT);
    let screenshot = dir.join(SCREENSHOT);
    chromium(
        &browser,
        &[
            format!("--window-size={SCREENSHOT_WIDTH},{height}"),
            format!("--screenshot={}", screenshot.display()),
            "--virtual-time-budget=30000".into(),
        ],
        &page_url,
    )?;
    let shot =
        image::image_dimensions(&screenshot).map_err(|e| format!("no screenshot at {}: {e}", screenshot.display()))?;
    println!("wrote {} ({} × {} px)", screenshot.display(), shot.0, shot.1);
    if faults.is_empty() {
        println!(
            "the page is complete: every image loaded, every chart has data, every PNG is shown, \
             every image of the gallery exists"
        );
        Ok(())
    } else {
        Err(format!("{} faults on {}:\n  {}", faults.len(), page.display(), faults.join("\n  ")))
    }
}

#[cfg(test)]
mod tests {
    use plotters::prelude::*;

    use super::*;
    use crate::chart::{draw_legend, drawing_error, legend_stroke, render_png};

    /// A 1200 × 800 chart with eight legend entries, drawing their data or not.
    fn chart(path: &Path, with_data: bool) {
        render_png(path, (1200, 800), |root| {
            let mut chart = ChartBuilder::on(root)
                .caption("test", ("sans-serif", 28))
                .x_label_area_size(40)
                .y_label_area_size(40)
                .build_cartesian_2d(0.0..1.0, 0.0..1.0)
                .map_err(drawing_error)?;
            chart.configure_mesh().draw().map_err(drawing_error)?;
            let colours = [RED, BLUE, GREEN, MAGENTA, CYAN, RGBColor(200, 120, 0), RGBColor(120, 0, 200), YELLOW];
            for (i, colour) in colours.into_iter().enumerate() {
                // Without data: one point, which draws nothing but gives the legend entry.
                let points: Vec<(f64, f64)> =
                    if with_data { vec![(0.0, 0.1 * i as f64), (1.0, 0.1 * i as f64)] } else { vec![(0.5, 0.5)] };
                chart
                    .draw_series(LineSeries::new(points, colour.stroke_width(2)))
                    .map_err(drawing_error)?
                    .label(format!("series {i}"))
                    .legend(legend_stroke(colour, 3, 24));
            }
            draw_legend(&mut chart, 18, SeriesLabelPosition::UpperRight)
        })
        .unwrap();
    }

    #[test]
    fn the_gallery_links_showcase_images_only() {
        let markdown = "![a](../target/showcase/fig9/x.png) text [doc](ARCHITECTURE.md) \
                        ![b](../target/showcase/svo/y_z.png)";
        assert_eq!(gallery_images(markdown), ["fig9/x.png", "svo/y_z.png"]);
        let gallery = std::fs::read_to_string(crate::workspace_root().join(FAILURE_MODES)).unwrap();
        let images = gallery_images(&gallery);
        assert!(images.len() >= 20, "{} images", images.len());
        // Each names a stage of the showcase.
        for image in &images {
            let stage = image.split('/').next().unwrap();
            assert!(crate::showcase::STAGES.iter().any(|s| s.folder == stage), "{image}");
        }
    }

    #[test]
    fn a_chart_with_a_legend_and_no_data_is_empty_and_one_with_data_is_not() {
        let dir = std::env::temp_dir().join(format!("report-check-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let (empty, full) = (dir.join("empty.png"), dir.join("full.png"));
        chart(&empty, false);
        chart(&full, true);
        let (is_empty, share) = chart_is_empty(&empty).unwrap();
        assert!(is_empty, "legend only: {share}");
        let (is_empty, share) = chart_is_empty(&full).unwrap();
        assert!(!is_empty, "eight lines: {share}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn the_harness_report_is_parsed_and_faults_named() {
        let dom = "<html><body><pre id=\"result\">image\tcomplete\t4\t2\trender\ta/x.png\n\
                   image\tcomplete\t0\t0\tchart\ta/missing.png\ntable\t0\t1\nheight\t900</pre></body></html>";
        let report = parse_report(dom).unwrap();
        assert_eq!(report.images.len(), 2);
        assert_eq!(report.images[0], LoadedImage { src: "a/x.png".into(), class: "render".into(), size: Some((4, 2)) });
        assert_eq!(report.images[1].size, None);
        assert_eq!((report.table_rows.clone(), report.height), (vec![1], 900));
        let dir = std::env::temp_dir().join(format!("report-faults-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("a")).unwrap();
        image::RgbImage::new(4, 2).save(dir.join("a/x.png")).unwrap();
        image::RgbImage::new(3, 3).save(dir.join("a/unshown.png")).unwrap();
        let (faults, _, _) = faults(&dir, &report).unwrap();
        assert_eq!(
            faults,
            [
                "a/missing.png: did not load",
                "table 0: 1 rows (a header and no data)",
                "a/unshown.png: in the folder but not on the page"
            ]
        );
        std::fs::remove_dir_all(&dir).unwrap();
        assert!(parse_report("<pre id=\"result\">not loaded</pre>").is_err());
    }
}

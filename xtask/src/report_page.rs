//! The showcase's page, `index.html`: one section per paper, one article per stage with
//! its command, its charts, its images (each render beside the images that share its
//! view: the reference, the error maps), its CSV tables and its printed output. Readable
//! offline: every link is relative to the page, nothing is fetched from the network and
//! the page has no script.

use std::fmt::Write as _;
use std::path::Path;

/// A paper and the stages shown under it.
pub struct Section<'a> {
    /// The anchor (`#id`).
    pub id: &'a str,
    /// The heading: authors, title, venue.
    pub title: &'a str,
    /// Its stages, in order.
    pub articles: Vec<Article>,
}

/// What one stage wrote and printed.
pub struct Article {
    /// The stage's folder under the page's (also its anchor).
    pub folder: String,
    /// The heading.
    pub title: String,
    /// What it shows, one paragraph.
    pub about: String,
    /// The command that produced it.
    pub command: String,
    /// Its wall-clock time in seconds.
    pub seconds: f64,
    /// Chart files (relative to `folder`), drawn by the project's chart writer.
    /// with their sizes in pixels.
    pub charts: Vec<(String, (u32, u32))>,
    /// The other PNG files with their widths in pixels, grouped: one row per subject.
    pub image_rows: Vec<Vec<(String, u32)>>,
    /// CSV files with their parsed rows (the first row is the header).
    pub tables: Vec<(String, Vec<Vec<String>>)>,
    /// The other files (atlases, JSON, …), linked.
    pub other_files: Vec<String>,
    /// What it printed.
    pub output: String,
}

/// The header's facts.
pub struct Meta<'a> {
    /// The page's heading.
    pub title: &'a str,
    /// The adapter the GPU stages ran on.
    pub adapter: &'a str,
    /// The commit (and whether the tree had changes).
    pub commit: &'a str,
    /// The settings (`quick`, `default`, `full`) and what they mean.
    pub settings: &'a str,
    /// When the page was written (UTC).
    pub date: &'a str,
    /// The machine: CPU cores.
    pub machine: &'a str,
    /// Total wall-clock time in seconds.
    pub seconds: f64,
}

/// Renders narrower than this are shown enlarged by an integer factor (pixels kept sharp),
/// so that a 96-pixel render can be judged.
const RENDER_SHOWN_WIDTH: u32 = 320;

/// The width a render `width` pixels wide is shown at: enlarged by the largest integer
/// factor that keeps it within [`RENDER_SHOWN_WIDTH`], never shrunk.
fn shown_width(width: u32) -> u32 {
    width * (RENDER_SHOWN_WIDTH / width.max(1)).max(1)
}

/// Charts are shown at most this wide, two side by side, except panels of charts
/// ([`WIDE_CHART_ASPECT`]), which take the page's width.
const CHART_SHOWN_WIDTH: u32 = 640;

/// Width over height from which a chart is a row of panels, shown up to the page's width.
const WIDE_CHART_ASPECT: f64 = 2.0;

/// The page's content width in CSS pixels (the style's `max-width` less its padding).
const CONTENT_WIDTH: u32 = 1368;

/// The width a chart of `(width, height)` pixels is shown at (never enlarged).
fn chart_shown_width((width, height): (u32, u32)) -> u32 {
    let wide = f64::from(width) > WIDE_CHART_ASPECT * f64::from(height.max(1));
    width.min(if wide { CONTENT_WIDTH } else { CHART_SHOWN_WIDTH })
}

/// Rows of a CSV table shown on the page; a longer table is cut there with a link to the
/// whole file.
pub const TABLE_ROWS_SHOWN: usize = 60;

/// `text` with `&`, `<`, `>` and `"` escaped for HTML text and attribute values.
pub fn escape(text: &str) -> String {
    let mut escaped = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => escaped.push_str("&amp;"),
            '<' => escaped.push_str("&lt;"),
            '>' => escaped.push_str("&gt;"),
            '"' => escaped.push_str("&quot;"),
            _ => escaped.push(c),
        }
    }
    escaped
}

/// The fields of one CSV line (RFC 4180 quoting: `"a,b"` and `""` inside quotes).
pub fn csv_fields(line: &str) -> Vec<String> {
    let (mut fields, mut field) = (Vec::new(), String::new());
    let (mut quoted, mut chars) = (false, line.chars().peekable());
    while let Some(c) = chars.next() {
        match (c, quoted) {
            ('"', true) if chars.peek() == Some(&'"') => {
                chars.next();
                field.push('"');
            }
            ('"', _) => quoted = !quoted,
            (',', false) => fields.push(std::mem::take(&mut field)),
            _ => field.push(c),
        }
    }
    fields.push(field);
    fields
}

/// The rows of the CSV file at `path`, or an error naming it. A file without a data row
/// is an error: the page would show an empty table.
pub fn read_csv(path: &Path) -> Result<Vec<Vec<String>>, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    let rows: Vec<Vec<String>> = text.lines().filter(|l| !l.trim().is_empty()).map(csv_fields).collect();
    if rows.len() < 2 {
        return Err(format!("{}: a table without data rows", path.display()));
    }
    Ok(rows)
}

/// Which part of an image's file name (its `_`-separated words, without `.png`) names
/// its subject: images of one subject share a row.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImageSubject {
    /// The first `n` words (`ball_plane_dm` with 2: `ball_plane`).
    FirstWords(usize),
    /// The last word (`reference_02` and `flip_02`: `02`).
    LastWord,
}

impl ImageSubject {
    /// The subject part of `stem`, and the rest (the image's role in its row).
    fn split(self, stem: &str) -> (String, String) {
        let words: Vec<&str> = stem.split('_').collect();
        let (subject, role) = match self {
            Self::FirstWords(n) => {
                let n = n.min(words.len());
                (&words[..n], &words[n..])
            }
            Self::LastWord => {
                let n = words.len().saturating_sub(1);
                (&words[n..], &words[..n])
            }
        };
        (subject.join("_"), role.join("_"))
    }
}

/// Where an image's role puts it in its row: the reference first, error maps last.
fn role_rank(role: &str) -> u8 {
    match role {
        "truth" | "reference" | "mesh" => 0,
        "flip" | "error" => 2,
        _ => 1,
    }
}

/// The images grouped into rows by `subject`, rows in name order, in each row the
/// reference (`truth`, `reference`) first and error maps (`flip`, `error`) last.
pub fn image_rows(names: &[String], subject: ImageSubject) -> Vec<Vec<String>> {
    let mut keyed: Vec<(String, u8, String, String)> = names
        .iter()
        .map(|name| {
            let (subject, role) = subject.split(name.strip_suffix(".png").unwrap_or(name));
            (subject, role_rank(&role), role, name.clone())
        })
        .collect();
    keyed.sort();
    let mut rows: Vec<(String, Vec<String>)> = Vec::new();
    for (subject, _, _, name) in keyed {
        match rows.last_mut() {
            Some((last, row)) if *last == subject => row.push(name),
            _ => rows.push((subject, vec![name])),
        }
    }
    rows.into_iter().map(|(_, row)| row).collect()
}

const STYLE: &str = "\
body{font-family:system-ui,sans-serif;margin:0 auto;max-width:1400px;padding:0 16px;color:#222}
h1{margin-bottom:4px}h2{border-bottom:2px solid #444;margin-top:48px}h3{margin-top:32px}
table{border-collapse:collapse;font-size:13px;margin:6px 0}td,th{border:1px solid #ccc;padding:2px 6px;text-align:right}
th{background:#eee}table.meta td,table.meta th{text-align:left}
.grid{display:flex;flex-wrap:wrap;gap:10px}.row{display:flex;flex-wrap:wrap;gap:6px;margin:8px 0}
figure{margin:0}figcaption{font-size:12px;color:#555;word-break:break-all;max-width:480px}
img.chart{max-width:100%;height:auto}.row figure{max-width:calc(33.3% - 4px)}img.render{max-width:100%;height:auto;image-rendering:pixelated}
pre{background:#f6f6f6;padding:8px;font-size:12px;overflow-x:auto;max-height:480px}
code{background:#f0f0f0;padding:1px 4px}.time{color:#666}nav a{margin-right:16px}
";

impl Article {
    fn write_html(&self, html: &mut String) {
        let link = |file: &str| format!("{}/{}", escape(&self.folder), escape(file));
        let _ = writeln!(html, "<article id=\"{}\">", escape(&self.folder));
        let _ = writeln!(html, "<h3>{}</h3>\n<p>{}</p>", escape(&self.title), escape(&self.about));
        let _ = writeln!(
            html,
            "<p><code>{}</code> <span class=\"time\">{:.0} s</span></p>",
            escape(&self.command),
            self.seconds
        );
        if !self.charts.is_empty() {
            html.push_str("<div class=\"grid\">\n");
            for (chart, size) in &self.charts {
                let _ = writeln!(
                    html,
                    "<figure><a href=\"{0}\"><img class=\"chart\" src=\"{0}\" alt=\"{1}\" width=\"{2}\"></a><figcaption>{1}</figcaption></figure>",
                    link(chart),
                    escape(chart),
                    chart_shown_width(*size)
                );
            }
            html.push_str("</div>\n");
        }
        for row in &self.image_rows {
            html.push_str("<div class=\"row\">\n");
            for (image, width) in row {
                let _ = writeln!(
                    html,
                    "<figure><a href=\"{0}\"><img class=\"render\" src=\"{0}\" alt=\"{1}\" width=\"{2}\"></a><figcaption>{1}</figcaption></figure>",
                    link(image),
                    escape(image),
                    shown_width(*width)
                );
            }
            html.push_str("</div>\n");
        }
        for (name, rows) in &self.tables {
            let data = rows.len() - 1;
            let _ = writeln!(
                html,
                "<details{}><summary><a href=\"{}\">{}</a> ({data} rows)</summary>\n<table>",
                if data <= 24 { " open" } else { "" },
                link(name),
                escape(name)
            );
            for (i, row) in rows.iter().take(TABLE_ROWS_SHOWN + 1).enumerate() {
                let cell = if i == 0 { "th" } else { "td" };
                html.push_str("<tr>");
                for field in row {
                    let _ = write!(html, "<{cell}>{}</{cell}>", escape(field));
                }
                html.push_str("</tr>\n");
            }
            html.push_str("</table>\n");
            if data > TABLE_ROWS_SHOWN {
                let _ = writeln!(html, "<p>… {} more rows in the file.</p>", data - TABLE_ROWS_SHOWN);
            }
            html.push_str("</details>\n");
        }
        if !self.other_files.is_empty() {
            html.push_str("<p>Other files: ");
            let links: Vec<String> =
                self.other_files.iter().map(|f| format!("<a href=\"{}\">{}</a>", link(f), escape(f))).collect();
            html.push_str(&links.join(", "));
            html.push_str("</p>\n");
        }
        let _ =
            writeln!(html, "<details><summary>Printed output</summary><pre>{}</pre></details>", escape(&self.output));
        html.push_str("</article>\n");
    }
}

/// The page.
pub fn render(meta: &Meta<'_>, sections: &[Section<'_>]) -> String {
    let mut html = String::from("<!doctype html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n");
    let title = escape(meta.title);
    let _ = writeln!(html, "<title>Dense stackings, directional distance maps, pre-filtered voxels: {title}</title>");
    let _ = writeln!(html, "<style>\n{STYLE}</style>\n</head>\n<body>");
    let _ = writeln!(html, "<h1>{title}</h1>\n<p>Every figure below was measured by the command printed above it.</p>");
    html.push_str("<table class=\"meta\">\n");
    for (label, value) in [
        ("adapter", meta.adapter.to_owned()),
        ("commit", meta.commit.to_owned()),
        ("settings", meta.settings.to_owned()),
        ("written", meta.date.to_owned()),
        ("machine", meta.machine.to_owned()),
        ("total time", format!("{:.0} s", meta.seconds)),
    ] {
        let _ = writeln!(html, "<tr><th>{label}</th><td>{}</td></tr>", escape(&value));
    }
    html.push_str("</table>\n<nav>");
    for section in sections {
        let _ = write!(html, "<a href=\"#{}\">{}</a>", escape(section.id), escape(section.title));
    }
    html.push_str("</nav>\n");
    for section in sections {
        let _ = writeln!(html, "<section id=\"{}\">\n<h2>{}</h2>", escape(section.id), escape(section.title));
        for article in &section.articles {
            article.write_html(&mut html);
        }
        html.push_str("</section>\n");
    }
    html.push_str("</body>\n</html>\n");
    html
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_fields_follow_rfc_4180_quoting() {
        assert_eq!(csv_fields("a,b,,c"), ["a", "b", "", "c"]);
        assert_eq!(csv_fields(r#""x, y",2,"say ""hi""""#), ["x, y", "2", r#"say "hi""#]);
    }

    #[test]
    fn html_is_escaped() {
        assert_eq!(escape(r#"<a href="x">&</a>"#), "&lt;a href=&quot;x&quot;&gt;&amp;&lt;/a&gt;");
    }

    #[test]
    fn images_of_one_view_share_a_row() {
        let names: Vec<String> =
            ["svo_v0_truth.png", "svo_v0_masks.png", "svo_v1_truth.png", "svo_v0_alpha.png", "x.png"]
                .map(str::to_owned)
                .to_vec();
        assert_eq!(
            image_rows(&names, ImageSubject::FirstWords(2)),
            [vec!["svo_v0_truth.png", "svo_v0_alpha.png", "svo_v0_masks.png"], vec!["svo_v1_truth.png"], vec!["x.png"]]
        );
        let frames: Vec<String> =
            ["flip_01.png", "frame_00.png", "reference_00.png", "flip_00.png"].map(str::to_owned).to_vec();
        assert_eq!(
            image_rows(&frames, ImageSubject::LastWord),
            [vec!["reference_00.png", "frame_00.png", "flip_00.png"], vec!["flip_01.png"]]
        );
    }

    #[test]
    fn small_renders_are_enlarged_by_whole_factors_and_large_ones_kept() {
        assert_eq!([96, 160, 200, 320, 480, 1].map(shown_width), [288, 320, 200, 320, 480, 320]);
    }

    #[test]
    fn charts_are_shown_at_most_half_the_page_wide_unless_they_are_panels() {
        assert_eq!(chart_shown_width((480, 360)), 480);
        assert_eq!(chart_shown_width((1024, 768)), CHART_SHOWN_WIDTH);
        assert_eq!(chart_shown_width((2400, 600)), CONTENT_WIDTH);
        assert_eq!(chart_shown_width((1000, 400)), 1000);
    }

    #[test]
    fn a_table_without_data_is_an_error_naming_the_file() {
        let dir = std::env::temp_dir().join(format!("report-page-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("empty.csv");
        std::fs::write(&path, "a,b\n").unwrap();
        let error = read_csv(&path).unwrap_err();
        assert!(error.contains("empty.csv") && error.contains("without data rows"), "{error}");
        std::fs::write(&path, "a,b\n1,2\n").unwrap();
        assert_eq!(read_csv(&path).unwrap(), [["a", "b"], ["1", "2"]]);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}

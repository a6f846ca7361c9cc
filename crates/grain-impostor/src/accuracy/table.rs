//! The sweep's rows as CSV, written by `cargo xtask impostor-accuracy` and read back by the
//! atlas chooser ([`crate::choice`]).

use std::fmt::Write as _;

use octahedral_map::{SamplingMode, ViewLayout};

use super::metrics::ImageError;
use super::sweep::SweepRow;

/// The CSV header; `cloud_ms` is empty for an untimed row.
pub const CSV_HEADER: &str = "grain,n,p,mode,layout,diameter_px,ssim,rmse,atlas_bytes,cloud_ms";
/// The header of tables written before the sweep was timed (the committed
/// `data/impostor_accuracy.csv`): [`CSV_HEADER`] without `cloud_ms`; [`rows_from_csv`] reads
/// both.
pub const UNTIMED_CSV_HEADER: &str = "grain,n,p,mode,layout,diameter_px,ssim,rmse,atlas_bytes";

/// The name of a sampling mode in tables and charts.
pub fn sampling_mode_name(mode: SamplingMode) -> &'static str {
    match mode {
        SamplingMode::Planar => "planar",
        SamplingMode::Spherical => "spherical",
        SamplingMode::Mixed => "mixed",
        SamplingMode::MixedSmooth => "mixed-smooth",
    }
}

/// The sampling mode called `name` by [`sampling_mode_name`].
pub fn sampling_mode_from_name(name: &str) -> Option<SamplingMode> {
    SamplingMode::ALL.into_iter().find(|&mode| sampling_mode_name(mode) == name)
}

/// The name of an atlas layout in tables.
pub fn view_layout_name(layout: ViewLayout) -> &'static str {
    match layout {
        ViewLayout::Listing1 => "paper",
        ViewLayout::Compact => "compact",
    }
}

/// The layout called `name` by [`view_layout_name`].
pub fn view_layout_from_name(name: &str) -> Option<ViewLayout> {
    [ViewLayout::Listing1, ViewLayout::Compact].into_iter().find(|&layout| view_layout_name(layout) == name)
}

/// `rows` as CSV with [`CSV_HEADER`].
pub fn rows_to_csv(rows: &[SweepRow]) -> String {
    let mut csv = format!("{CSV_HEADER}\n");
    for r in rows {
        let _ = writeln!(
            csv,
            "{},{},{},{},{},{},{:.6},{:.6},{},{}",
            r.grain,
            r.subdivisions,
            r.texels,
            sampling_mode_name(r.mode),
            view_layout_name(r.layout),
            r.apparent_diameter,
            r.error.ssim,
            r.error.rmse,
            r.atlas_bytes,
            r.cloud_ms.map(|ms| format!("{ms:.4}")).unwrap_or_default()
        );
    }
    csv
}

/// Parses CSV written by [`rows_to_csv`] (or with [`UNTIMED_CSV_HEADER`]); the error names
/// the line and the field.
pub fn rows_from_csv(text: &str) -> Result<Vec<SweepRow>, String> {
    let mut lines = text.lines().enumerate();
    let field_count = match lines.next() {
        Some((_, header)) if header.trim() == CSV_HEADER => 10,
        Some((_, header)) if header.trim() == UNTIMED_CSV_HEADER => 9,
        Some((_, header)) => return Err(format!("line 1: expected the header `{CSV_HEADER}`, found `{header}`")),
        None => return Err("empty table".into()),
    };
    let mut rows = Vec::new();
    for (index, line) in lines {
        if line.trim().is_empty() {
            continue;
        }
        let fields: Vec<&str> = line.split(',').collect();
        let at = |what: &str| format!("line {}: bad {what} in `{line}`", index + 1);
        if fields.len() != field_count {
            return Err(at("field count"));
        }
        let number =
            |k: usize, what: &str| fields[k].parse::<f64>().ok().filter(|v| v.is_finite()).ok_or_else(|| at(what));
        let integer = |k: usize, what: &str| fields[k].parse::<u64>().map_err(|_| at(what));
        rows.push(SweepRow {
            grain: fields[0].to_owned(),
            subdivisions: u32::try_from(integer(1, "n")?).map_err(|_| at("n"))?,
            texels: u32::try_from(integer(2, "p")?).map_err(|_| at("p"))?,
            mode: sampling_mode_from_name(fields[3]).ok_or_else(|| at("mode"))?,
            layout: view_layout_from_name(fields[4]).ok_or_else(|| at("layout"))?,
            apparent_diameter: number(5, "diameter")? as f32,
            error: ImageError { ssim: number(6, "ssim")?, rmse: number(7, "rmse")? },
            atlas_bytes: integer(8, "atlas_bytes")?,
            cloud_ms: match fields.get(9) {
                None | Some(&"") => None,
                Some(_) => Some(number(9, "cloud_ms")?),
            },
        });
    }
    Ok(rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_round_trip_through_csv() {
        let rows = vec![SweepRow {
            grain: "bean".into(),
            subdivisions: 8,
            texels: 64,
            mode: SamplingMode::Mixed,
            layout: ViewLayout::Compact,
            apparent_diameter: 32.0,
            error: ImageError { ssim: 0.908_2, rmse: 0.021_2 },
            atlas_bytes: 8_738_000,
            cloud_ms: Some(1.25),
        }];
        assert_eq!(rows_from_csv(&rows_to_csv(&rows)).unwrap(), rows);
        let untimed = vec![SweepRow { cloud_ms: None, ..rows[0].clone() }];
        assert_eq!(rows_from_csv(&rows_to_csv(&untimed)).unwrap(), untimed);
        let old = format!("{UNTIMED_CSV_HEADER}\nbean,8,64,mixed,compact,32,0.9082,0.0212,8738000\n");
        assert_eq!(rows_from_csv(&old).unwrap(), untimed);
    }

    #[test]
    fn bad_tables_name_the_line() {
        assert!(rows_from_csv("").is_err());
        assert!(rows_from_csv("grain,n\n").unwrap_err().contains("line 1"));
        let bad_mode = format!("{CSV_HEADER}\nball,8,64,curved,paper,32,0.9,0.1,1,\n");
        assert!(rows_from_csv(&bad_mode).unwrap_err().contains("line 2: bad mode"));
        let bad_ssim = format!("{CSV_HEADER}\nball,8,64,mixed,paper,32,NaN,0.1,1,\n");
        assert!(rows_from_csv(&bad_ssim).unwrap_err().contains("bad ssim"));
        let bad_time = format!("{CSV_HEADER}\nball,8,64,mixed,paper,32,0.9,0.1,1,fast\n");
        assert!(rows_from_csv(&bad_time).unwrap_err().contains("bad cloud_ms"));
        let short = format!("{CSV_HEADER}\nball,8,64,mixed,paper,32,0.9,0.1,1\n");
        assert!(rows_from_csv(&short).unwrap_err().contains("bad field count"));
    }
}

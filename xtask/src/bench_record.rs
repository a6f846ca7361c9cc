//! `cargo xtask bench [--save NAME] [--compare NAME] [CRITERION ARGS]`: the benchmarks'
//! figures as JSON under `target/bench/`, and the comparison of a run with a saved one.
//!
//! A record ([`Record`]) holds every criterion benchmark that the run measured (its
//! `new/estimates.json` written after the run began: the mean and its 95 % confidence
//! interval, in ns) and every GPU benchmark CSV under `target/bench-gpu/` (each row's
//! time columns — names ending in `_ms` — keyed by the fields before the first of them,
//! which name the configuration: adapter, scene, grains, …).
//!
//! A regression is a benchmark slower than the saved one beyond the spread of this
//! machine ([`compare`]). Two spreads are measured. The comparison's own: the robust
//! deviation (1.4826 × MAD) of the log time ratios about their median (the run's drift)
//! over every benchmark both runs have — most benchmarks are untouched by a change, so
//! their ratios are the machine's run-to-run noise. And each benchmark's own: `--save`
//! runs the benchmarks twice, back to back, and records per benchmark the log ratio of
//! the two runs ([`Figure::run_to_run`]; the record keeps the second run). A benchmark is
//! flagged when it is slower and its log ratio exceeds the drift by more than [`SPREADS`]
//! times the larger of the two spreads, and, for criterion benchmarks, when the
//! confidence intervals of the two means are disjoint too. A change that slows every
//! benchmark alike shows as the drift, which is printed, not flagged.
//!
//! Why both: the first end-to-end run (`--save before smith_micro`, then `--compare
//! before` on the same commit, 1 s per benchmark) flagged
//! `smith_micro/visible_mean_attribute_for_directions` at 1.022 while the six benchmarks'
//! common spread was 0.001 and criterion's intervals were disjoint: criterion's interval
//! is the noise within a run, and a few benchmarks agreeing closely say nothing of a
//! noisier one. A benchmark's own run-to-run ratio does.

use std::path::{Path, PathBuf};
use std::time::SystemTime;

use serde_json::{Value, json};

/// One benchmark's figure.
#[derive(Clone, Debug, PartialEq)]
pub struct Figure {
    /// The benchmark's identifier: criterion's full id, or
    /// `bench-gpu/<subject>/<file>/<configuration>/<column>`.
    pub id: String,
    /// Its time: criterion's mean in ns, a GPU CSV's value in ms.
    pub time: f64,
    /// The 95 % confidence interval of `time` where the source gives one.
    pub interval: Option<(f64, f64)>,
    /// `ns` or `ms`.
    pub unit: &'static str,
    /// |ln(t₂/t₁)| of two back-to-back runs of this benchmark on the machine that saved
    /// it (`--save` measures it; `None` for a single run).
    pub run_to_run: Option<f64>,
}

/// A saved run: its figures and where they came from.
#[derive(Clone, Debug, PartialEq)]
pub struct Record {
    /// The name given to `--save`.
    pub name: String,
    /// The commit measured.
    pub commit: String,
    /// When (UTC).
    pub date: String,
    /// The figures, sorted by id.
    pub figures: Vec<Figure>,
}

impl Record {
    /// The record as JSON.
    pub fn to_json(&self) -> Value {
        let figures: Vec<Value> = self
            .figures
            .iter()
            .map(|f| {
                let mut v = json!({ "id": f.id, "time": f.time, "unit": f.unit });
                if let Some((lower, upper)) = f.interval {
                    v["lower"] = json!(lower);
                    v["upper"] = json!(upper);
                }
                if let Some(spread) = f.run_to_run {
                    v["run_to_run"] = json!(spread);
                }
                v
            })
            .collect();
        json!({ "name": self.name, "commit": self.commit, "date": self.date, "figures": figures })
    }

    /// A record from its JSON, or an error naming the field (`source` names the file).
    pub fn from_json(value: &Value, source: &str) -> Result<Self, String> {
        let text = |key: &str| {
            value
                .get(key)
                .and_then(Value::as_str)
                .map(str::to_owned)
                .ok_or_else(|| format!("{source}: no string `{key}`"))
        };
        let list =
            value.get("figures").and_then(Value::as_array).ok_or_else(|| format!("{source}: no list `figures`"))?;
        let mut figures = Vec::with_capacity(list.len());
        for (i, f) in list.iter().enumerate() {
            let field = |key: &str| f.get(key).ok_or_else(|| format!("{source}: figures[{i}] has no `{key}`"));
            let number =
                |key: &str| field(key)?.as_f64().ok_or_else(|| format!("{source}: figures[{i}].{key} is not a number"));
            let unit = match field("unit")?.as_str() {
                Some("ns") => "ns",
                Some("ms") => "ms",
                other => return Err(format!("{source}: figures[{i}].unit is {other:?}, not \"ns\" or \"ms\"")),
            };
            let interval = match (f.get("lower"), f.get("upper")) {
                (None, None) => None,
                _ => Some((number("lower")?, number("upper")?)),
            };
            let id = field("id")?.as_str().ok_or_else(|| format!("{source}: figures[{i}].id is not a string"))?;
            let run_to_run = match f.get("run_to_run") {
                None => None,
                Some(_) => Some(number("run_to_run")?)
                    .filter(|s| *s >= 0.0)
                    .map(Some)
                    .ok_or_else(|| format!("{source}: figures[{i}].run_to_run is negative"))?,
            };
            figures.push(Figure { id: id.to_owned(), time: number("time")?, interval, unit, run_to_run });
        }
        Ok(Self { name: text("name")?, commit: text("commit")?, date: text("date")?, figures })
    }
}

impl Record {
    /// The figures measured since `started`: criterion's under `target/criterion`, and the
    /// GPU benchmark CSVs under `target/bench-gpu`.
    pub fn measured(target: &Path, name: &str, started: SystemTime) -> Result<Self, String> {
        let mut figures = criterion_figures(&target.join("criterion"), started)?;
        figures.extend(gpu_figures(&target.join("bench-gpu"))?);
        figures.sort_by(|a, b| a.id.cmp(&b.id));
        Ok(Self { name: name.to_owned(), commit: crate::showcase::commit(), date: crate::showcase::utc_now(), figures })
    }

    /// The record of a second run, each figure carrying its run-to-run spread against
    /// `first` (figures `first` lacks keep none).
    pub fn with_run_to_run(mut self, first: &Record) -> Self {
        for figure in &mut self.figures {
            figure.run_to_run = first
                .figures
                .iter()
                .find(|f| f.id == figure.id && f.unit == figure.unit && f.time > 0.0 && figure.time > 0.0)
                .map(|f| (figure.time / f.time).ln().abs());
        }
        self
    }

    /// Writes the record as JSON to `path` (its folder created).
    pub fn write(&self, path: &Path) -> Result<(), String> {
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
        }
        let text = serde_json::to_string_pretty(&self.to_json()).map_err(|e| e.to_string())?;
        std::fs::write(path, text + "\n").map_err(|e| format!("cannot write {}: {e}", path.display()))
    }

    /// Reads a record written by [`Record::write`]; errors name the file.
    pub fn read(path: &Path) -> Result<Self, String> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| format!("cannot read the saved run {} (`--save NAME` writes it): {e}", path.display()))?;
        let value: Value = serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
        Self::from_json(&value, &path.display().to_string())
    }
}

/// Prints the ratio per benchmark of `new` against `saved`, the drift and the spread;
/// an error listing the regressions when there are any.
pub fn print_comparison(saved: &Record, new: &Record) -> Result<(), String> {
    let report = compare(&saved.figures, &new.figures);
    println!("bench: {} against `{}` ({}, {}):", new.commit, saved.name, saved.commit, saved.date);
    println!("{:>8} {:>11}  benchmark", "ratio", "run-to-run");
    for row in &report.rows {
        let own = row.run_to_run.map_or_else(|| "-".to_owned(), |s| format!("{s:.3}"));
        println!("{:>8.3} {own:>11}  {}{}", row.ratio, row.id, if row.regression { "  REGRESSION" } else { "" });
    }
    println!(
        "drift (median ratio) {:.3}, spread (robust, of the log ratios) {:.3}: a regression is slower than \
         drift × exp({SPREADS} × max(spread, its run-to-run)) — at least {:.3} — with disjoint confidence \
         intervals; {} compared, {} in one run only",
        report.drift.exp(),
        report.spread,
        (SPREADS * report.spread).exp(),
        report.rows.len(),
        report.unmatched.len()
    );
    for id in &report.unmatched {
        println!("  only in one run: {id}");
    }
    let regressions: Vec<&str> = report.rows.iter().filter(|r| r.regression).map(|r| r.id.as_str()).collect();
    if regressions.is_empty() {
        Ok(())
    } else {
        Err(format!("{} regression(s) against `{}`: {}", regressions.len(), saved.name, regressions.join(", ")))
    }
}

/// `target/bench/NAME.json`, or an error when `name` is not a plain file name.
pub fn record_path(target: &Path, name: &str) -> Result<PathBuf, String> {
    let plain = !name.is_empty() && name.chars().all(|c| c.is_ascii_alphanumeric() || "-_.".contains(c));
    if !plain || name.starts_with('.') {
        return Err(format!("`{name}` is not a record name (letters, digits, `-`, `_`, `.`)"));
    }
    Ok(target.join("bench").join(format!("{name}.json")))
}

/// The criterion benchmarks under `criterion_dir` measured since `since`.
pub fn criterion_figures(criterion_dir: &Path, since: SystemTime) -> Result<Vec<Figure>, String> {
    let mut figures = Vec::new();
    let mut pending = vec![criterion_dir.to_path_buf()];
    while let Some(dir) = pending.pop() {
        let Ok(entries) = std::fs::read_dir(&dir) else { continue };
        for entry in entries.flatten() {
            let path = entry.path();
            if !path.is_dir() {
                continue;
            }
            let estimates = path.join("new").join("estimates.json");
            let benchmark = path.join("new").join("benchmark.json");
            let fresh = std::fs::metadata(&estimates).and_then(|m| m.modified()).is_ok_and(|t| t >= since);
            if fresh && benchmark.is_file() {
                figures.push(criterion_figure(&estimates, &benchmark)?);
            } else if path.file_name().is_some_and(|n| n != "new" && n != "base" && n != "report") {
                pending.push(path);
            }
        }
    }
    figures.sort_by(|a, b| a.id.cmp(&b.id));
    Ok(figures)
}

/// Reads one criterion benchmark: its id and its mean with the confidence interval.
fn criterion_figure(estimates: &Path, benchmark: &Path) -> Result<Figure, String> {
    let read = |path: &Path| -> Result<Value, String> {
        let text = std::fs::read_to_string(path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
        serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))
    };
    let (estimates_json, benchmark_json) = (read(estimates)?, read(benchmark)?);
    let id = benchmark_json["full_id"]
        .as_str()
        .ok_or_else(|| format!("{}: no string `full_id`", benchmark.display()))?
        .to_owned();
    let mean = &estimates_json["mean"];
    let number = |v: &Value, key: &str| {
        v.as_f64().ok_or_else(|| format!("{}: `mean.{key}` is not a number", estimates.display()))
    };
    let time = number(&mean["point_estimate"], "point_estimate")?;
    let lower = number(&mean["confidence_interval"]["lower_bound"], "confidence_interval.lower_bound")?;
    let upper = number(&mean["confidence_interval"]["upper_bound"], "confidence_interval.upper_bound")?;
    Ok(Figure { id, time, interval: Some((lower, upper)), unit: "ns", run_to_run: None })
}

/// The GPU benchmark figures of the CSV files in `bench_gpu_dir/<subject>/`.
pub fn gpu_figures(bench_gpu_dir: &Path) -> Result<Vec<Figure>, String> {
    let mut figures = Vec::new();
    let Ok(subjects) = std::fs::read_dir(bench_gpu_dir) else { return Ok(figures) };
    for subject in subjects.flatten().filter(|e| e.path().is_dir()) {
        let Ok(files) = std::fs::read_dir(subject.path()) else { continue };
        for file in files.flatten().filter(|e| e.path().extension().is_some_and(|x| x == "csv")) {
            let path = file.path();
            let text = std::fs::read_to_string(&path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
            let stem = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
            let prefix = format!("bench-gpu/{}/{stem}", subject.file_name().to_string_lossy());
            figures.extend(csv_figures(&text, &prefix).map_err(|e| format!("{}: {e}", path.display()))?);
        }
    }
    figures.sort_by(|a, b| a.id.cmp(&b.id));
    Ok(figures)
}

/// The time columns (`*_ms`) of every row of a GPU benchmark CSV, keyed by the fields
/// before the first time column.
fn csv_figures(text: &str, prefix: &str) -> Result<Vec<Figure>, String> {
    let mut lines = text.lines().filter(|l| !l.trim().is_empty());
    let header: Vec<String> = crate::report_page::csv_fields(lines.next().ok_or("an empty file")?);
    let first_time = header.iter().position(|c| c.ends_with("_ms")).ok_or("no time column (`*_ms`)")?;
    let mut figures = Vec::new();
    for (row, line) in lines.enumerate() {
        let fields = crate::report_page::csv_fields(line);
        if fields.len() != header.len() {
            return Err(format!("row {} has {} fields, the header {}", row + 2, fields.len(), header.len()));
        }
        let key = fields[..first_time].join("/");
        for (column, field) in header.iter().zip(&fields).skip(first_time).filter(|(c, _)| c.ends_with("_ms")) {
            if field.is_empty() {
                continue;
            }
            let time: f64 =
                field.parse().map_err(|_| format!("row {}: {column} `{field}` is not a number", row + 2))?;
            figures.push(Figure {
                id: format!("{prefix}/{key}/{column}"),
                time,
                interval: None,
                unit: "ms",
                run_to_run: None,
            });
        }
    }
    Ok(figures)
}

/// One benchmark compared.
#[derive(Clone, Debug, PartialEq)]
pub struct Comparison {
    /// The benchmark's id.
    pub id: String,
    /// New time / saved time.
    pub ratio: f64,
    /// The saved run's own run-to-run spread of this benchmark.
    pub run_to_run: Option<f64>,
    /// Whether it is a regression beyond the measured spread.
    pub regression: bool,
}

/// The comparison of `new` with `saved` over the benchmarks both have.
#[derive(Clone, Debug, PartialEq)]
pub struct Report {
    /// Per benchmark, in id order.
    pub rows: Vec<Comparison>,
    /// The median log ratio: the whole run's drift.
    pub drift: f64,
    /// 1.4826 × the median absolute deviation of the log ratios about `drift`.
    pub spread: f64,
    /// Ids only one run has.
    pub unmatched: Vec<String>,
}

/// How many spreads beyond the drift make a regression.
pub const SPREADS: f64 = 3.0;

/// Compares two runs (see the module's documentation for the rule).
pub fn compare(saved: &[Figure], new: &[Figure]) -> Report {
    let mut pairs = Vec::new();
    let mut unmatched = Vec::new();
    for figure in new {
        match saved.iter().find(|s| s.id == figure.id && s.unit == figure.unit) {
            Some(old) if old.time > 0.0 && figure.time > 0.0 => pairs.push((old, figure)),
            _ => unmatched.push(figure.id.clone()),
        }
    }
    unmatched.extend(saved.iter().filter(|s| !new.iter().any(|n| n.id == s.id)).map(|s| s.id.clone()));
    unmatched.sort();
    let logs: Vec<f64> = pairs.iter().map(|(old, new)| (new.time / old.time).ln()).collect();
    let drift = median(&logs);
    let deviations: Vec<f64> = logs.iter().map(|l| (l - drift).abs()).collect();
    let spread = 1.4826 * median(&deviations);
    let rows = pairs
        .iter()
        .zip(&logs)
        .map(|((old, new), &log)| {
            let own = old.run_to_run.unwrap_or(0.0);
            let beyond_spread = log - drift > SPREADS * spread.max(own) && log > 0.0;
            let disjoint = match (old.interval, new.interval) {
                (Some((_, old_upper)), Some((new_lower, _))) => new_lower > old_upper,
                _ => true,
            };
            Comparison {
                id: new.id.clone(),
                ratio: log.exp(),
                run_to_run: old.run_to_run,
                regression: beyond_spread && disjoint,
            }
        })
        .collect();
    Report { rows, drift, spread, unmatched }
}

/// The median (0 for none).
fn median(values: &[f64]) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    let mid = sorted.len() / 2;
    if sorted.len() % 2 == 1 { sorted[mid] } else { 0.5 * (sorted[mid - 1] + sorted[mid]) }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn figure(id: &str, time: f64, interval: Option<(f64, f64)>) -> Figure {
        Figure { id: id.to_owned(), time, interval, unit: "ns", run_to_run: None }
    }

    #[test]
    fn a_noisy_benchmark_is_judged_by_its_own_run_to_run_spread() {
        // Six quiet benchmarks and one that moved 2 % between the two saved runs: a 2.2 %
        // slowdown of it is its noise, a 10 % one is not.
        let first = Record {
            name: "a".into(),
            commit: "c".into(),
            date: "d".into(),
            figures: (0..7)
                .map(|i| figure(&format!("b{i}"), if i == 6 { 98.0 } else { 100.0 }, Some((99.9, 100.1))))
                .collect(),
        };
        let second = Record {
            figures: (0..7).map(|i| figure(&format!("b{i}"), 100.0, Some((99.9, 100.1)))).collect(),
            ..first.clone()
        };
        let saved = second.clone().with_run_to_run(&first);
        assert!((saved.figures[6].run_to_run.unwrap() - (100.0_f64 / 98.0).ln()).abs() < 1e-12);
        assert_eq!(saved.figures[0].run_to_run, Some(0.0));
        let mut new: Vec<Figure> = (0..6)
            .map(|i| {
                let t = 100.0 * (1.0 + 0.001 * f64::from(i));
                figure(&format!("b{i}"), t, Some((t - 0.1, t + 0.1)))
            })
            .collect();
        new.push(figure("b6", 102.2, Some((102.1, 102.3))));
        assert!(compare(&saved.figures, &new).rows.iter().all(|r| !r.regression));
        new[6] = figure("b6", 110.0, Some((109.9, 110.1)));
        let flagged: Vec<String> =
            compare(&saved.figures, &new).rows.into_iter().filter(|r| r.regression).map(|r| r.id).collect();
        assert_eq!(flagged, ["b6"]);
        // Without the saved spread the same 2.2 % is flagged (the first end-to-end run).
        let unsaved: Vec<Figure> = second.figures.clone();
        new[6] = figure("b6", 102.2, Some((102.1, 102.3)));
        assert!(compare(&unsaved, &new).rows.iter().any(|r| r.regression));
    }

    #[test]
    fn a_slow_benchmark_among_noisy_ones_is_a_regression_and_uniform_noise_is_not() {
        // Twenty benchmarks with ±2 % noise about a 5 % machine drift, one 30 % slower.
        let saved: Vec<Figure> = (0..21).map(|i| figure(&format!("b{i:02}"), 100.0, Some((99.0, 101.0)))).collect();
        let mut new: Vec<Figure> = (0..20)
            .map(|i| {
                let t = 105.0 * (1.0 + 0.02 * (f64::from(i) * 0.9).sin());
                figure(&format!("b{i:02}"), t, Some((t - 1.0, t + 1.0)))
            })
            .collect();
        new.push(figure("b20", 136.5, Some((135.0, 138.0))));
        new.push(figure("fresh", 1.0, None));
        let report = compare(&saved, &new);
        assert!((report.drift.exp() - 1.05).abs() < 0.02, "drift {}", report.drift.exp());
        assert!(report.spread > 0.0 && report.spread < 0.03, "spread {}", report.spread);
        let flagged: Vec<&str> = report.rows.iter().filter(|r| r.regression).map(|r| r.id.as_str()).collect();
        assert_eq!(flagged, ["b20"]);
        assert_eq!(report.rows.len(), 21);
        assert_eq!(report.unmatched, ["fresh"]);
    }

    #[test]
    fn overlapping_confidence_intervals_are_not_a_regression() {
        let saved: Vec<Figure> = (0..5).map(|i| figure(&format!("b{i}"), 100.0, Some((99.9, 100.1)))).collect();
        let mut new = saved.clone();
        new[4] = figure("b4", 150.0, Some((90.0, 210.0)));
        assert!(compare(&saved, &new).rows.iter().all(|r| !r.regression));
    }

    #[test]
    fn gpu_csv_rows_are_keyed_by_their_configuration() {
        let text = "adapter,scene,grains,map_ms,split_ms,culled\n\"llvmpipe (LLVM, 256 bits)\",beans,20000,1.5,2.0,7\n";
        let figures = csv_figures(text, "bench-gpu/culling/culling").unwrap();
        let ids: Vec<&str> = figures.iter().map(|f| f.id.as_str()).collect();
        assert_eq!(
            ids,
            [
                "bench-gpu/culling/culling/llvmpipe (LLVM, 256 bits)/beans/20000/map_ms",
                "bench-gpu/culling/culling/llvmpipe (LLVM, 256 bits)/beans/20000/split_ms"
            ]
        );
        assert_eq!(figures[1].time, 2.0);
        assert!(csv_figures("a,b\n1,2\n", "x").unwrap_err().contains("no time column"));
        assert!(csv_figures("a,t_ms\n1,fast\n", "x").unwrap_err().contains("row 2"));
    }

    #[test]
    fn records_round_trip_through_json_and_bad_fields_are_named() {
        let record = Record {
            name: "base".into(),
            commit: "abc".into(),
            date: "2026-12-02 23:00 UTC".into(),
            figures: vec![
                Figure { run_to_run: Some(0.01), ..figure("a/b", 12.5, Some((12.0, 13.0))) },
                Figure { unit: "ms", ..figure("g", 2.0, None) },
            ],
        };
        assert_eq!(Record::from_json(&record.to_json(), "base.json").unwrap(), record);
        let mut bad = record.to_json();
        bad["figures"][1]["unit"] = json!("s");
        let error = Record::from_json(&bad, "base.json").unwrap_err();
        assert!(error.contains("base.json") && error.contains("figures[1].unit"), "{error}");
    }

    #[test]
    fn record_names_are_plain_file_names() {
        let target = Path::new("target");
        assert_eq!(record_path(target, "main-1.2").unwrap(), Path::new("target/bench/main-1.2.json"));
        for bad in ["", "../x", "a/b", ".hidden"] {
            assert!(record_path(target, bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn criterion_estimates_are_read_when_fresh() {
        let dir = std::env::temp_dir().join(format!("xtask-criterion-{}", std::process::id()));
        let new = dir.join("group").join("bench").join("new");
        std::fs::create_dir_all(&new).unwrap();
        std::fs::write(new.join("benchmark.json"), r#"{"full_id":"group/bench"}"#).unwrap();
        std::fs::write(
            new.join("estimates.json"),
            r#"{"mean":{"point_estimate":10.0,"confidence_interval":{"lower_bound":9.5,"upper_bound":10.5}}}"#,
        )
        .unwrap();
        let before = SystemTime::now() - std::time::Duration::from_secs(60);
        assert_eq!(criterion_figures(&dir, before).unwrap(), [figure("group/bench", 10.0, Some((9.5, 10.5)))]);
        let after = SystemTime::now() + std::time::Duration::from_secs(60);
        assert!(criterion_figures(&dir, after).unwrap().is_empty());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}

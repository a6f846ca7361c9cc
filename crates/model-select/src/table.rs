//! Measured tables: what each representation of each object costs and how far its image
//! is from the truth, stamped with what produced them; CSV in and out.

use std::fmt::Write as _;

use crate::{Metric, SelectError};

/// One representation of one object at one condition, as measured.
#[derive(Clone, Debug, PartialEq)]
pub struct Measurement {
    /// The object (a mesostructure, a grain type, a material).
    pub object: String,
    /// The representation: a method and its parameters, by name.
    pub representation: String,
    /// The condition it was measured at, in the table's unit (e.g. pixels per voxel);
    /// larger is harder: error grows with it.
    pub condition: f64,
    /// Mean ꟻLIP of its image against the truth ([`Metric::Flip`]).
    pub flip: f64,
    /// One minus the mean SSIM of its image against the truth ([`Metric::SsimLoss`]).
    pub ssim_loss: f64,
    /// Its cost, in the table's unit (e.g. ns per ray).
    pub cost: f64,
}

impl Measurement {
    /// Its error under `metric`.
    pub fn error(&self, metric: Metric) -> f64 {
        match metric {
            Metric::Flip => self.flip,
            Metric::SsimLoss => self.ssim_loss,
        }
    }
}

/// What produced a table.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Stamp {
    /// The command that writes it (`cargo xtask select-tables`).
    pub command: String,
    /// The commit of the sources (with `-dirty` when they were edited).
    pub commit: String,
    /// The adapter or processor its costs were measured on.
    pub adapter: String,
    /// The [`fingerprint`](crate::fingerprint) of the sources that produced it.
    pub sources: String,
}

/// A validated table of [`Measurement`]s with its [`Stamp`] and units.
#[derive(Clone, Debug, PartialEq)]
pub struct Table {
    name: String,
    stamp: Stamp,
    condition_unit: String,
    cost_unit: String,
    rows: Vec<Measurement>,
}

/// The CSV columns, in order.
const COLUMNS: &str = "object,representation,condition,flip,ssim_loss,cost";
/// The header keys, in order.
const KEYS: [&str; 7] = ["table", "command", "commit", "adapter", "sources", "condition", "cost"];

/// An error unless `text` is a non-empty single-line name without commas.
fn check_name(table: &str, field: String, text: &str) -> Result<(), SelectError> {
    if text.trim().is_empty() || text.trim() != text || text.contains([',', '\n', '\r']) {
        return Err(SelectError::InvalidTable {
            table: table.to_owned(),
            field,
            reason: format!("`{text}` must be a non-empty line without commas or surrounding spaces"),
        });
    }
    Ok(())
}

impl Table {
    /// A table named `name`; an error naming the field when a name is empty or holds a
    /// comma or line break, a number is negative or not finite (conditions must be
    /// positive), there are no rows, or two rows measure the same object, representation
    /// and condition.
    pub fn new(
        name: &str,
        stamp: Stamp,
        condition_unit: &str,
        cost_unit: &str,
        rows: Vec<Measurement>,
    ) -> Result<Self, SelectError> {
        check_name(name, "name".into(), name)?;
        for (field, text) in [
            ("stamp.command", &stamp.command),
            ("stamp.commit", &stamp.commit),
            ("stamp.adapter", &stamp.adapter),
            ("stamp.sources", &stamp.sources),
        ] {
            check_name(name, field.into(), text)?;
        }
        check_name(name, "condition unit".into(), condition_unit)?;
        check_name(name, "cost unit".into(), cost_unit)?;
        let invalid =
            |field: String, reason: String| SelectError::InvalidTable { table: name.to_owned(), field, reason };
        if rows.is_empty() {
            return Err(invalid("rows".into(), "no measurements".into()));
        }
        for (i, row) in rows.iter().enumerate() {
            check_name(name, format!("rows[{i}].object"), &row.object)?;
            check_name(name, format!("rows[{i}].representation"), &row.representation)?;
            if !(row.condition.is_finite() && row.condition > 0.0) {
                return Err(invalid(format!("rows[{i}].condition"), format!("{} is not positive", row.condition)));
            }
            for (field, value) in [("flip", row.flip), ("ssim_loss", row.ssim_loss), ("cost", row.cost)] {
                if !(value.is_finite() && value >= 0.0) {
                    return Err(invalid(format!("rows[{i}].{field}"), format!("{value} is not a finite number ≥ 0")));
                }
            }
            if let Some(j) = rows[..i].iter().position(|r| {
                r.object == row.object && r.representation == row.representation && r.condition == row.condition
            }) {
                return Err(invalid(
                    format!("rows[{i}]"),
                    format!("measures {} / {} at {} again (rows[{j}])", row.object, row.representation, row.condition),
                ));
            }
        }
        Ok(Self {
            name: name.to_owned(),
            stamp,
            condition_unit: condition_unit.to_owned(),
            cost_unit: cost_unit.to_owned(),
            rows,
        })
    }

    /// Its name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// What produced it.
    pub fn stamp(&self) -> &Stamp {
        &self.stamp
    }

    /// The unit of [`Measurement::condition`].
    pub fn condition_unit(&self) -> &str {
        &self.condition_unit
    }

    /// The unit of [`Measurement::cost`].
    pub fn cost_unit(&self) -> &str {
        &self.cost_unit
    }

    /// The measurements, in the order given.
    pub fn rows(&self) -> &[Measurement] {
        &self.rows
    }

    /// The objects, in order of first appearance.
    pub fn objects(&self) -> Vec<&str> {
        let mut objects: Vec<&str> = Vec::new();
        for row in &self.rows {
            if !objects.contains(&row.object.as_str()) {
                objects.push(&row.object);
            }
        }
        objects
    }

    /// Whether the table was produced from sources with this fingerprint.
    pub fn is_fresh(&self, sources: &str) -> bool {
        self.stamp.sources == sources
    }

    /// The table as CSV: `# key: value` header lines (table, command, commit, adapter,
    /// sources, condition unit, cost unit), the column names, one line per row. Numbers
    /// are written in Rust's shortest round-trip form, so [`Table::from_csv`] gives the
    /// same table back.
    pub fn to_csv(&self) -> String {
        let s = &self.stamp;
        let values = [&self.name, &s.command, &s.commit, &s.adapter, &s.sources, &self.condition_unit, &self.cost_unit];
        let mut text = String::new();
        for (key, value) in KEYS.iter().zip(values) {
            let _ = writeln!(text, "# {key}: {value}");
        }
        let _ = writeln!(text, "{COLUMNS}");
        for r in &self.rows {
            let _ = writeln!(
                text,
                "{},{},{},{},{},{}",
                r.object, r.representation, r.condition, r.flip, r.ssim_loss, r.cost
            );
        }
        text
    }

    /// The table of CSV `text` as [`Table::to_csv`] writes it; `file` names it in errors,
    /// which give the line and what is wrong (a missing or unknown header key, a wrong
    /// column count, a number that does not parse) or the invalid field.
    pub fn from_csv(file: &str, text: &str) -> Result<Self, SelectError> {
        let parse_error = |line: usize, reason: String| SelectError::Parse { file: file.to_owned(), line, reason };
        let mut lines = text.lines().enumerate().map(|(i, l)| (i + 1, l));
        let mut values = Vec::with_capacity(KEYS.len());
        for key in KEYS {
            let (n, line) = lines.next().ok_or_else(|| parse_error(values.len() + 1, format!("missing `# {key}:`")))?;
            let value = line
                .strip_prefix(&format!("# {key}: "))
                .ok_or_else(|| parse_error(n, format!("expected `# {key}: …`, found `{line}`")))?;
            values.push(value.to_owned());
        }
        let (n, header) = lines.next().ok_or_else(|| parse_error(KEYS.len() + 1, "missing the column names".into()))?;
        if header != COLUMNS {
            return Err(parse_error(n, format!("expected the columns `{COLUMNS}`, found `{header}`")));
        }
        let mut rows = Vec::new();
        for (n, line) in lines {
            if line.is_empty() {
                continue;
            }
            let fields: Vec<&str> = line.split(',').collect();
            let [object, representation, numbers @ ..] = fields.as_slice() else { unreachable!("split gives one") };
            if numbers.len() != 4 {
                return Err(parse_error(n, format!("{} fields, expected 6", fields.len())));
            }
            let mut parsed = [0.0; 4];
            for ((value, text), column) in
                parsed.iter_mut().zip(numbers).zip(["condition", "flip", "ssim_loss", "cost"])
            {
                *value = text.parse().map_err(|_| parse_error(n, format!("{column} `{text}` is not a number")))?;
            }
            let [condition, flip, ssim_loss, cost] = parsed;
            rows.push(Measurement {
                object: (*object).to_owned(),
                representation: (*representation).to_owned(),
                condition,
                flip,
                ssim_loss,
                cost,
            });
        }
        let [name, command, commit, adapter, sources, condition_unit, cost_unit] =
            <[String; 7]>::try_from(values).expect("one value per key");
        Self::new(&name, Stamp { command, commit, adapter, sources }, &condition_unit, &cost_unit, rows)
    }

    /// The table in the CSV file at `path` ([`Table::from_csv`]).
    pub fn read(path: &std::path::Path) -> Result<Self, SelectError> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| SelectError::Io { path: path.display().to_string(), reason: e.to_string() })?;
        Self::from_csv(&path.display().to_string(), &text)
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    pub(crate) fn stamp() -> Stamp {
        Stamp {
            command: "cargo xtask demo".into(),
            commit: "abc".into(),
            adapter: "CPU".into(),
            sources: "00ff".into(),
        }
    }

    pub(crate) fn row(object: &str, representation: &str, condition: f64, flip: f64, cost: f64) -> Measurement {
        Measurement {
            object: object.into(),
            representation: representation.into(),
            condition,
            flip,
            ssim_loss: flip * 0.5,
            cost,
        }
    }

    #[test]
    fn csv_round_trips_exactly() {
        let rows =
            vec![row("ball", "DDM 4x1 + adaptive", 1.5, 0.0123456789, 812.25), row("maze", "DM", 0.75, 0.3, 1e-9)];
        let table = Table::new("ddm", stamp(), "pixels per voxel", "ns per ray", rows).unwrap();
        let text = table.to_csv();
        assert!(text.starts_with("# table: ddm\n# command: cargo xtask demo\n"), "{text}");
        assert_eq!(Table::from_csv("t.csv", &text).unwrap(), table);
        assert_eq!(table.objects(), ["ball", "maze"]);
        assert!(table.is_fresh("00ff") && !table.is_fresh("00fe"));
    }

    #[test]
    fn bad_tables_name_the_field_or_line() {
        let new = |rows| Table::new("t", stamp(), "px", "ns", rows).unwrap_err().to_string();
        assert!(new(vec![]).contains("rows: no measurements"));
        assert!(new(vec![row("a,b", "m", 1.0, 0.1, 1.0)]).contains("rows[0].object"));
        assert!(new(vec![row("a", "m", 0.0, 0.1, 1.0)]).contains("rows[0].condition"));
        assert!(new(vec![row("a", "m", 1.0, f64::NAN, 1.0)]).contains("rows[0].flip"));
        assert!(new(vec![row("a", "m", 1.0, 0.1, -1.0)]).contains("rows[0].cost"));
        let twice = new(vec![row("a", "m", 1.0, 0.1, 1.0), row("a", "m", 1.0, 0.2, 2.0)]);
        assert!(twice.contains("rows[1]: measures a / m at 1 again (rows[0])"), "{twice}");

        let good = Table::new("t", stamp(), "px", "ns", vec![row("a", "m", 1.0, 0.1, 1.0)]).unwrap().to_csv();
        let parse = |text: &str| Table::from_csv("t.csv", text).unwrap_err().to_string();
        assert!(parse("").contains("t.csv:1: missing `# table:`"));
        assert!(parse(&good.replace("# adapter:", "# gpu:")).contains("t.csv:4: expected `# adapter: …`"));
        assert!(parse(&good.replace("ssim_loss", "ssim")).contains("t.csv:8: expected the columns"));
        assert!(parse(&(good.clone() + "a,m,2\n")).contains("t.csv:10: 3 fields, expected 6"));
        assert!(parse(&(good + "a,m,2,x,0,1\n")).contains("t.csv:10: flip `x` is not a number"));
    }
}

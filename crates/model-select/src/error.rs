//! Why a table cannot be read or a selection cannot be made.

use std::fmt;

/// Every failure of the crate; each names the field, file, line or object concerned.
#[derive(Clone, Debug, PartialEq)]
pub enum SelectError {
    /// A budget that is not a positive number, or an unknown metric.
    InvalidBudget {
        /// What is wrong.
        reason: String,
    },
    /// A table's field, or a field of one of its rows, is out of range.
    InvalidTable {
        /// The table's name.
        table: String,
        /// The field (`rows[3].cost`, `stamp.commit`, …).
        field: String,
        /// What is wrong with it.
        reason: String,
    },
    /// Samples that give no prediction bound ([`prediction_bound`](crate::prediction_bound)):
    /// too few, not finite, or a confidence out of range.
    InvalidSamples {
        /// What is wrong.
        reason: String,
    },
    /// A table's CSV text does not parse.
    Parse {
        /// The file (or the name given for the text).
        file: String,
        /// The 1-based line.
        line: usize,
        /// What is wrong with it.
        reason: String,
    },
    /// A file could not be read.
    Io {
        /// The file.
        path: String,
        /// The system's message.
        reason: String,
    },
    /// The table has no row for the object.
    UnknownObject {
        /// The table's name.
        table: String,
        /// The object asked for.
        object: String,
        /// The objects it has.
        known: Vec<String>,
    },
    /// The condition asked is not a positive number, or beyond every measured one.
    ConditionNotMeasured {
        /// The object.
        object: String,
        /// The condition asked for.
        condition: f64,
        /// The largest condition measured for the object.
        largest: f64,
    },
    /// No representation of the object meets the budget.
    OverBudget {
        /// The object.
        object: String,
        /// The budget, as text (`ꟻLIP ≤ 0.05`).
        budget: String,
        /// The measured condition the selection looked at.
        condition: f64,
        /// The least error measured there.
        least: f64,
        /// The representation that has it.
        best: String,
    },
}

impl fmt::Display for SelectError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::InvalidBudget { reason } => write!(f, "invalid budget: {reason}"),
            Self::InvalidTable { table, field, reason } => write!(f, "table {table}: {field}: {reason}"),
            Self::InvalidSamples { reason } => write!(f, "no prediction bound: {reason}"),
            Self::Parse { file, line, reason } => write!(f, "{file}:{line}: {reason}"),
            Self::Io { path, reason } => write!(f, "cannot read {path}: {reason}"),
            Self::UnknownObject { table, object, known } => {
                write!(f, "table {table} has no object `{object}` (it has: {})", known.join(", "))
            }
            Self::ConditionNotMeasured { object, condition, largest } => write!(
                f,
                "{object}: condition {condition} is not measured (the table goes up to {largest}; measure larger ones)"
            ),
            Self::OverBudget { object, budget, condition, least, best } => write!(
                f,
                "{object}: nothing meets {budget} at condition {condition}: the least {} measured is {least} ({best})",
                budget.split(" ≤").next().unwrap_or(budget)
            ),
        }
    }
}

impl std::error::Error for SelectError {}

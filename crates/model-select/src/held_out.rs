//! A choice checked where the table was not measured: another camera, another
//! realization of the object.

use crate::{Budget, Measurement, SelectError, Table};

/// What [`Table::check_held_out`] found: the table's choice and how it fared on held-out
/// measurements of the same object.
#[derive(Clone, Debug, PartialEq)]
pub struct HeldOutCheck {
    /// The budget.
    pub budget: Budget,
    /// The object.
    pub object: String,
    /// The chosen representation's row in the table.
    pub chosen: Measurement,
    /// The chosen representation's held-out measurement.
    pub measured: Measurement,
    /// Whether its held-out error is within budget.
    pub within_budget: bool,
    /// Representations that met the budget on the held-out measurements although the
    /// table gives them a lower cost than the choice (at the condition the choice was made
    /// at): empty when the choice was also the cheapest there. A non-empty list measures
    /// how conservative the table is, not a wrong choice.
    pub cheaper_within_budget: Vec<String>,
    /// How many representations the table held at that condition, and how many met the
    /// budget there.
    pub candidates: (usize, usize),
}

impl Table {
    /// The table's choice for the object of `held_out` (measurements of one object, all at
    /// one condition, e.g. every representation traced from a camera the table never
    /// saw) within `budget`, checked against the held-out measurement of the chosen
    /// representation.
    ///
    /// Errors: `held_out` empty or mixing objects or conditions
    /// ([`SelectError::InvalidTable`] naming the field), the errors of [`Table::select`],
    /// or a chosen representation missing from `held_out` ([`SelectError::UnknownObject`]
    /// is not it: [`SelectError::InvalidTable`] with field `held_out`).
    pub fn check_held_out(&self, held_out: &[Measurement], budget: Budget) -> Result<HeldOutCheck, SelectError> {
        let invalid = |reason: String| SelectError::InvalidTable {
            table: self.name().to_owned(),
            field: "held_out".to_owned(),
            reason,
        };
        let first = held_out.first().ok_or_else(|| invalid("no held-out measurements".to_owned()))?;
        let (object, condition) = (first.object.as_str(), first.condition);
        if let Some(other) = held_out.iter().find(|m| m.object != object || m.condition != condition) {
            return Err(invalid(format!(
                "one object at one condition expected: {object} at {condition}, then {} at {}",
                other.object, other.condition
            )));
        }
        let choice = self.select(object, condition, budget)?;
        let representation = &choice.measurement.representation;
        let measured = held_out
            .iter()
            .find(|m| &m.representation == representation)
            .ok_or_else(|| invalid(format!("{object}: the choice {representation} was not measured")))?
            .clone();
        let table_cost = |name: &str| {
            self.rows()
                .iter()
                .find(|r| r.object == object && r.condition == choice.condition && r.representation == name)
                .map(|r| r.cost)
        };
        let metric = budget.metric();
        let cheaper_within_budget = held_out
            .iter()
            .filter(|m| m.error(metric) <= budget.max())
            .filter(|m| table_cost(&m.representation).is_some_and(|c| c < choice.measurement.cost))
            .map(|m| m.representation.clone())
            .collect();
        Ok(HeldOutCheck {
            budget,
            object: object.to_owned(),
            chosen: choice.measurement.clone(),
            within_budget: measured.error(metric) <= budget.max(),
            measured,
            cheaper_within_budget,
            candidates: (choice.candidates, choice.within_budget),
        })
    }
}

#[cfg(test)]
mod tests {
    use crate::table::tests::{row, stamp};
    use crate::{Budget, Metric, SelectError, Table};

    #[test]
    fn a_choice_is_checked_on_the_held_out_rows_and_cheaper_passes_are_listed() {
        let rows = vec![
            row("ball", "coarse", 2.0, 0.20, 1.0),
            row("ball", "medium", 2.0, 0.05, 3.0),
            row("ball", "exact", 2.0, 0.01, 9.0),
        ];
        let table = Table::new("t", stamp(), "px", "ns", rows).unwrap();
        let budget = Budget::new(Metric::Flip, 0.06).unwrap();
        // Held out at 1.5: the table answers from its rows at 2.
        let held = vec![
            row("ball", "coarse", 1.5, 0.04, 1.0),
            row("ball", "medium", 1.5, 0.07, 3.0),
            row("ball", "exact", 1.5, 0.02, 9.0),
        ];
        let check = table.check_held_out(&held, budget).unwrap();
        assert_eq!(check.chosen.representation, "medium");
        assert_eq!(check.chosen.condition, 2.0);
        assert_eq!(check.measured.flip, 0.07);
        assert!(!check.within_budget, "0.07 is over 0.06");
        assert_eq!(check.cheaper_within_budget, ["coarse"]);
        assert_eq!(check.candidates, (3, 2));

        let mixed = vec![row("ball", "coarse", 1.5, 0.04, 1.0), row("ball", "medium", 1.0, 0.07, 3.0)];
        let error = table.check_held_out(&mixed, budget).unwrap_err().to_string();
        assert!(error.contains("held_out: one object at one condition expected"), "{error}");
        assert!(table.check_held_out(&[], budget).unwrap_err().to_string().contains("no held-out"));
        let missing = vec![row("ball", "coarse", 1.5, 0.04, 1.0)];
        let error = table.check_held_out(&missing, budget).unwrap_err().to_string();
        assert!(error.contains("the choice medium was not measured"), "{error}");
        let unknown = vec![row("nut", "coarse", 1.5, 0.04, 1.0)];
        assert!(matches!(table.check_held_out(&unknown, budget), Err(SelectError::UnknownObject { .. })));
    }
}

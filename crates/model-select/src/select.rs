//! The cheapest representation of an object within a budget.

use crate::{Budget, Measurement, SelectError, Table, pareto_front};

/// What [`Table::select`] picked, and where it stands among the candidates.
#[derive(Clone, Debug, PartialEq)]
pub struct Choice<'a> {
    /// The chosen measurement.
    pub measurement: &'a Measurement,
    /// Its error under the budget's metric.
    pub error: f64,
    /// The measured condition the choice was made at (the least at or above the one
    /// asked).
    pub condition: f64,
    /// The candidates measured at that condition.
    pub candidates: usize,
    /// How many of them met the budget.
    pub within_budget: usize,
    /// Whether it lies on the candidates' [`pareto_front`] (a cheapest candidate within
    /// budget always does; the field lets a report show it).
    pub on_front: bool,
}

impl Table {
    /// The cheapest representation of `object` whose error under `budget`'s metric is
    /// within it, among the rows measured at the least condition at or above `condition`
    /// (equal costs: the smaller error, then the earlier row).
    ///
    /// Errors: an object the table lacks ([`SelectError::UnknownObject`], listing the
    /// ones it has), a condition that is not positive or beyond every measured one
    /// ([`SelectError::ConditionNotMeasured`]), or nothing within budget
    /// ([`SelectError::OverBudget`], with the least error measured and its representation).
    pub fn select(&self, object: &str, condition: f64, budget: Budget) -> Result<Choice<'_>, SelectError> {
        let of_object: Vec<&Measurement> = self.rows().iter().filter(|r| r.object == object).collect();
        if of_object.is_empty() {
            return Err(SelectError::UnknownObject {
                table: self.name().to_owned(),
                object: object.to_owned(),
                known: self.objects().into_iter().map(str::to_owned).collect(),
            });
        }
        let largest = of_object.iter().map(|r| r.condition).fold(f64::NEG_INFINITY, f64::max);
        let not_measured = || SelectError::ConditionNotMeasured { object: object.to_owned(), condition, largest };
        if !(condition.is_finite() && condition > 0.0) {
            return Err(not_measured());
        }
        let measured = of_object.iter().map(|r| r.condition).filter(|&c| c >= condition).fold(f64::INFINITY, f64::min);
        if !measured.is_finite() {
            return Err(not_measured());
        }
        let candidates: Vec<&Measurement> = of_object.into_iter().filter(|r| r.condition == measured).collect();
        let metric = budget.metric();
        let within: Vec<usize> =
            (0..candidates.len()).filter(|&i| candidates[i].error(metric) <= budget.max()).collect();
        let Some(&chosen) = within.iter().min_by(|&&a, &&b| {
            let (a, b) = (candidates[a], candidates[b]);
            a.cost.total_cmp(&b.cost).then(a.error(metric).total_cmp(&b.error(metric)))
        }) else {
            let best = candidates
                .iter()
                .min_by(|a, b| a.error(metric).total_cmp(&b.error(metric)))
                .expect("an object has rows at its measured conditions");
            return Err(SelectError::OverBudget {
                object: object.to_owned(),
                budget: budget.to_string(),
                condition: measured,
                least: best.error(metric),
                best: best.representation.clone(),
            });
        };
        let points: Vec<(f64, f64)> = candidates.iter().map(|r| (r.cost, r.error(metric))).collect();
        let measurement = candidates[chosen];
        Ok(Choice {
            measurement,
            error: measurement.error(metric),
            condition: measured,
            candidates: candidates.len(),
            within_budget: within.len(),
            on_front: pareto_front(&points).contains(&chosen),
        })
    }
}

#[cfg(test)]
mod tests {
    use crate::table::tests::{row, stamp};
    use crate::{Budget, Metric, SelectError, Table};

    fn table() -> Table {
        let rows = vec![
            row("ball", "coarse", 1.0, 0.20, 1.0),
            row("ball", "medium", 1.0, 0.05, 3.0),
            row("ball", "slow-and-bad", 1.0, 0.30, 5.0),
            row("ball", "exact", 1.0, 0.01, 9.0),
            row("ball", "coarse", 2.0, 0.40, 1.0),
            row("ball", "medium", 2.0, 0.12, 3.0),
            row("ball", "exact", 2.0, 0.02, 9.0),
            row("maze", "only", 1.0, 0.0, 2.0),
        ];
        Table::new("t", stamp(), "px per voxel", "ns", rows).unwrap()
    }

    fn flip(max: f64) -> Budget {
        Budget::new(Metric::Flip, max).unwrap()
    }

    #[test]
    fn the_choice_is_the_cheapest_within_budget_at_the_next_measured_condition() {
        let table = table();
        for (condition, max, expected, at) in [
            (0.3, 0.5, "coarse", 1.0),
            (1.0, 0.1, "medium", 1.0),
            (1.2, 0.1, "exact", 2.0), // between conditions: the harder one decides
            (2.0, 0.12, "medium", 2.0),
            (0.5, 0.01, "exact", 1.0),
        ] {
            let choice = table.select("ball", condition, flip(max)).unwrap();
            assert_eq!((choice.measurement.representation.as_str(), choice.condition), (expected, at), "{condition}");
            assert!(choice.error <= max && choice.on_front);
            // No candidate at that condition is cheaper within budget: brute force.
            let cheaper = table
                .rows()
                .iter()
                .any(|r| r.object == "ball" && r.condition == at && r.flip <= max && r.cost < choice.measurement.cost);
            assert!(!cheaper);
        }
        let choice = table.select("ball", 1.0, Budget::new(Metric::SsimLoss, 0.1).unwrap()).unwrap();
        assert_eq!(
            (choice.measurement.representation.as_str(), choice.within_budget, choice.candidates),
            ("coarse", 3, 4)
        );
    }

    #[test]
    fn failures_say_what_is_missing() {
        let table = table();
        let Err(SelectError::UnknownObject { known, .. }) = table.select("nut", 1.0, flip(0.1)) else { panic!() };
        assert_eq!(known, ["ball", "maze"]);
        let error = table.select("ball", 2.5, flip(0.1)).unwrap_err().to_string();
        assert!(error.contains("condition 2.5 is not measured (the table goes up to 2"), "{error}");
        assert!(matches!(table.select("ball", f64::NAN, flip(0.1)), Err(SelectError::ConditionNotMeasured { .. })));
        assert!(matches!(table.select("ball", 0.0, flip(0.1)), Err(SelectError::ConditionNotMeasured { .. })));
        let error = table.select("ball", 2.0, flip(0.01)).unwrap_err().to_string();
        assert!(
            error.contains("nothing meets ꟻLIP ≤ 0.01 at condition 2: the least ꟻLIP measured is 0.02 (exact)"),
            "{error}"
        );
    }
}

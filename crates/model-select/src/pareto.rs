//! The Pareto front of candidates measured by cost and error.

/// The indices of the points `(cost, error)` that no other point beats in both (cheaper
/// or as cheap *and* more or as accurate, one of them strictly), in increasing cost (so in
/// decreasing error). Of identical points the first is kept; points with a NaN are never
/// on the front.
///
/// ```
/// let points = [(1.0, 0.5), (2.0, 0.6), (0.5, 0.9), (4.0, 0.1), (2.0, 0.3)];
/// assert_eq!(model_select::pareto_front(&points), vec![2, 0, 4, 3]);
/// ```
pub fn pareto_front(points: &[(f64, f64)]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..points.len()).filter(|&i| !points[i].0.is_nan() && !points[i].1.is_nan()).collect();
    order.sort_by(|&a, &b| {
        points[a].0.total_cmp(&points[b].0).then(points[a].1.total_cmp(&points[b].1)).then(a.cmp(&b))
    });
    let mut front = Vec::new();
    let mut best = f64::INFINITY;
    for i in order {
        if points[i].1 < best {
            best = points[i].1;
            front.push(i);
        }
    }
    front
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_front_holds_exactly_the_points_nothing_beats() {
        // A deterministic cloud: every point is either on the front or dominated.
        let points: Vec<(f64, f64)> =
            (0..200).map(|i: i32| (f64::from((i * 37) % 101) / 10.0, f64::from((i * 53) % 89) / 89.0)).collect();
        let front = pareto_front(&points);
        let dominates = |a: (f64, f64), b: (f64, f64)| a.0 <= b.0 && a.1 <= b.1 && (a.0 < b.0 || a.1 < b.1);
        for (i, &p) in points.iter().enumerate() {
            let beaten = points.iter().any(|&q| dominates(q, p));
            if front.contains(&i) {
                assert!(!beaten, "front point {i} {p:?} is beaten");
            } else {
                // Off the front: beaten, or a later duplicate of a front point.
                assert!(beaten || front.iter().any(|&f| f < i && points[f] == p), "point {i} {p:?} left out");
            }
        }
        assert!(front.windows(2).all(|w| points[w[0]].0 < points[w[1]].0 && points[w[0]].1 > points[w[1]].1));
    }

    #[test]
    fn duplicates_keep_the_first_and_nans_are_left_out() {
        assert_eq!(pareto_front(&[(1.0, 1.0), (1.0, 1.0), (f64::NAN, 0.0), (2.0, f64::NAN)]), vec![0]);
        assert!(pareto_front(&[]).is_empty());
    }
}

//! CPU timing of the tracers on a shared machine: the fastest of a few passes for a
//! method's own speed (the minimum is the least disturbed measurement), and for a ratio of
//! two methods (Table 3's "time within 5 %") the median over rounds of two passes in
//! alternating order, so that a drift of the machine's speed between two timings cancels
//! (±15 % on a shared 2-core VM, more than the difference measured), where two separate
//! minima did not.

use std::time::Instant;

use ddm_tracer::TraceOutcome;
use glam::Vec3;

/// A ray: origin and direction.
pub type Ray = (Vec3, Vec3);

/// One method's outcome on every ray, and its CPU time.
#[derive(Clone, Debug, PartialEq)]
pub struct CpuRun {
    /// The outcome of each ray, in order.
    pub outcomes: Vec<TraceOutcome>,
    /// Seconds per ray: the fastest of the timed passes over all rays, divided by their
    /// count (NaN for no rays).
    pub seconds_per_ray: f64,
}

/// Seconds of one pass of `f` over `rays` (results are kept from being optimised away).
pub fn pass_seconds(rays: &[Ray], f: &dyn Fn(Vec3, Vec3) -> TraceOutcome) -> f64 {
    let start = Instant::now();
    for &(o, d) in rays {
        std::hint::black_box(f(o, d));
    }
    start.elapsed().as_secs_f64()
}

/// Traces every ray with `f` once for the outcomes, then times `passes` more passes
/// (at least one) and keeps the fastest.
pub fn timed(rays: &[Ray], passes: usize, f: impl Fn(Vec3, Vec3) -> TraceOutcome) -> CpuRun {
    let outcomes: Vec<TraceOutcome> = rays.iter().map(|&(o, d)| f(o, d)).collect();
    let best = (0..passes.max(1)).map(|_| pass_seconds(rays, &f)).fold(f64::INFINITY, f64::min);
    CpuRun { outcomes, seconds_per_ray: best / rays.len() as f64 }
}

/// The median of `values` (the mean of the two middle values for an even count; NaNs
/// sort last), or `None` for no values.
pub fn median(values: &mut [f64]) -> Option<f64> {
    if values.is_empty() {
        return None;
    }
    values.sort_by(f64::total_cmp);
    let middle = values.len() / 2;
    Some(if values.len() % 2 == 1 { values[middle] } else { 0.5 * (values[middle - 1] + values[middle]) })
}

/// The median over `rounds` rounds of `time_b() / time_a()`, the two timings of a round
/// taken in alternating order (`a` first in even rounds, `b` first in odd ones); `None`
/// for zero rounds.
pub fn interleaved_ratio(
    rounds: usize,
    mut time_a: impl FnMut() -> f64,
    mut time_b: impl FnMut() -> f64,
) -> Option<f64> {
    let mut ratios: Vec<f64> = (0..rounds)
        .map(|round| {
            if round % 2 == 0 {
                let a = time_a();
                time_b() / a
            } else {
                let b = time_b();
                b / time_a()
            }
        })
        .collect();
    median(&mut ratios)
}

/// Rounds of [`interleaved_time_ratio`] in the tables.
pub const RATIO_ROUNDS: usize = 15;

/// The time of a pass of `rays` with `packed` over one with `raw`:
/// [`interleaved_ratio`] over `rounds` rounds of [`pass_seconds`] (NaN for zero rounds).
pub fn interleaved_time_ratio(
    rays: &[Ray],
    rounds: usize,
    raw: impl Fn(Vec3, Vec3) -> TraceOutcome,
    packed: impl Fn(Vec3, Vec3) -> TraceOutcome,
) -> f64 {
    interleaved_ratio(rounds, || pass_seconds(rays, &raw), || pass_seconds(rays, &packed)).unwrap_or(f64::NAN)
}

#[cfg(test)]
mod tests {
    use std::cell::RefCell;

    use super::*;

    #[test]
    fn median_of_known_values() {
        assert_eq!(median(&mut [5.0, 1.0, 3.0]), Some(3.0));
        assert_eq!(median(&mut [4.0, 1.0, 3.0, 2.0]), Some(2.5));
        assert_eq!(median(&mut [7.0]), Some(7.0));
        assert_eq!(median(&mut []), None);
        // A NaN sorts last: the median of the rest's lower half still comes out.
        assert_eq!(median(&mut [f64::NAN, 2.0, 1.0]), Some(2.0));
    }

    #[test]
    fn interleaved_rounds_alternate_their_order() {
        let log = RefCell::new(String::new());
        let ratio = interleaved_ratio(
            4,
            || {
                log.borrow_mut().push('a');
                1.0
            },
            || {
                log.borrow_mut().push('b');
                2.0
            },
        );
        assert_eq!(log.into_inner(), "abbaabba");
        assert_eq!(ratio, Some(2.0));
        assert_eq!(interleaved_ratio(0, || 1.0, || 1.0), None);
    }

    #[test]
    fn the_ratio_is_the_median_of_the_rounds() {
        // `b` takes 3, 1, 2, 9, 0.5 times as long as `a` in successive rounds.
        let factors = [3.0, 1.0, 2.0, 9.0, 0.5];
        let round = RefCell::new(0_usize);
        let ratio = interleaved_ratio(
            factors.len(),
            || 1.0,
            || {
                let mut r = round.borrow_mut();
                *r += 1;
                factors[*r - 1]
            },
        );
        assert_eq!(ratio, Some(2.0));
    }

    /// A machine that slows down steadily: each timing takes longer than the one before.
    /// Interleaving cancels most of the drift that two back-to-back blocks of passes keep.
    #[test]
    fn interleaving_cancels_a_linear_drift() {
        let drift = 0.01; // 1 % slower per timing
        let clock = RefCell::new(0.0_f64);
        let timing = |work: f64| {
            let mut calls = clock.borrow_mut();
            *calls += 1.0;
            work * (1.0 + drift * *calls)
        };
        let ratio = interleaved_ratio(RATIO_ROUNDS, || timing(1.0), || timing(2.0)).unwrap();
        // One pair's drift is a factor 1 + drift at most around the true ratio 2.
        assert!((ratio / 2.0 - 1.0).abs() < drift, "ratio {ratio}");
        // All `a` passes, then all `b` passes: the drift of RATIO_ROUNDS timings stays.
        *clock.borrow_mut() = 0.0;
        let a: f64 = (0..RATIO_ROUNDS).map(|_| timing(1.0)).sum();
        let b: f64 = (0..RATIO_ROUNDS).map(|_| timing(2.0)).sum();
        assert!((b / a / 2.0 - 1.0).abs() > 5.0 * (ratio / 2.0 - 1.0).abs());
    }

    #[test]
    fn timed_keeps_every_outcome_in_order() {
        let rays: Vec<Ray> = (0..5).map(|i| (Vec3::splat(i as f32), Vec3::NEG_Z)).collect();
        let run = timed(&rays, 2, |o, _| TraceOutcome { hit: None, steps: o.x as u32, exhausted: false, cone: 0 });
        let steps: Vec<u32> = run.outcomes.iter().map(|o| o.steps).collect();
        assert_eq!(steps, [0, 1, 2, 3, 4]);
        assert!(run.seconds_per_ray.is_finite() && run.seconds_per_ray >= 0.0);
    }
}

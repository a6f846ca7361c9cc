//! Every pixel of an image on every core, with a result independent of the threads.

use std::sync::atomic::{AtomicU32, Ordering};
use std::thread;

/// The threads [`per_pixel`] uses: the machine's available parallelism (1 if unknown).
pub fn threads() -> usize {
    thread::available_parallelism().map_or(1, |n| n.get())
}

/// `f(x, y)` for every pixel of a `width × height` image, row-major (`y` down), on
/// [`threads`] scoped threads that take rows from a shared counter.
///
/// Each pixel is a pure function of its coordinates, and rows are put back in order, so the
/// result is the same bits whatever the number of threads or their schedule. A panic in `f`
/// is propagated to the caller.
pub fn per_pixel<T: Send>(width: u32, height: u32, f: impl Fn(u32, u32) -> T + Sync) -> Vec<T> {
    let workers = threads().min(height as usize).max(1);
    let next = AtomicU32::new(0);
    let work = || {
        let mut rows = Vec::new();
        loop {
            let y = next.fetch_add(1, Ordering::Relaxed);
            if y >= height {
                break rows;
            }
            rows.push((y, (0..width).map(|x| f(x, y)).collect::<Vec<T>>()));
        }
    };
    let batches: Vec<Vec<(u32, Vec<T>)>> = thread::scope(|scope| {
        let handles: Vec<_> = (0..workers).map(|_| scope.spawn(work)).collect();
        handles.into_iter().map(|h| h.join().unwrap_or_else(|panic| std::panic::resume_unwind(panic))).collect()
    });
    let mut rows: Vec<(u32, Vec<T>)> = batches.into_iter().flatten().collect();
    rows.sort_unstable_by_key(|(y, _)| *y);
    rows.into_iter().flat_map(|(_, row)| row).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pixels_come_back_in_row_major_order() {
        let out = per_pixel(7, 5, |x, y| (x, y));
        assert_eq!(out.len(), 35);
        for (i, &(x, y)) in out.iter().enumerate() {
            assert_eq!((x + 7 * y) as usize, i);
        }
        assert!(per_pixel(0, 3, |x, y| x + y).is_empty());
        assert!(per_pixel(3, 0, |x, y| x + y).is_empty());
    }
}

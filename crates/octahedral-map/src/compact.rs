//! A view layout without the duplicated equator views.
//!
//! Listing 1's layout stores `N = 2n²` views: an `n × n` grid per hemisphere. The grid's
//! boundary (`u` or `v` equal to `0` or `n - 1`) lies on the equator `z = 0`, so the
//! `4(n - 1)` boundary views of the upper hemisphere are the same directions as those of
//! the lower one (for `n ≥ 2`; `n = 1` holds the two poles and no duplicate). `GrainViewer`'s
//! `ViewIndexToDirection` notes the redundancy ("find a mapping without redundancy").
//!
//! The **compact** layout stores each distinct direction once, `2n² − 4(n − 1)` views:
//!
//! - compact indices `0 .. n²` are the lower hemisphere's views, in Listing 1's order
//!   (`u n + v`), equator included;
//! - compact indices `n² .. n² + (n − 2)²` are the upper hemisphere's interior views
//!   (`1 ≤ u, v ≤ n − 2`), row-major: `n² + (u − 1)(n − 2) + (v − 1)`.
//!
//! An upper boundary view maps to its lower twin, which has the same `(u, v)`.
//! For `n = 1` the compact layout equals Listing 1's (two poles).

use crate::views::OctahedralViews;

/// The compact layout of an [`OctahedralViews`]: each distinct view direction stored once.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct CompactViews {
    views: OctahedralViews,
}

impl CompactViews {
    /// The compact layout of `views`.
    pub const fn new(views: OctahedralViews) -> Self {
        Self { views }
    }

    /// The Listing 1 layout this one compacts.
    pub const fn views(self) -> OctahedralViews {
        self.views
    }

    /// The number of distinct views: `2n² − 4(n − 1)` for `n ≥ 2`, 2 for `n = 1`.
    pub const fn view_count(self) -> u32 {
        compact_view_count(self.views.subdivisions())
    }

    /// The compact index of Listing 1 index `index`, or `None` when `index ≥ 2n²`.
    /// Both copies of an equator view map to the same compact index.
    pub fn compact_index(self, index: u32) -> Option<u32> {
        (index < self.views.view_count()).then(|| compact_from_listing_index(index, self.views.subdivisions()))
    }

    /// The Listing 1 index stored at compact index `compact` (the lower copy of an equator
    /// view), or `None` when `compact` is not below [`view_count`](Self::view_count).
    pub fn listing_index(self, compact: u32) -> Option<u32> {
        (compact < self.view_count()).then(|| listing_from_compact_index(compact, self.views.subdivisions()))
    }
}

/// `2n² − 4(n − 1)` (2 for `n = 1`), `n` clamped to `1..=MAX_SUBDIVISIONS`.
pub const fn compact_view_count(subdivisions: u32) -> u32 {
    let n = clamp_subdivisions(subdivisions);
    if n == 1 { 2 } else { n * n + (n - 2) * (n - 2) }
}

const fn clamp_subdivisions(subdivisions: u32) -> u32 {
    if subdivisions == 0 {
        1
    } else if subdivisions > crate::MAX_SUBDIVISIONS {
        crate::MAX_SUBDIVISIONS
    } else {
        subdivisions
    }
}

/// The compact index of Listing 1 index `index` for `n = subdivisions` (clamped to
/// `1..=MAX_SUBDIVISIONS`); mirrored by the WGSL `octahedral_compact_index`. Indices
/// `≥ 2n²` are taken modulo `2n²` (callers validate; see [`CompactViews::compact_index`]).
pub const fn compact_from_listing_index(index: u32, subdivisions: u32) -> u32 {
    let n = clamp_subdivisions(subdivisions);
    let per_hemisphere = n * n;
    let index = index % (2 * per_hemisphere);
    if n == 1 || index < per_hemisphere {
        return index;
    }
    let local = index - per_hemisphere;
    let (u, v) = (local / n, local % n);
    if u == 0 || v == 0 || u == n - 1 || v == n - 1 { local } else { per_hemisphere + (u - 1) * (n - 2) + (v - 1) }
}

/// The Listing 1 index at compact index `compact` for `n = subdivisions` (clamped);
/// mirrored by the WGSL `octahedral_listing_index`. Compact indices beyond the count are
/// taken modulo it.
pub const fn listing_from_compact_index(compact: u32, subdivisions: u32) -> u32 {
    let n = clamp_subdivisions(subdivisions);
    let per_hemisphere = n * n;
    let compact = compact % compact_view_count(n);
    if n == 1 || compact < per_hemisphere {
        return compact;
    }
    let interior = compact - per_hemisphere;
    let (u, v) = (interior / (n - 2) + 1, interior % (n - 2) + 1);
    per_hemisphere + u * n + v
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn compact_layout_is_a_bijection_onto_the_distinct_directions() {
        for n in 1..=14 {
            let views = OctahedralViews::new(n).unwrap();
            let compact = CompactViews::new(views);
            let count = compact.view_count();
            assert_eq!(count, if n == 1 { 2 } else { 2 * n * n - 4 * (n - 1) });
            // compact -> listing -> compact is the identity, and directions are distinct.
            let mut points = [glam::IVec3::ZERO; 2 * 14 * 14];
            for c in 0..count {
                let listing = compact.listing_index(c).unwrap();
                assert_eq!(compact.compact_index(listing), Some(c), "n={n} compact {c}");
                points[c as usize] = views.view_lattice_point(listing).unwrap();
            }
            for a in 0..count as usize {
                for b in 0..a {
                    assert_ne!(points[a], points[b], "n={n}: compact views {a} and {b} coincide");
                }
            }
            // Every Listing 1 view maps to a compact view with exactly its direction.
            for index in 0..views.view_count() {
                let c = compact.compact_index(index).unwrap();
                assert!(c < count);
                let twin = compact.listing_index(c).unwrap();
                assert_eq!(views.view_lattice_point(twin), views.view_lattice_point(index), "n={n} view {index}");
            }
            assert_eq!(compact.compact_index(views.view_count()), None);
            assert_eq!(compact.listing_index(count), None);
        }
    }
}

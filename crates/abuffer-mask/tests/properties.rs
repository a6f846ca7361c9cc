//! Property tests of the mask algebra and of the table lookup.

use std::f32::consts::PI;
use std::sync::OnceLock;

use abuffer_mask::{Mask, Mask128, MaskTable, TableLayout};
use proptest::prelude::*;

fn table() -> &'static MaskTable<4> {
    static TABLE: OnceLock<MaskTable<4>> = OnceLock::new();
    TABLE.get_or_init(|| MaskTable::paper().unwrap())
}

fn mask() -> impl Strategy<Value = Mask128> {
    any::<[u32; 4]>().prop_map(|words| Mask { words })
}

/// Any `f32` `θ` or `v`, biased towards the useful range and special values.
fn parameter() -> impl Strategy<Value = f32> {
    prop_oneof![
        8 => -4.0_f32..4.0,
        1 => any::<f32>(),
        1 => prop_oneof![Just(0.0_f32), Just(-0.0), Just(f32::NAN), Just(f32::INFINITY), Just(f32::NEG_INFINITY)],
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn union_is_commutative_and_idempotent(a in mask(), b in mask()) {
        prop_assert_eq!(a.union(b), b.union(a));
        prop_assert_eq!(a.union(a), a);
        prop_assert_eq!(a.union(b).union(b), a.union(b));
    }

    #[test]
    fn popcount_is_subadditive_and_inclusion_exclusion_holds(a in mask(), b in mask()) {
        let union = a.union(b).popcount();
        prop_assert!(union <= a.popcount() + b.popcount());
        prop_assert_eq!(union + a.intersection(b).popcount(), a.popcount() + b.popcount());
        prop_assert_eq!(a.difference(b).popcount() + a.intersection(b).popcount(), a.popcount());
    }

    #[test]
    fn coverage_is_in_the_unit_interval(theta in parameter(), v in parameter(), a in mask()) {
        let coverage = table().lookup(theta, v).coverage();
        prop_assert!((0.0..=1.0).contains(&coverage));
        prop_assert!((0.0..=1.0).contains(&a.coverage()));
        prop_assert!(table().layout().cell_index(theta, v) < 256 * 256);
    }

    #[test]
    fn complementary_cells_partition_the_samples(i in 0_u32..256, j in 0_u32..256) {
        let layout = table().layout();
        let (ci, cj) = layout.complementary_cell(i, j);
        let a = table().cell_mask(i * 256 + j);
        let b = table().cell_mask(ci * 256 + cj);
        prop_assert_eq!(a.intersection(b), Mask::EMPTY);
        prop_assert_eq!(a.union(b), Mask::FULL);
    }

    #[test]
    fn complementary_half_planes_cover_everything_once(theta in -PI..PI, v in -1.5_f32..1.5) {
        // (θ + π, −v) is the complement of (θ, v); away from cell boundaries (where the
        // rounding of θ + π may pick the neighbour cell) the lookups partition the samples.
        let layout = table().layout();
        let (t, s) = (theta * layout.theta_scale(), v * layout.v_scale());
        prop_assume!((t - t.round()).abs() > 1e-3 && (s - s.round()).abs() > 1e-3);
        let a = table().lookup(theta, v);
        let b = table().lookup(theta + PI, -v);
        prop_assert_eq!(a.intersection(b), Mask::EMPTY);
        prop_assert_eq!(a.union(b), Mask::FULL);
    }

    #[test]
    fn masks_grow_with_v(theta in -PI..PI, v in -1.5_f32..1.5, dv in 0.0_f32..1.0) {
        let (a, b) = (table().lookup(theta, v), table().lookup(theta, v + dv));
        prop_assert_eq!(a.difference(b), Mask::EMPTY, "a larger v must cover a superset");
    }
}

#[test]
fn small_layouts_build_complementary_tables() {
    let table = MaskTable::<1>::new(TableLayout::new(6, 4).unwrap()).unwrap();
    let layout = table.layout();
    for i in 0..6 {
        for j in 0..4 {
            let (ci, cj) = layout.complementary_cell(i, j);
            assert_eq!(table.cell_mask(i * 4 + j).complement(), table.cell_mask(ci * 4 + cj));
        }
    }
}

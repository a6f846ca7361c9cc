//! Times the generation of the paper's stacking sizes and checks their gaps.
//!
//! `cargo run --release -p grain-scenes --example generate_timing [-- 20k 200k 1.6M 20M]`

use std::time::Instant;

use glam::Vec4;
use grain_scenes::{GrainRadii, Region, Shake, Stacking, StackingSize, StackingSpec};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let sizes: Vec<StackingSize> = match std::env::args().skip(1).collect::<Vec<_>>() {
        args if args.is_empty() => StackingSize::ALL.to_vec(),
        args => args.iter().map(|a| a.parse()).collect::<Result<_, _>>()?,
    };
    let radii = GrainRadii::new(0.6, 1.0)?;
    for size in sizes {
        for region in [Region::Pile { slope: 0.6 }, Region::Box { aspect: glam::Vec3::ONE }] {
            let mut spec = StackingSpec::new(size.count(), radii);
            spec.seed = 1;
            spec.region = region;
            spec.scale_jitter = 0.2;
            spec.jitter = 0.1;
            spec.spacing = 0.95;
            let start = Instant::now();
            let stacking = Stacking::generate(&spec)?;
            let generate = start.elapsed();
            let start = Instant::now();
            let inner = stacking.min_inner_gap();
            let gap_time = start.elapsed();
            let shake = Shake::new(0.05, 2.0, 1.0)?;
            let mut c = vec![Vec4::ZERO; stacking.len()];
            let mut q = vec![Vec4::ZERO; stacking.len()];
            let start = Instant::now();
            shake.pose_at(&stacking, 0.5, &mut c, &mut q)?;
            let pose = start.elapsed();
            println!(
                "{size:>5} {region:?}: generate {:.3} s, min inner gap {inner} ({:.3} s), pose {:.3} s, bounds {:?}",
                generate.as_secs_f64(),
                gap_time.as_secs_f64(),
                pose.as_secs_f64(),
                stacking.bounds()
            );
        }
    }
    Ok(())
}

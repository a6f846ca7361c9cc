//! Prints the atlas chosen for each measured grain, screen size and SSIM budget, from the
//! committed accuracy table, next to the paper's eq. 4 choice.
//!
//! ```text
//! cargo run -p grain-impostor --example choose_atlas
//! ```

use grain_impostor::accuracy::{sampling_mode_name, view_layout_name};
use grain_impostor::choice::{choose_atlas, measured_accuracy, paper_choice};

fn main() -> Result<(), String> {
    let rows = measured_accuracy()?;
    println!("| grain | px | budget (1 − SSIM) | n | p | mode | layout | MiB | measured SSIM | eq. 4 (n, p) |");
    println!("|---|---|---|---|---|---|---|---|---|---|");
    for grain in ["ball", "bean", "rock", "nut"] {
        for diameter in [32.0_f32, 64.0] {
            let paper = paper_choice(diameter, 1024).map_or("none ≤ 1024".into(), |(n, p)| format!("({n}, {p})"));
            for budget in [0.05, 0.08, 0.12] {
                match choose_atlas(&rows, grain, diameter, budget) {
                    Some(c) => println!(
                        "| {grain} | {diameter} | {budget} | {} | {} | {} | {} | {:.2} | {:.4} | {paper} |",
                        c.subdivisions,
                        c.texels,
                        sampling_mode_name(c.mode),
                        view_layout_name(c.layout),
                        c.atlas_bytes as f64 / 1048576.0,
                        c.measured_ssim
                    ),
                    None => println!("| {grain} | {diameter} | {budget} | – | – | – | – | – | not met | {paper} |"),
                }
            }
        }
    }
    Ok(())
}

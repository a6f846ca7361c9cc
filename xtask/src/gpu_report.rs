//! `cargo xtask gpu-report [OUT_DIR] [--quick]`: every `bench-gpu` subject of the project
//! in one run, each into `OUT_DIR/<subject>/`, and a page of their tables
//! (`OUT_DIR/index.html`, the showcase's machinery): the one command that a person with a
//! GPU runs to get every performance figure. By default each subject runs at its own
//! settings, which are the paper sizes on a GPU (20 M grains, 1024² cone tracing, DDMs at
//! 1920×1080, …) and
//! reduced ones on a software adapter; `--quick` shrinks them further (a smoke run).

use crate::report_page::ImageSubject;
use crate::showcase::{Report, Stage};

/// The sections: the papers with a GPU benchmark.
const PAPERS: [(&str, &str); 3] = [
    ("stackings", "Michel & Boubekeur, Real Time Multiscale Rendering of Dense Dynamic Stackings (CGF 2020)"),
    ("ddm", "Mehra & Kumar, Accurate and Efficient Rendering of Detail using Directional Distance Maps"),
    (
        "svo",
        "Heitz & Neyret, Representing Appearance and Pre-filtering Subpixel Data in Sparse Voxel Octrees (HPG 2012)",
    ),
];

/// Every `bench-gpu` subject; flags at (quick, default, default).
const STAGES: &[Stage] = &[
    Stage {
        folder: "culling",
        paper: "stackings",
        title: "Occluder map and splitter (§7–8)",
        about: "GPU time of the occluder map and the splitter for piles of coffee beans and balls at 1920×1080, every \
                occluder map the adapter has, the paper's cone, + Hi-Z, + two-phase, both list orders, two shots.",
        command: "bench-gpu culling",
        flags: [&["--grains", "20k", "--frames", "3", "--resolution", "480x270"], &[], &[]],
        subject: ImageSubject::FirstWords(1),
    },
    Stage {
        folder: "stackings",
        paper: "stackings",
        title: "The multiscale renderer stage by stage (§3, §9–10)",
        about: "Occluder map, split, meshes, impostor and point visibility, resolve and shading over a backward dolly \
                at 1920×1080, beans and sand, every visibility buffer, early-Z on and off, compute and raster.",
        command: "bench-gpu stackings",
        flags: [&["--grains", "20k", "--frames", "1", "--scene", "bean", "--resolution", "480x270"], &[], &[]],
        subject: ImageSubject::FirstWords(1),
    },
    Stage {
        folder: "ddm",
        paper: "ddm",
        title: "The DDM renderer on a plane and a torus (Table 3, §5)",
        about: "GPU ms per frame of ddm-render (G-buffer, exit distance, trace, shading) at 1920×1080 for every tile, \
                both base meshes, every method, with and without shadow rays, compressed (4³ blocks) and \
                uncompressed maps.",
        command: "bench-gpu ddm",
        flags: [&["--quick"], &[], &[]],
        subject: ImageSubject::FirstWords(1),
    },
    Stage {
        folder: "svo",
        paper: "svo",
        title: "The cone tracer along a dolly (Fig. 8)",
        about: "GPU ms, µs per covered pixel and cone elements per pixel for every model, plain, with a shadow cone \
                and with a lens, at every view of the dolly.",
        command: "bench-gpu svo",
        flags: [&["--pixels", "64", "--levels", "4", "--views", "2", "--zoom", "2", "--frames", "1"], &[], &[]],
        subject: ImageSubject::FirstWords(1),
    },
];

/// The GPU report.
pub const GPU_REPORT: Report = Report {
    title: "GPU benchmarks",
    papers: &PAPERS,
    stages: STAGES,
    settings: [
        "quick (every subject shrunk: a smoke run)",
        "default (each subject's own settings: paper sizes on a GPU, reduced on a software adapter)",
        "default (each subject's own settings: paper sizes on a GPU, reduced on a software adapter)",
    ],
};

/// The command.
pub fn run(args: &crate::cli::Args<'_>) -> Result<(), String> {
    let settings =
        if args.flag("quick") { crate::showcase::Settings::Quick } else { crate::showcase::Settings::Default };
    crate::showcase::write(&args.out_dir(), &GPU_REPORT, settings).map(|_| ())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_bench_gpu_subject_is_a_stage() {
        crate::showcase::check_stages(&GPU_REPORT);
        let crate::cli::Positional::SubjectThenOutDir(subjects) =
            crate::command("bench-gpu").expect("bench-gpu").positional
        else {
            panic!("bench-gpu takes a subject");
        };
        let mut staged: Vec<&str> = STAGES.iter().filter_map(|s| s.command.strip_prefix("bench-gpu ")).collect();
        staged.sort_unstable();
        let mut all = subjects.to_vec();
        all.sort_unstable();
        assert_eq!(staged, all);
    }
}

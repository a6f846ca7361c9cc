//! `cargo xtask showcase [OUT_DIR] [--quick | --full | --check]`: the report. Every stage is
//! one of the project's commands, run as a child process of this xtask into a folder of
//! its own (`OUT_DIR/<stage>/`, emptied first), its output printed as it comes and kept;
//! then [`crate::report_page`] writes `OUT_DIR/index.html` from what each folder holds:
//! one section per paper, one article per stage. `--check` opens an existing page in
//! headless Chromium instead ([`crate::report_check`]).
//!
//! Settings: the default finishes in about 5 minutes on 2 cores with lavapipe; `--quick`
//! (CI's) shrinks the slowest stages; `--full` runs every command at its own (paper-size)
//! settings, for a real GPU.

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Instant;

use crate::cli::Args;
use crate::report_page::{Article, ImageSubject, Meta, Section, read_csv, render};

/// How big the stages run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Settings {
    /// CI's: the slowest stages shrunk further.
    Quick,
    /// Every command at its `--quick` settings.
    Default,
    /// Every command at its own settings (paper sizes).
    Full,
}

/// A page of stages: the showcase, or the GPU report ([`crate::gpu_report`]).
pub struct Report {
    /// The page's heading.
    pub title: &'static str,
    /// Its sections, in page order: (anchor, heading).
    pub papers: &'static [(&'static str, &'static str)],
    /// Its stages, in page order.
    pub stages: &'static [Stage],
    /// What [`Settings::Quick`], [`Settings::Default`] and [`Settings::Full`] mean here.
    pub settings: [&'static str; 3],
}

/// The showcase: every figure of the project.
pub const SHOWCASE: Report = Report {
    title: "The report",
    papers: &PAPERS,
    stages: STAGES,
    settings: [
        "quick (CI: every command's --quick settings, the slowest smaller still)",
        "default (every command's --quick settings)",
        "full (every command's own settings: paper sizes, for a real GPU)",
    ],
};

/// The papers, in page order: (anchor, heading).
const PAPERS: [(&str, &str); 3] = [
    ("stackings", "Michel & Boubekeur, Real Time Multiscale Rendering of Dense Dynamic Stackings (CGF 2020)"),
    ("ddm", "Mehra & Kumar, Accurate and Efficient Rendering of Detail using Directional Distance Maps"),
    (
        "svo",
        "Heitz & Neyret, Representing Appearance and Pre-filtering Subpixel Data in Sparse Voxel Octrees (HPG 2012)",
    ),
];

/// One stage: a command run into `OUT_DIR/<folder>`.
pub struct Stage {
    /// The folder under the page's, also the article's anchor.
    pub folder: &'static str,
    /// The paper's anchor in [`PAPERS`].
    pub paper: &'static str,
    /// The article's heading.
    pub title: &'static str,
    /// What it shows.
    pub about: &'static str,
    /// The xtask command and the words before its `OUT_DIR` (`bench-gpu svo`).
    pub command: &'static str,
    /// Its flags at [`Settings::Quick`], [`Settings::Default`] and [`Settings::Full`].
    pub flags: [&'static [&'static str]; 3],
    /// The part of its images' file names that names what they show (one row each).
    pub subject: ImageSubject,
}

impl Stage {
    /// The flags at `settings`.
    pub fn flags(&self, settings: Settings) -> &'static [&'static str] {
        self.flags[settings as usize]
    }
}

const Q: &[&str] = &["--quick"];

/// Every stage, in page order (grouped by paper).
pub const STAGES: &[Stage] = &[
    Stage {
        folder: "octahedral",
        paper: "stackings",
        title: "Octahedral view layout (Listing 1, eq. 4)",
        about: "The angle between a direction and its nearest view against n, with the eq. 4 validity half-angles \
                the atlas resolution asks for.",
        command: "octahedral-error",
        flags: [&[], &[], &[]],
        subject: ImageSubject::FirstWords(1),
    },
    Stage {
        folder: "impostor-accuracy",
        paper: "stackings",
        title: "Impostor accuracy (Fig. 12–13)",
        about: "SSIM and RMSE of octahedral impostors against the mesh for the four procedural grains, every (n, p), \
                the three sampling modes, against atlas memory and against the time of the cloud pass that draws them (the \
                Pareto front labelled); per grain a strip mesh | planar | spherical | mixed.",
        command: "impostor-accuracy",
        flags: [Q, Q, &[]],
        subject: ImageSubject::FirstWords(2),
    },
    Stage {
        folder: "culling",
        paper: "stackings",
        title: "Occlusion culling (Fig. 15, §8)",
        about: "The share of grains still rendered after culling against the r/R the test assumes, for three shots, \
                the paper's cone beside occluder fusion and two-phase culling.",
        command: "culling-chart",
        flags: [Q, Q, &[]],
        subject: ImageSubject::FirstWords(1),
    },
    Stage {
        folder: "interpenetration",
        paper: "stackings",
        title: "Interpenetrating grains (a hypothesis relaxed)",
        about: "The pile of the bean and the nut packed tighter step by step, from outer balls disjoint (no two grains \
                touch) to the tightest spacing the culling allows, every grain an impostor against the meshes 4 × 4 \
                supersampled (their depth test resolves each intersection); at the tightest, the mesh, the impostors \
                and the ꟻLIP map.",
        command: "interpenetration",
        flags: [&["--quick", "--grains", "500"], Q, &[]],
        subject: ImageSubject::FirstWords(1),
    },
    Stage {
        folder: "stackings",
        paper: "stackings",
        title: "The multiscale renderer over a bean pile (Fig. 9)",
        about: "A backward dolly from a close view to the whole pile, every tier in one frame, each frame against the \
                all-mesh reference; per-stage times.",
        command: "stackings",
        flags: [&["--quick", "--accuracy", "--grains", "2000"], &["--quick", "--accuracy"], &["--accuracy"]],
        subject: ImageSubject::LastWord,
    },
    Stage {
        folder: "select-grains",
        paper: "stackings",
        title: "Model no more than a scene needs: the least atlas within a budget",
        about: "For three ꟻLIP budgets, per grain, the impostor atlas (n, p, sampling mode, layout) the selector picks \
                from the committed table (crates/grain-impostor/tables/grain_selection.csv: 64 grains seen from 64 \
                directions at 16, 32 and 64 px against the supersampled mesh; cost the atlas's GPU memory), checked \
                on other directions at 24 px: the choice's image, its ꟻLIP map and measured error, every candidate on \
                the table's Pareto front.",
        command: "select",
        flags: [&["--only", "grains"], &["--only", "grains"], &["--only", "grains"]],
        subject: ImageSubject::FirstWords(1),
    },
    Stage {
        folder: "select-tiers",
        paper: "stackings",
        title: "Model no more than a scene needs: points or impostors by projected size",
        about: "For three ꟻLIP budgets, per grain, the tier (every grain a point or an impostor) the selector picks from \
                the committed table (crates/grain-renderer/tables/tier_selection.csv: a pile of 2000 grains from the \
                wide shot at 1 to 4 px per grain against its meshes 4 × 4 supersampled, worst size up to each; cost the \
                frame's time), checked on the middle shot at 2.5 px: the choice's image, its ꟻLIP map and measured \
                error. `stackings` reads its point thresholds from the same table (points wherever ꟻLIP ≤ 0.1).",
        command: "select",
        flags: [&["--only", "tiers"], &["--only", "tiers"], &["--only", "tiers"]],
        subject: ImageSubject::FirstWords(1),
    },
    Stage {
        folder: "ddm-compression",
        paper: "ddm",
        title: "Compression of directional distance maps (Table 3)",
        about: "The plain distance map and the downward DDMs 2×1, 4×1, 8×1 compressed losslessly in blocks of 2, 4, 8.",
        command: "ddm-compression",
        flags: [Q, Q, &[]],
        subject: ImageSubject::FirstWords(1),
    },
    Stage {
        folder: "ddm-trace",
        paper: "ddm",
        title: "Tracing the mesostructures (Tables 1–3)",
        about: "Every tracing method on the five mesostructure tiles against the exact mesh: accuracy, steps, time; \
                the steps against the view angle.",
        command: "ddm-trace",
        flags: [
            &["--quick", "--resolution", "64x48", "--timing-rounds", "3"],
            &["--quick", "--timing-rounds", "5"],
            &[],
        ],
        subject: ImageSubject::FirstWords(1),
    },
    Stage {
        folder: "ddm-resolution",
        paper: "ddm",
        title: "Error against resolution, against each tile's own surface",
        about: "Each patch construction (the paper's C⁰, fitted quadrics, exact triangles, adaptive, watertight) on \
                the DDM 4×1 as the tiles are sampled by finer grids, measured against the analytic spheres and tori \
                and the height fields' triangles: p99 |SDF(hit)| and leaks.",
        command: "ddm-resolution",
        flags: [Q, Q, &[]],
        subject: ImageSubject::FirstWords(2),
    },
    Stage {
        folder: "ddm-render",
        paper: "ddm",
        title: "Mesostructures on a base mesh (§3)",
        about: "The tiles mapped onto a plane of 4 × 4 tiles and a torus: rasterized base mesh, per-pixel trace in \
                tangent space, shading and shadow rays; each method beside the reference (the mesh's own triangles \
                through the same pipeline) with its ꟻLIP map.",
        command: "ddm-render",
        flags: [Q, &["--quick", "--resolution", "480x360"], &[]],
        subject: ImageSubject::FirstWords(2),
    },
    Stage {
        folder: "select",
        paper: "ddm",
        title: "Model no more than a scene needs: the cheapest DDM method within a budget",
        about: "For three ꟻLIP budgets, per mesostructure, the method the selector picks from the committed table \
                (crates/ddm-experiments/tables/ddm_selection.csv: 95 % prediction bound of four cameras' errors, CPU cost), checked on a \
                held-out camera: the choice's image, its ꟻLIP map and measured error, and every candidate on the \
                table's Pareto front.",
        command: "select",
        flags: [&["--only", "ddm"], &["--only", "ddm"], &["--only", "ddm"]],
        subject: ImageSubject::FirstWords(1),
    },
    Stage {
        folder: "fig9",
        paper: "svo",
        title: "Micro-visibility against ray-traced truth (Fig. 9)",
        about: "The mean attribute seen at each view angle on Gaussian and non-Gaussian height fields, ray traced, \
                against eq. 17 and MIP-mapping.",
        command: "fig9",
        flags: [Q, Q, &[]],
        subject: ImageSubject::FirstWords(1),
    },
    Stage {
        folder: "abuffer",
        paper: "svo",
        title: "A-buffer masks (§5.4)",
        about: "The coverage error of the (θ, v) mask tables against the number of samples N.",
        command: "abuffer-chart",
        flags: [&[], &[], &[]],
        subject: ImageSubject::FirstWords(1),
    },
    Stage {
        folder: "select-smith",
        paper: "svo",
        title: "Model no more than a scene needs: the cheapest Smith model within a budget",
        about: "For three ꟻLIP budgets, per surface, the appearance model (MIP-mapping, eq. 17, eq. 17 with the cubic or \
                the table correction, the correlated model) the selector picks from the committed table \
                (crates/microsurface-truth/tables/smith_selection.csv: a plane seen up to a largest view angle, worst of \
                16 band cameras and two truths, CPU cost per pixel), checked on a held-out camera over another \
                realization: the choice's image, its ꟻLIP map and measured error, every candidate on the table's \
                Pareto front.",
        command: "select",
        flags: [&["--only", "smith"], &["--only", "smith"], &["--only", "smith"]],
        subject: ImageSubject::FirstWords(1),
    },
    Stage {
        folder: "svo",
        paper: "svo",
        title: "The cone tracer along a dolly, with depth of field and soft shadows (Fig. 8, 10–12)",
        about: "Every model (masks, α-blending, nearest voxel, separate filtering) against the supersampled truth of \
                the unfiltered surface, per view; error against time.",
        command: "svo",
        flags: [&["--quick", "--levels", "4"], Q, &[]],
        subject: ImageSubject::FirstWords(2),
    },
    Stage {
        folder: "svo-stability",
        paper: "svo",
        title: "Where the SVO's hypotheses fail (H7, H6, H3, grazing views)",
        about: "Thin plates, strong curvature and box corners, non-Gaussian micro-surfaces and grazing views, each \
                relaxed step by step, every model against the truth.",
        command: "svo-stability",
        flags: [Q, Q, &[]],
        subject: ImageSubject::FirstWords(1),
    },
];

/// A bar of `done` out of `total` stages.
fn progress_bar(done: usize, total: usize) -> String {
    const WIDTH: usize = 22;
    let filled = WIDTH * done / total.max(1);
    format!("[{}{}] {done}/{total}", "#".repeat(filled), "-".repeat(WIDTH - filled))
}

/// Runs `stage` into `dir` as a child process of this xtask, printing its output as it comes;
/// returns what it printed and its time.
fn run_stage(stage: &Stage, settings: Settings, dir: &Path) -> Result<(String, f64), String> {
    if dir.exists() {
        std::fs::remove_dir_all(dir).map_err(|e| format!("cannot empty {}: {e}", dir.display()))?;
    }
    std::fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let exe = std::env::current_exe().map_err(|e| format!("cannot locate xtask's binary: {e}"))?;
    let start = Instant::now();
    let mut child = Command::new(&exe)
        .args(stage.command.split(' '))
        .arg(dir)
        .args(stage.flags(settings))
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| format!("cannot run {}: {e}", exe.display()))?;
    let stderr = child.stderr.take().ok_or("no pipe for the stage's errors")?;
    let errors = std::thread::spawn(move || {
        let mut kept = String::new();
        for line in BufReader::new(stderr).lines().map_while(Result::ok) {
            eprintln!("  | {line}");
            kept += &line;
            kept.push('\n');
        }
        kept
    });
    let mut output = String::new();
    if let Some(stdout) = child.stdout.take() {
        for line in BufReader::new(stdout).lines().map_while(Result::ok) {
            println!("  | {line}");
            output += &line;
            output.push('\n');
        }
    }
    let status = child.wait().map_err(|e| format!("cannot wait for {}: {e}", stage.command))?;
    let errors = errors.join().unwrap_or_default();
    if !status.success() {
        return Err(format!("stage {} (`cargo xtask {}`) failed ({status}):\n{errors}", stage.folder, stage.command));
    }
    if !errors.is_empty() {
        output += "\n(standard error)\n";
        output += &errors;
    }
    Ok((output, start.elapsed().as_secs_f64()))
}

/// The article for a stage that wrote into `dir`.
fn article(stage: &Stage, settings: Settings, dir: &Path, output: String, seconds: f64) -> Result<Article, String> {
    let mut files: Vec<String> = Vec::new();
    let entries = std::fs::read_dir(dir).map_err(|e| format!("cannot list {}: {e}", dir.display()))?;
    for entry in entries {
        let entry = entry.map_err(|e| format!("cannot list {}: {e}", dir.display()))?;
        if entry.path().is_file() {
            files.push(entry.file_name().to_string_lossy().into_owned());
        }
    }
    files.sort();
    let charts = crate::chart::charts_in(dir)?;
    let (mut images, mut tables, mut other_files) = (Vec::new(), Vec::new(), Vec::new());
    for file in files {
        if file == crate::chart::CHART_LIST {
            continue;
        } else if file.ends_with(".png") {
            if !charts.contains(&file) {
                images.push(file);
            }
        } else if file.ends_with(".csv") {
            tables.push((file.clone(), read_csv(&dir.join(&file))?));
        } else {
            other_files.push(file);
        }
    }
    let size = |file: &str| {
        let path = dir.join(file);
        image::image_dimensions(&path).map_err(|e| format!("cannot read {}: {e}", path.display()))
    };
    let charts = charts.iter().map(|file| Ok((file.clone(), size(file)?))).collect::<Result<Vec<_>, String>>()?;
    let mut image_rows = Vec::new();
    for row in crate::report_page::image_rows(&images, stage.subject) {
        let mut sized = Vec::new();
        for file in row {
            let (width, _) = size(&file)?;
            sized.push((file, width));
        }
        image_rows.push(sized);
    }
    let mut command = format!("cargo xtask {} OUT_DIR/{}", stage.command, stage.folder);
    for flag in stage.flags(settings) {
        command = format!("{command} {flag}");
    }
    Ok(Article {
        folder: stage.folder.to_owned(),
        title: stage.title.to_owned(),
        about: stage.about.to_owned(),
        command,
        seconds,
        charts,
        image_rows,
        tables,
        other_files,
        output,
    })
}

/// `git rev-parse HEAD`, marked when the tree has uncommitted changes.
pub fn commit() -> String {
    let git = |args: &[&str]| {
        Command::new("git")
            .args(args)
            .current_dir(crate::workspace_root())
            .output()
            .ok()
            .filter(|o| o.status.success())
            .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_owned())
    };
    match (git(&["rev-parse", "HEAD"]), git(&["status", "--porcelain", "--untracked-files=no"])) {
        (Some(head), Some(changes)) if changes.is_empty() => head,
        (Some(head), Some(_)) => format!("{head} with uncommitted changes"),
        _ => "unknown (no git repository)".into(),
    }
}

/// Now, as `YYYY-MM-DD HH:MM UTC` (civil from days, Howard Hinnant's algorithm).
pub fn utc_now() -> String {
    let seconds = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_secs());
    let (days, rest) = ((seconds / 86_400) as i64, seconds % 86_400);
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!("{year:04}-{month:02}-{day:02} {:02}:{:02} UTC", rest / 3600, rest % 3600 / 60)
}

/// Runs every stage of `report` into `out` and writes `out/index.html`.
pub fn write(out: &Path, report: &Report, settings: Settings) -> Result<PathBuf, String> {
    std::fs::create_dir_all(out).map_err(|e| format!("cannot create {}: {e}", out.display()))?;
    let adapter = gpu_harness::Gpu::new().map_err(|e| e.to_string())?.describe();
    let start = Instant::now();
    let mut articles = Vec::new();
    let stages = report.stages;
    for (i, stage) in stages.iter().enumerate() {
        println!(
            "{} {} — cargo xtask {} {}  ({:.0} s so far)",
            progress_bar(i, stages.len()),
            stage.folder,
            stage.command,
            stage.flags(settings).join(" "),
            start.elapsed().as_secs_f64()
        );
        let dir = out.join(stage.folder);
        let (output, seconds) = run_stage(stage, settings, &dir)?;
        println!("{} {} done in {seconds:.0} s", progress_bar(i + 1, stages.len()), stage.folder);
        articles.push((stage.paper, article(stage, settings, &dir, output, seconds)?));
    }
    let sections: Vec<Section<'_>> = report
        .papers
        .iter()
        .map(|&(id, title)| Section {
            id,
            title,
            articles: articles.extract_if(.., |(paper, _)| *paper == id).map(|(_, a)| a).collect(),
        })
        .collect();
    let cores = std::thread::available_parallelism().map_or(0, usize::from);
    let meta = Meta {
        title: report.title,
        adapter: &adapter,
        commit: &commit(),
        settings: report.settings[settings as usize],
        date: &utc_now(),
        machine: &format!("{cores} CPU threads ({})", std::env::consts::ARCH),
        seconds: start.elapsed().as_secs_f64(),
    };
    let page = out.join("index.html");
    std::fs::write(&page, render(&meta, &sections)).map_err(|e| format!("cannot write {}: {e}", page.display()))?;
    println!("wrote {} in {:.0} s", page.display(), meta.seconds);
    Ok(page)
}

/// The command: the page, or `--check` of an existing one.
pub fn run(args: &Args<'_>) -> Result<(), String> {
    let out = args.out_dir();
    if args.flag("check") {
        return crate::report_check::run(&out);
    }
    let settings = match (args.flag("quick"), args.flag("full")) {
        (true, _) => Settings::Quick,
        (_, true) => Settings::Full,
        _ => Settings::Default,
    };
    write(&out, &SHOWCASE, settings).map(|_| ())
}

/// Asserts that every stage of `report` is a command whose words parse at every setting,
/// in one of its sections, with a folder of its own.
#[cfg(test)]
pub fn check_stages(report: &Report) {
    for stage in report.stages {
        let mut words = stage.command.split(' ');
        let name = words.next().unwrap_or_default();
        let command = crate::command(name).unwrap_or_else(|| panic!("{}", stage.command));
        assert!(report.papers.iter().any(|(id, _)| *id == stage.paper), "{}", stage.folder);
        for settings in [Settings::Quick, Settings::Default, Settings::Full] {
            let mut given: Vec<String> = words.clone().map(str::to_owned).collect();
            given.push("dir".to_owned());
            given.extend(stage.flags(settings).iter().map(|&f| f.to_owned()));
            assert!(matches!(command.parse(&given), Ok(crate::cli::Parsed::Run(_))), "{} {given:?}", stage.command);
        }
    }
    let mut folders: Vec<&str> = report.stages.iter().map(|s| s.folder).collect();
    folders.sort_unstable();
    folders.dedup();
    assert_eq!(folders.len(), report.stages.len(), "stage folders are distinct");
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_stage_is_a_command_whose_flags_parse_at_every_setting() {
        check_stages(&SHOWCASE);
    }

    #[test]
    fn the_date_is_civil_utc() {
        let now = utc_now();
        assert!(now.len() == 20 && now.ends_with(" UTC") && now.starts_with("20"), "{now}");
    }
}

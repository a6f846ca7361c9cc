//! The command table: every `cargo xtask` command declared once (its flags, its `OUT_DIR`
//! and what runs it), the usage lines printed from it, and the tests that every command
//! parses as its usage says.

use crate::cli::{self, Command, Positional, repeated, switch, value};
use crate::{
    abuffer_chart, bench_gpu, cargo_tasks, culling_chart, ddm_build, ddm_compression, ddm_input, ddm_render,
    ddm_resolution, ddm_trace, fig9, gpu_report, impostor_accuracy, impostor_cloud, interpenetration, occlusion_check,
    octahedral_error, select, showcase, stackings, svo, svo_stability,
};

/// `--quick`: the command's quick settings.
const QUICK: cli::Flag = switch("quick");
/// `--size WxHxD`: the tile's voxels.
const SIZE: cli::Flag = value("size", "WxHxD");
/// `--obj PATH`: a grain from an OBJ file.
const OBJ: cli::Flag = value("obj", "PATH");

/// `--height-map PNG`: a grayscale height map.
const HEIGHT_MAP: cli::Flag = value("height-map", "PNG");

/// Every command, in usage order.
pub const COMMANDS: &[Command] = &[
    Command { name: "test", flags: &[], exclusive: &[], positional: Positional::None, run: cargo_tasks::test },
    Command {
        name: "test-gpu",
        flags: &[],
        exclusive: &[],
        positional: Positional::None,
        run: |_| cargo_tasks::test_gpu(),
    },
    Command {
        name: "bench",
        flags: &[value("save", "NAME"), value("compare", "NAME")],
        exclusive: &[],
        positional: Positional::PassThrough("CRITERION ARGS"),
        run: cargo_tasks::bench,
    },
    Command {
        name: "bench-gpu",
        flags: &[
            value("grains", "LIST"),
            value("frames", "N"),
            value("dolly-frames", "LIST"),
            value("scene", "NAME"),
            OBJ,
            value("mesh-above", "PX"),
            value("samples", "S"),
            HEIGHT_MAP,
            value("pixels", "N"),
            value("levels", "L"),
            value("zoom", "K"),
            value("views", "N"),
            value("resolution", "WxH"),
            QUICK,
            SIZE,
            ddm_input::SCALE,
            ddm_input::FIT_SLAB,
            ddm_input::HEIGHT,
            ddm_input::PERIODIC,
            ddm_input::CLAMP,
        ],
        exclusive: &[
            ("obj", "scene"),
            ("obj", "height-map"),
            ("scene", "height-map"),
            ("scale", "fit-slab"),
            ("periodic", "clamp"),
        ],
        positional: Positional::SubjectThenOutDir(&["culling", "ddm", "stackings", "svo"]),
        run: bench_gpu::run,
    },
    Command {
        name: "gpu-report",
        flags: &[QUICK],
        exclusive: &[],
        positional: Positional::OutDir("target/gpu-report"),
        run: gpu_report::run,
    },
    Command {
        name: "select-tables",
        flags: &[value("only", "ddm|smith|grains|tiers")],
        exclusive: &[],
        positional: Positional::None,
        run: select::tables,
    },
    Command {
        name: "select",
        flags: &[value("only", "ddm|smith|grains|tiers"), repeated("budget", "METRIC:MAX")],
        exclusive: &[],
        positional: Positional::OutDir("target/select"),
        run: select::run,
    },
    Command {
        name: "codegen",
        flags: &[],
        exclusive: &[],
        positional: Positional::None,
        run: |_| cargo_tasks::codegen(),
    },
    Command {
        name: "showcase",
        flags: &[switch("quick"), switch("full"), switch("check")],
        exclusive: &[("quick", "full"), ("quick", "check"), ("full", "check")],
        positional: Positional::OutDir("target/showcase"),
        run: showcase::run,
    },
    Command {
        name: "octahedral-error",
        flags: &[],
        exclusive: &[],
        positional: Positional::OutDir("target/octahedral"),
        run: |args| octahedral_error::run(&args.out_dir()),
    },
    Command {
        name: "fig9",
        flags: &[value("height-map", "PNG"), QUICK, switch("spectra")],
        exclusive: &[],
        positional: Positional::OutDir("target/fig9"),
        run: fig9::run,
    },
    Command {
        name: "abuffer-chart",
        flags: &[],
        exclusive: &[],
        positional: Positional::OutDir("target/showcase"),
        run: |args| abuffer_chart::run(&args.out_dir()),
    },
    Command {
        name: "ddm-compression",
        flags: &[
            QUICK,
            SIZE,
            ddm_input::OBJ,
            ddm_input::SCALE,
            ddm_input::FIT_SLAB,
            ddm_input::HEIGHT_MAP,
            ddm_input::HEIGHT,
            ddm_input::PERIODIC,
            ddm_input::CLAMP,
        ],
        exclusive: ddm_input::EXCLUSIVE,
        positional: Positional::OutDir("target/ddm-compression"),
        run: ddm_compression::run,
    },
    Command {
        name: "ddm-trace",
        flags: &[
            QUICK,
            SIZE,
            value("resolution", "WxH"),
            value("timing-rounds", "N"),
            value("watertight-subdivision", "N"),
            ddm_input::OBJ,
            ddm_input::SCALE,
            ddm_input::FIT_SLAB,
            ddm_input::HEIGHT_MAP,
            ddm_input::HEIGHT,
            ddm_input::PERIODIC,
            ddm_input::CLAMP,
        ],
        exclusive: ddm_input::EXCLUSIVE,
        positional: Positional::OutDir("target/ddm-trace"),
        run: ddm_trace::run,
    },
    Command {
        name: "ddm-render",
        flags: &[
            QUICK,
            SIZE,
            value("resolution", "WxH"),
            ddm_input::OBJ,
            ddm_input::SCALE,
            ddm_input::FIT_SLAB,
            ddm_input::HEIGHT_MAP,
            ddm_input::HEIGHT,
            ddm_input::PERIODIC,
            ddm_input::CLAMP,
        ],
        exclusive: ddm_input::EXCLUSIVE,
        positional: Positional::OutDir("target/ddm-render"),
        run: ddm_render::run,
    },
    Command {
        name: "impostor-accuracy",
        flags: &[QUICK, repeated("obj", "PATH")],
        exclusive: &[],
        positional: Positional::OutDir("target/impostor-accuracy"),
        run: impostor_accuracy::run,
    },
    Command {
        name: "impostor-cloud",
        flags: &[
            OBJ,
            value("grain", "NAME"),
            value("n", "N"),
            value("p", "P"),
            value("mode", "MODE"),
            value("grains", "COUNT"),
        ],
        exclusive: &[("obj", "grain")],
        positional: Positional::OutDir("target/impostor-cloud"),
        run: impostor_cloud::run,
    },
    Command {
        name: "occlusion-check",
        flags: &[value("cases", "N"), value("seed", "S")],
        exclusive: &[],
        positional: Positional::None,
        run: occlusion_check::run,
    },
    Command {
        name: "interpenetration",
        flags: &[value("grains", "COUNT"), QUICK],
        exclusive: &[],
        positional: Positional::OutDir("target/interpenetration"),
        run: interpenetration::run,
    },
    Command {
        name: "culling-chart",
        flags: &[value("grains", "COUNT"), QUICK],
        exclusive: &[],
        positional: Positional::OutDir("target/culling"),
        run: culling_chart::run,
    },
    Command {
        name: "stackings",
        flags: &[
            value("grains", "COUNT"),
            value("frames", "K"),
            OBJ,
            value("grain", "NAME"),
            value("mix", "NAME"),
            value("mesh-above", "PX"),
            value("point-below", "PX"),
            switch("shake"),
            switch("accuracy"),
            value("samples", "S"),
            QUICK,
        ],
        exclusive: &[("obj", "grain"), ("shake", "accuracy")],
        positional: Positional::OutDir("target/stackings"),
        run: stackings::run,
    },
    Command {
        name: "svo",
        flags: &[
            value("scene", "NAME"),
            OBJ,
            HEIGHT_MAP,
            value("zoom", "K"),
            value("views", "N"),
            value("pixels", "N"),
            value("levels", "L"),
            value("frames", "N"),
            QUICK,
        ],
        exclusive: &[("scene", "obj"), ("scene", "height-map"), ("obj", "height-map")],
        positional: Positional::OutDir("target/svo"),
        run: svo::run,
    },
    Command {
        name: "ddm-build",
        flags: &[
            QUICK,
            SIZE,
            value("cones", "MxN"),
            switch("plain"),
            switch("gpu"),
            value("tolerance", "T"),
            ddm_input::OBJ,
            ddm_input::SCALE,
            ddm_input::FIT_SLAB,
            ddm_input::HEIGHT_MAP,
            ddm_input::HEIGHT,
            ddm_input::PERIODIC,
            ddm_input::CLAMP,
        ],
        exclusive: &[("obj", "height-map"), ("scale", "fit-slab"), ("periodic", "clamp"), ("cones", "plain")],
        positional: Positional::OutDir("target/ddm-build"),
        run: ddm_build::run,
    },
    Command {
        name: "ddm-resolution",
        flags: &[QUICK],
        exclusive: &[],
        positional: Positional::OutDir("target/ddm-resolution"),
        run: ddm_resolution::run,
    },
    Command {
        name: "svo-stability",
        flags: &[QUICK],
        exclusive: &[],
        positional: Positional::OutDir("target/svo-stability"),
        run: svo_stability::run,
    },
];

/// The usage of every command.
pub fn usage() -> String {
    let mut text = String::from("usage (`cargo xtask COMMAND --help` prints one):");
    for command in COMMANDS {
        text += &format!("\n  {}", command.usage());
    }
    text
}

/// The command called `name`.
pub fn command(name: &str) -> Option<&'static Command> {
    COMMANDS.iter().find(|c| c.name == name)
}

#[cfg(test)]
mod tests {
    use std::path::PathBuf;

    use ddm_experiments::compression::CompressionSettings;
    use ddm_experiments::trace_tables::{TraceMethod, TraceTablesSettings};
    use glam::UVec3;
    use octahedral_map::SamplingMode;

    use super::*;
    use crate::cli::{Args, Parsed};
    use crate::{run, workspace_root};

    fn words(text: &str) -> Vec<String> {
        text.split_whitespace().map(str::to_owned).collect()
    }

    /// The arguments of `cargo xtask NAME TEXT`, or the parse error.
    fn parse(name: &str, text: &str) -> Result<Args<'static>, String> {
        match command(name).unwrap_or_else(|| panic!("no command {name}")).parse(&words(text))? {
            Parsed::Run(args) => Ok(args),
            Parsed::Help(usage) => Err(format!("help: {usage}")),
        }
    }

    fn root(path: &str) -> PathBuf {
        workspace_root().join(path)
    }

    /// Every command of the table, so that a new one cannot skip it (parsed only: a
    /// command that took the flag would otherwise run).
    #[test]
    fn every_command_rejects_an_unknown_flag_with_its_usage() {
        for command in COMMANDS {
            let usage = format!("usage: {}", command.usage());
            if let Positional::PassThrough(_) = command.positional {
                // `bench` hands every argument to criterion: checked below, without running.
                continue;
            }
            for flag in ["--obj-typo", "-x"] {
                let error = command.parse(&words(&format!("{flag} out"))).err().expect(command.name);
                assert!(error.starts_with(&format!("{}: unknown flag {flag}\n", command.name)), "{error}");
                assert!(error.ends_with(&usage), "{error}");
            }
        }
        // Through `run`, as `main` calls it: the example writes nothing.
        let error = run(&words("ddm-trace --mesh foo.obj")).unwrap_err();
        assert!(error.starts_with("ddm-trace: unknown flag --mesh\n"), "{error}");
        // A tile file that does not exist fails before anything is created or traced.
        let error = run(&words("ddm-trace --obj no-such-tile.obj")).unwrap_err();
        assert!(error.starts_with("--obj no-such-tile.obj: "), "{error}");
        let Ok(args) = parse("bench", "--obj-typo -x out") else { panic!("bench parses anything") };
        assert_eq!(args.rest(), words("--obj-typo -x out"));
    }

    #[test]
    fn every_command_prints_its_usage_with_help() {
        for command in COMMANDS {
            let parsed = command.parse(&words("--help"));
            assert!(matches!(parsed, Ok(Parsed::Help(ref u)) if *u == command.usage()), "{}", command.name);
            assert!(command.usage().starts_with(&format!("cargo xtask {}", command.name)));
        }
        assert!(run(&words("--help")).is_ok() && run(&words("help")).is_ok());
    }

    #[test]
    fn an_unknown_or_missing_command_gets_the_usage() {
        for text in ["ddm-tracing --quick", ""] {
            let error = run(&words(text)).unwrap_err();
            assert!(error.ends_with(&usage()), "{error}");
        }
        for command in COMMANDS {
            assert!(usage().contains(&format!("\n  {}", command.usage())));
        }
    }

    #[test]
    fn a_second_positional_is_rejected() {
        for command in COMMANDS {
            let error = match command.positional {
                Positional::OutDir(_) => command.parse(&words("a b")).err(),
                Positional::None => command.parse(&words("a")).err(),
                Positional::PassThrough(_) => continue,
                Positional::SubjectThenOutDir(subjects) => command.parse(&words(&format!("{} a b", subjects[0]))).err(),
            };
            let error = error.unwrap_or_else(|| panic!("{} took it", command.name));
            assert!(error.contains("unexpected argument"), "{error}");
            assert!(error.ends_with(&command.usage()), "{error}");
        }
    }

    #[test]
    fn a_subject_is_required_known_and_names_the_default_folder() {
        let error = parse("bench-gpu", "").err().unwrap();
        assert!(error.contains("needs a subject: culling"), "{error}");
        let error = parse("bench-gpu", "sorting").err().unwrap();
        assert!(error.contains("unknown subject `sorting` (known: culling, ddm, stackings, svo)"), "{error}");
        let args = parse("bench-gpu", "culling --frames 50").unwrap();
        assert_eq!(args.subject(), "culling");
        assert!(args.out_dir().ends_with("target/bench-gpu/culling"));
        assert_eq!(parse("bench-gpu", "culling out").unwrap().out_dir(), PathBuf::from("out"));
    }

    #[test]
    fn bench_gpu_refuses_the_flags_of_other_subjects() {
        // Checked before any adapter is asked for.
        let error = bench_gpu::run(&parse("bench-gpu", "ddm --grains 20k").unwrap()).unwrap_err();
        assert!(error.contains("--grains does not apply to `bench-gpu ddm`"), "{error}");
        for subject in ["culling", "ddm", "svo"] {
            let error =
                bench_gpu::run(&parse("bench-gpu", &format!("{subject} --dolly-frames 0,4")).unwrap()).unwrap_err();
            assert!(error.contains("--dolly-frames applies to `bench-gpu stackings` only"), "{subject}: {error}");
        }
        for subject in ["culling", "stackings", "svo"] {
            for flag in ["--quick", "--size 8x8x4", "--fit-slab", "--height 2"] {
                let error = bench_gpu::run(&parse("bench-gpu", &format!("{subject} {flag}")).unwrap()).unwrap_err();
                assert!(error.contains("applies to `bench-gpu ddm` only"), "{subject} {flag}: {error}");
            }
        }
        assert!(parse("bench-gpu", "ddm --scale 2 --fit-slab").is_err());
    }

    #[test]
    fn every_flag_with_a_value_needs_one() {
        for command in COMMANDS {
            for flag in command.flags {
                if let cli::Takes::Value(placeholder) | cli::Takes::Values(placeholder) = flag.takes {
                    let error = command.parse(&words(&format!("--{}", flag.name))).err().unwrap();
                    let expected = format!("{}: --{} needs a value {placeholder}\n", command.name, flag.name);
                    assert!(error.starts_with(&expected), "{error}");
                }
            }
        }
    }

    #[test]
    fn a_malformed_size_names_the_flag_and_value() {
        for name in ["ddm-trace", "ddm-compression"] {
            let args = parse(name, "--size 12x12").unwrap();
            let error = if name == "ddm-trace" {
                ddm_trace::Options::from_args(&args).err()
            } else {
                ddm_compression::Options::from_args(&args).err()
            };
            let error = error.unwrap();
            assert!(
                error.starts_with(&format!("{name}: --size 12x12: expected three positive sizes WxHxD\n")),
                "{error}"
            );
            assert!(error.ends_with(&command(name).unwrap().usage()));
        }
    }

    #[test]
    fn ddm_trace_and_compression_parse_to_their_settings() {
        let options = ddm_trace::Options::from_args(&parse("ddm-trace", "").unwrap()).unwrap();
        assert_eq!(
            options,
            ddm_trace::Options { out: root("target/ddm-trace"), settings: TraceTablesSettings::full(), tile: None }
        );
        let options = ddm_trace::Options::from_args(
            &parse("ddm-trace", "target/x --quick --size 4x4x2 --timing-rounds 3").unwrap(),
        )
        .unwrap();
        let settings =
            TraceTablesSettings { dims: UVec3::new(4, 4, 2), ratio_rounds: 3, ..TraceTablesSettings::quick() };
        assert_eq!(options, ddm_trace::Options { out: PathBuf::from("target/x"), settings, tile: None });
        let options =
            ddm_trace::Options::from_args(&parse("ddm-trace", "--quick --watertight-subdivision 4").unwrap()).unwrap();
        assert_eq!(options.settings.watertight_subdivision, 4);
        for bad in ["0", "9", "two"] {
            let args = parse("ddm-trace", &format!("--watertight-subdivision {bad}")).unwrap();
            let error = ddm_trace::Options::from_args(&args).unwrap_err();
            assert!(error.contains("--watertight-subdivision"), "{bad}: {error}");
        }
        let options = ddm_compression::Options::from_args(&parse("ddm-compression", "--quick out").unwrap()).unwrap();
        assert_eq!(
            options,
            ddm_compression::Options { out: PathBuf::from("out"), settings: CompressionSettings::quick(), tile: None }
        );
        let options = ddm_compression::Options::from_args(&parse("ddm-compression", "--size=3x2x1").unwrap()).unwrap();
        let settings = CompressionSettings { dims: UVec3::new(3, 2, 1), ..CompressionSettings::paper() };
        assert_eq!(options, ddm_compression::Options { out: root("target/ddm-compression"), settings, tile: None });
    }

    #[test]
    fn the_ddm_commands_take_the_users_tile() {
        use ddm_input::{Placement, TileSource};
        let tile = |name: &str, text: &str| TileSource::from_args(&parse(name, text).unwrap());
        for name in ["ddm-trace", "ddm-compression", "ddm-render"] {
            let usage = command(name).unwrap().usage();
            let tile_flags = " [--obj PATH | --height-map PNG] [--scale S | --fit-slab] [--height H]";
            assert!(usage.ends_with(&format!("{tile_flags} [--periodic | --clamp]")), "{usage}");
            {
                let periodic = |text: &str| {
                    let args = parse(name, text).unwrap();
                    ddm_input::periodic_from_args(&args, TileSource::from_args(&args).unwrap().as_ref())
                };
                assert_eq!(periodic("--obj t.obj"), Ok(true));
                assert_eq!(periodic("--obj t.obj --periodic"), Ok(true));
                assert_eq!(periodic("--obj t.obj --clamp"), Ok(false));
                assert_eq!(periodic("--height-map h.png --height 1 --clamp"), Ok(false));
                assert!(periodic("--clamp").unwrap_err().contains("--clamp needs --obj PATH or --height-map PNG"));
                assert!(parse(name, "--obj t.obj --clamp --periodic").is_err());
            }
            let obj = |placement| Ok(Some(TileSource::Obj { path: PathBuf::from("t.obj"), placement }));
            assert_eq!(tile(name, "--obj t.obj"), obj(Placement::Scale(1.0)));
            assert_eq!(tile(name, "--obj t.obj --scale 0.5"), obj(Placement::Scale(0.5)));
            assert_eq!(tile(name, "out --fit-slab --obj=t.obj"), obj(Placement::FitSlab));
            let height_map = Some(TileSource::HeightMap { path: PathBuf::from("h.png"), height: 2.5 });
            assert_eq!(tile(name, "--height-map h.png --height 2.5"), Ok(height_map));
            assert_eq!(tile(name, "--quick"), Ok(None));
            // Errors of the words: each names the flags, then the usage.
            for (text, expected) in [
                ("--obj t.obj --height-map h.png", "--obj and --height-map exclude each other"),
                ("--obj t.obj --scale 2 --fit-slab", "--scale and --fit-slab exclude each other"),
                ("--obj", "--obj needs a value PATH"),
                ("--fit-slab=1 --obj t.obj", "--fit-slab takes no value"),
            ] {
                let error = parse(name, text).err().unwrap_or_else(|| panic!("{name} {text} parsed"));
                assert!(error.starts_with(&format!("{name}: {expected}")), "{name} {text}: {error}");
            }
            // Errors of the values.
            for (text, expected) in [
                ("--obj t.obj --scale 0", "--scale 0: expected a positive finite number"),
                ("--obj t.obj --scale=-2", "--scale -2: expected a positive finite number"),
                ("--obj t.obj --scale=NaN", "--scale NaN: expected a positive finite number"),
                ("--obj t.obj --scale inf", "--scale inf: expected a positive finite number"),
                ("--scale 2", "--scale needs --obj PATH"),
                ("--fit-slab", "--fit-slab needs --obj PATH"),
                ("--obj t.obj --height 2", "--height is for --height-map, not --obj"),
                ("--height-map h.png", "--height-map h.png needs --height H (voxels)"),
                ("--height-map h.png --height 0", "--height 0: expected a positive finite number"),
                ("--height-map h.png --height=-1", "--height -1: expected a positive finite number"),
                ("--height 3", "--height needs --height-map PNG"),
            ] {
                let error = tile(name, text).err().unwrap_or_else(|| panic!("{name} {text} parsed"));
                assert!(error.starts_with(&format!("{name}: {expected}\n")), "{name} {text}: {error}");
                assert!(error.ends_with(&usage), "{error}");
            }
        }
        let options = ddm_trace::Options::from_args(&parse("ddm-trace", "--quick --obj t.obj --fit-slab").unwrap());
        let tile = Some(TileSource::Obj { path: PathBuf::from("t.obj"), placement: Placement::FitSlab });
        assert_eq!(options.map(|o| o.tile), Ok(tile.clone()));
        let options = ddm_compression::Options::from_args(&parse("ddm-compression", "--obj t.obj --fit-slab").unwrap());
        assert_eq!(options.map(|o| o.tile), Ok(tile));
    }

    #[test]
    fn repeated_obj_flags_are_kept_in_order_where_allowed() {
        let options =
            impostor_accuracy::Options::from_args(&parse("impostor-accuracy", "--obj a.obj x --obj b.obj").unwrap());
        let expected = impostor_accuracy::Options {
            out: PathBuf::from("x"),
            quick: false,
            objs: vec![PathBuf::from("a.obj"), PathBuf::from("b.obj")],
        };
        assert_eq!(options, expected);
        let error = parse("impostor-cloud", "--obj a.obj --obj b.obj").err().unwrap();
        assert!(error.starts_with("impostor-cloud: --obj given twice\n"), "{error}");
    }

    #[test]
    fn impostor_cloud_parses_and_checks_its_values() {
        let options = impostor_cloud::Options::from_args(&parse("impostor-cloud", "").unwrap()).unwrap();
        let defaults = impostor_cloud::Options {
            out: root("target/impostor-cloud"),
            obj: None,
            grain: "bean",
            n: 8,
            p: 64,
            mode: SamplingMode::Mixed,
            count: 400,
        };
        assert_eq!(options, defaults);
        let text = "--grain rock --n 4 --p 32 --mode spherical --grains 10 pile";
        let options = impostor_cloud::Options::from_args(&parse("impostor-cloud", text).unwrap()).unwrap();
        let expected = impostor_cloud::Options {
            out: PathBuf::from("pile"),
            grain: "rock",
            n: 4,
            p: 32,
            mode: SamplingMode::Spherical,
            count: 10,
            ..defaults
        };
        assert_eq!(options, expected);
        for (text, expected) in [
            ("--n 0", "--n 0: expected a positive integer"),
            ("--grains many", "--grains many: expected a positive integer"),
            ("--mode fuzzy", "--mode fuzzy: expected one of planar, spherical, mixed, mixed-smooth"),
            ("--grain pebble", "--grain pebble: expected one of ball, bean, rock, nut"),
        ] {
            let error = impostor_cloud::Options::from_args(&parse("impostor-cloud", text).unwrap()).err().unwrap();
            assert!(error.starts_with(&format!("impostor-cloud: {expected}\n")), "{error}");
        }
        let error = parse("impostor-cloud", "--obj a.obj --grain ball").err().unwrap();
        assert!(error.starts_with("impostor-cloud: --obj and --grain exclude each other\n"), "{error}");
    }

    #[test]
    fn fig9_ddm_render_and_bench_parse() {
        let options = fig9::Options::from_args(&parse("fig9", "--spectra --height-map h.png out").unwrap());
        let expected = fig9::Options {
            out: PathBuf::from("out"),
            height_map: Some(PathBuf::from("h.png")),
            quick: false,
            spectra: true,
        };
        assert_eq!(options, expected);
        let args = parse("ddm-render", "--quick").unwrap();
        assert!(args.flag("quick") && args.out_dir() == root("target/ddm-render"));
        assert_eq!(parse("abuffer-chart", "").unwrap().out_dir(), root("target/showcase"));
        assert_eq!(parse("bench", "-- ddm --save-baseline main").unwrap().rest(), words("ddm --save-baseline main"));
    }

    /// The README's command table shows exactly the usage lines of [`COMMANDS`].
    #[test]
    fn the_readme_table_shows_every_usage() {
        let readme = std::fs::read_to_string(workspace_root().join("README.md")).unwrap();
        let mut listed: Vec<String> = readme
            .lines()
            .filter_map(|line| line.strip_prefix("| `cargo xtask "))
            .map(|rest| format!("cargo xtask {}", rest.split('`').next().unwrap_or_default().replace("\\|", "|")))
            .collect();
        let mut usages: Vec<String> = COMMANDS.iter().map(Command::usage).collect();
        listed.sort();
        usages.sort();
        assert_eq!(listed, usages);
    }

    /// Every method and steps row of `ddm-trace` has a colour in the charts.
    #[test]
    fn every_ddm_method_has_a_chart_colour() {
        let names: Vec<&str> = ddm_trace::METHOD_COLORS.iter().map(|(name, _)| *name).collect();
        assert_eq!(names.len(), TraceMethod::ALL.len());
        for method in TraceMethod::ALL {
            assert_eq!(names.iter().filter(|n| **n == method.name()).count(), 1, "{}", method.name());
        }
        for (_, exit) in ddm_experiments::steps::EXIT_NAMES {
            assert!(names.contains(&exit));
        }
    }
}

//! The command line's parsing: flags, values and their errors.

use super::*;
use clap::CommandFactory;

fn parse(args: &[&str]) -> Result<Cli, clap::Error> {
    Cli::try_parse_from(std::iter::once("ppm").chain(args.iter().copied()))
}

#[test]
fn definition_is_consistent() {
    Cli::command().debug_assert();
}

#[test]
fn render_is_the_default() {
    let cli = parse(&[
        "scene.yml",
        "-n",
        "3",
        "-o",
        "out.png",
        "--seed",
        "7",
        "-a",
        "pt",
    ])
    .unwrap();
    assert!(cli.command.is_none());
    let r = cli.render;
    assert_eq!(r.scene, Some(PathBuf::from("scene.yml")));
    assert_eq!(r.iterations, Some(3));
    assert_eq!(r.output, Some(PathBuf::from("out.png")));
    assert_eq!(r.settings.seed, Some(7));
    assert_eq!(r.algorithm, Some(Algorithm::Path));
}

/// `-a` takes every name and alias of the algorithm table, for `render` and for
/// `converge`'s list, and nothing else; `--help` lists each name with its description.
#[test]
fn every_algorithm_of_the_table_is_accepted_by_name() {
    for entry in Algorithm::TABLE {
        for name in std::iter::once(&entry.name).chain(entry.aliases) {
            let cli = parse(&["s.yml", "-a", name]).unwrap();
            assert_eq!(cli.render.algorithm, Some(entry.algorithm), "-a {name}");
            let list = format!("vcm,{name}");
            let cli = parse(&[
                "converge",
                "s.yml",
                "--reference",
                "r.exr",
                "--time-limit",
                "1",
                "-a",
                &list,
            ])
            .unwrap();
            let Some(Command::Converge(c)) = cli.command else {
                panic!("expected converge")
            };
            assert_eq!(c.algorithm, [Algorithm::Vcm, entry.algorithm], "-a {list}");
        }
    }
    let err = parse(&["s.yml", "-a", "mlt"]).unwrap_err().to_string();
    assert!(
        err.contains("[possible values: pt, ppm, sppm, vcm, bpt, bpm, lt]"),
        "{err}"
    );
    let help = Cli::command().render_long_help().to_string();
    for entry in Algorithm::TABLE {
        assert!(help.contains(entry.description), "{help}");
    }
}

#[test]
fn radius_is_a_number_or_auto_and_aov_names_an_image() {
    let radius = |v: &str| {
        parse(&["s.yml", "--radius", v])
            .unwrap()
            .render
            .settings
            .radius
    };
    assert_eq!(radius("auto"), Some(Radius::Auto));
    assert_eq!(radius("footprint"), Some(Radius::Auto));
    assert_eq!(radius("photons"), Some(Radius::Photons));
    assert_eq!(radius("0.5"), Some(Radius::World(0.5)));
    let e = parse(&["s.yml", "--radius", "knn"])
        .unwrap_err()
        .to_string();
    assert!(e.contains("`photons`, `footprint` or `auto`"), "{e}");
    assert_eq!(parse(&["s.yml"]).unwrap().render.settings.radius, None);
    let r = parse(&["s.yml", "--aov", "radius"]).unwrap().render;
    assert_eq!(r.aov, [AovArg::Radius]);
    let r = parse(&["s.yml", "--aov", "radius", "--aov", "photons"])
        .unwrap()
        .render;
    assert_eq!(r.aov, [AovArg::Radius, AovArg::Photons]);
    assert!(parse(&["s.yml", "--aov", "depth"]).is_err());
}

#[test]
fn explicit_render_subcommand() {
    let cli = parse(&[
        "render",
        "scene.yml",
        "--photons",
        "1000",
        "--direct",
        "sampled",
    ])
    .unwrap();
    let Some(Command::Render(r)) = cli.command else {
        panic!("expected render")
    };
    assert_eq!(r.scene, Some(PathBuf::from("scene.yml")));
    assert_eq!(r.settings.photons, Some(1000));
    assert_eq!(r.settings.direct, Some(DirectArg::Sampled));
    // Without -a: the scene's render.algorithm, else ppm.
    assert_eq!(r.algorithm, None);
    assert_eq!(resolve_algorithm(None, None), Algorithm::Ppm);
    assert_eq!(
        resolve_algorithm(None, Some(Algorithm::Vcm)),
        Algorithm::Vcm
    );
    assert_eq!(
        resolve_algorithm(Some(Algorithm::Path), Some(Algorithm::Vcm)),
        Algorithm::Path
    );
}

#[test]
fn compare_subcommand() {
    let cli = parse(&["compare", "a.exr", "b.exr"]).unwrap();
    let Some(Command::Compare(c)) = cli.command else {
        panic!("expected compare")
    };
    assert_eq!((c.a, c.b), (PathBuf::from("a.exr"), PathBuf::from("b.exr")));
    assert!(parse(&["compare", "a.exr"]).is_err());
}

#[test]
fn converge_subcommand() {
    let cli = parse(&[
        "converge",
        "s.yml",
        "--reference",
        "r.exr",
        "--time-limit",
        "2",
        "-a",
        "pt,ppm",
        "--seeds",
        "3",
        "--out",
        "plots",
    ])
    .unwrap();
    let Some(Command::Converge(c)) = cli.command else {
        panic!("expected converge")
    };
    assert_eq!(c.algorithm, [Algorithm::Path, Algorithm::Ppm]);
    assert_eq!((c.seeds, c.time_limit), (3, 2.0));
    assert_eq!(c.out, PathBuf::from("plots"));
    let c = match parse(&[
        "converge",
        "s.yml",
        "--reference",
        "r.exr",
        "--time-limit",
        "1",
    ])
    .unwrap()
    .command
    {
        Some(Command::Converge(c)) => c,
        _ => panic!(),
    };
    assert_eq!(c.algorithm, [Algorithm::Path, Algorithm::Ppm]);
    assert!(
        parse(&["converge", "s.yml", "--time-limit", "1"]).is_err(),
        "reference is required"
    );
}

#[test]
fn conventional_flags() {
    let r = parse(&["s.yml", "--spp", "16", "-t", "3", "-q"])
        .unwrap()
        .render;
    assert_eq!((r.spp, r.iterations), (Some(16), None));
    assert_eq!(r.settings.threads, Some(3), "-t is threads (Mitsuba)");
    assert!(r.quiet && !r.verbose);
    assert!(parse(&["s.yml", "-v"]).unwrap().render.verbose);
    let r = parse(&[
        "s.yml",
        "--cropwindow",
        "0.25",
        "0.5",
        "0",
        "1",
        "--display-server",
        "localhost:14158",
    ])
    .unwrap()
    .render;
    assert_eq!(r.cropwindow, Some(vec![0.25, 0.5, 0.0, 1.0]));
    assert_eq!(r.display_server.as_deref(), Some("localhost:14158"));
    let r = parse(&["s.yml", "--pixelbounds", "1", "5", "2", "6"])
        .unwrap()
        .render;
    assert_eq!(r.pixelbounds, Some(vec![1, 5, 2, 6]));
    let Some(Command::Info(i)) = parse(&["info", "a.exr"]).unwrap().command else {
        panic!("expected info")
    };
    assert_eq!(i.image, PathBuf::from("a.exr"));
}

#[test]
fn bad_values_are_usage_errors() {
    for bad in [
        &["s.yml", "-n", "0"][..],
        &["s.yml", "-n", "many"],
        &["s.yml", "--width", "0"],
        &["s.yml", "--width", "100000"],
        &["s.yml", "--radius", "-1"],
        &["s.yml", "--radius", "nan"],
        &["s.yml", "--radius", "Auto"],
        &["s.yml", "--radius", "0"],
        &["s.yml", "--alpha", "1.5"],
        &["s.yml", "--alpha", "0"],
        &["s.yml", "--threads", "0"],
        &["s.yml", "--time-limit", "-3"],
        &["s.yml", "--time-limit", "inf"],
        &["s.yml", "-a", "bdpt"],
        &["s.yml", "--error-log", "e.csv"], // needs --reference
        &["s.yml", "--frobnicate"],
        &["s.yml", "--spp", "4", "-n", "4"],
        &["s.yml", "--spp", "0"],
        &["s.yml", "-q", "-v"],
        &["s.yml", "--cropwindow", "0", "1", "0"],
        &[
            "s.yml",
            "--cropwindow",
            "0",
            "1",
            "0",
            "1",
            "--pixelbounds",
            "0",
            "1",
            "0",
            "1",
        ],
        &["s.yml", "--pixelbounds", "0", "1", "0", "-1"],
        &[
            "s.yml",
            "--cropwindow",
            "0",
            "1",
            "0",
            "1",
            "--reference",
            "r.exr",
        ],
        &[], // no scene
    ] {
        let err = parse(bad).expect_err(&format!("{bad:?} should be rejected"));
        assert_ne!(err.kind(), clap::error::ErrorKind::DisplayHelp);
    }
}

//! The command line is consistent: one spelling of the output option
//! (`-o/--output`, `--out` as an alias) on every subcommand that writes a file, every
//! default in `--help`, the estimator names and the input units in `estimate --help`, and
//! no rustdoc link syntax in any help text.
use clap::CommandFactory;

mod common;
use common::{pendtilt, s, stderr};
use pendtilt::bank::planar::REGISTRY;
use pendtilt::cli::Cli;
use pendtilt::sim::planar::{Scenario, SCENARIO_NAMES};

fn help(args: &[&str]) -> String {
    let o = pendtilt(args);
    assert!(o.status.success(), "{args:?}: {}", stderr(&o));
    String::from_utf8(o.stdout).unwrap()
}

const SUBCOMMANDS: [&str; 8] = [
    "estimate",
    "filter",
    "simulate",
    "fit",
    "report",
    "reproduce",
    "stream",
    "tune",
];

#[test]
fn no_help_text_has_rustdoc_link_syntax() {
    for c in SUBCOMMANDS {
        for flag in ["-h", "--help"] {
            let h = help(&[c, flag]);
            assert!(!h.contains("[`") && !h.contains("`]"), "{c} {flag}:\n{h}");
            // rustdoc's escaped brackets: `\[s\]` reached `--score-from`'s help.
            assert!(!h.contains("\\["), "{c} {flag}:\n{h}");
        }
    }
    let h = help(&["--help"]);
    assert!(!h.contains("[`"), "{h}");
}

/// Every option that takes a value and is not required says its default: clap's
/// `[default: ..]`, or the word "default" in its help ("Default: the rig file's", "No
/// default: give it or --config").
#[test]
fn every_optional_value_says_its_default() {
    let mut cmd = Cli::command();
    cmd.build();
    let mut missing = Vec::new();
    for sub in cmd.get_subcommands() {
        for arg in sub.get_arguments() {
            let takes_value = arg.get_action().takes_values();
            if !takes_value || arg.is_required_set() || arg.is_positional() {
                continue;
            }
            let text = format!(
                "{} {}",
                arg.get_help().map(|h| h.to_string()).unwrap_or_default(),
                arg.get_long_help()
                    .map(|h| h.to_string())
                    .unwrap_or_default()
            );
            let shown = !arg.get_default_values().is_empty() && !arg.is_hide_default_value_set();
            if !shown && !text.to_lowercase().contains("default") {
                missing.push(format!("{} --{}", sub.get_name(), arg.get_id()));
            }
        }
    }
    assert!(missing.is_empty(), "no default in the help of: {missing:?}");
}

#[test]
fn estimate_help_lists_every_estimator_and_the_input_units() {
    for c in ["estimate", "stream"] {
        let h = help(&[c, "--help"]);
        for e in REGISTRY {
            assert!(
                h.contains(&format!("  {}", e.name)),
                "{c}: {} missing:\n{h}",
                e.name
            );
        }
        for unit in [
            "t [s]",
            "phi [rad]",
            "gyro [rad/s]",
            "ax, ay [m/s^2]",
            "theta [rad]",
            // What happens to a reading beyond, at and without a full scale.
            "flagged implausible",
            "kept and flagged saturated",
            "ekf and ukf do not use it",
            "a clip is found in the readings",
        ] {
            assert!(h.contains(unit), "{c}: {unit} missing:\n{h}");
        }
    }
}

#[test]
fn simulate_help_gives_each_scenarios_duration() {
    let h = help(&["simulate", "--help"]);
    let line = h
        .lines()
        .find(|l| l.contains("--duration"))
        .expect("a --duration line");
    for n in SCENARIO_NAMES {
        let d = Scenario::named(n).unwrap().duration;
        assert!(line.contains(&format!("{n} {d}")), "{n} {d}: {line}");
    }
}

/// `-o`, `--output` and `--out` write the same file on every subcommand that writes one.
#[test]
fn one_output_option_spelling_with_out_as_alias() {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("run.csv");
    let o = pendtilt(&[
        "simulate",
        "--scenario",
        "sigmoid",
        // 3 s, so that the step (at 2 s) is in the log: `fit`'s default output-error cost
        // rightly calls a motionless log unidentifiable.
        "--duration",
        "3",
        "--out",
        s(&log),
        "-q",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(log.exists() && dir.path().join("run.rig.toml").exists());
    for c in ["estimate", "filter", "fit", "report"] {
        let mut bodies = Vec::new();
        for (i, spelling) in ["-o", "--output", "--out"].iter().enumerate() {
            let out = dir.path().join(format!("{c}{i}"));
            let mut args = vec![c, s(&log), *spelling, s(&out)];
            if c != "filter" {
                args.push("-q");
            }
            let o = pendtilt(&args);
            assert!(o.status.success(), "{c} {spelling}: {}", stderr(&o));
            let file = if c == "report" {
                out.join("report.md")
            } else {
                out
            };
            bodies.push(std::fs::read(file).unwrap());
        }
        // The three runs wrote the same bytes (report.md has no timings).
        assert!(bodies.windows(2).all(|w| w[0] == w[1]), "{c}");
    }
    for c in [
        "estimate",
        "filter",
        "simulate",
        "fit",
        "report",
        "reproduce",
    ] {
        let h = help(&[c, "--help"]);
        assert!(h.contains("-o, --output <"), "{c}:\n{h}");
        assert!(h.contains("[alias: --out]"), "{c}:\n{h}");
    }
}

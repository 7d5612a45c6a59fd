//! The conventions of a Unix tool: shell completions and man pages generated from the
//! command line's own definition, `--version` with the commit, and a pipe whose reader
//! stops early ending the run quietly.
use std::io::{BufRead, BufReader};
use std::process::Stdio;

mod common;
use common::{bin, pendtilt, s, stderr};

const SUBCOMMANDS: [&str; 11] = [
    "estimate",
    "filter",
    "simulate",
    "fit",
    "report",
    "replay",
    "reproduce",
    "stream",
    "tune",
    "completions",
    "man",
];

fn stdout_of(args: &[&str]) -> String {
    let o = pendtilt(args);
    assert!(o.status.success(), "{args:?}: {}", stderr(&o));
    String::from_utf8(o.stdout).unwrap()
}

#[test]
fn completions_know_every_subcommand_and_option() {
    let bash = stdout_of(&["completions", "bash"]);
    assert!(bash.contains("_pendtilt()"), "{bash}");
    for c in SUBCOMMANDS {
        assert!(bash.contains(c), "bash completion lacks {c}");
    }
    // An option of one subcommand, and the values of an enumerated one.
    assert!(bash.contains("--vibration") && bash.contains("--time-unit"));
    let zsh = stdout_of(&["completions", "zsh"]);
    assert!(
        zsh.starts_with("#compdef pendtilt"),
        "{}",
        &zsh[..40.min(zsh.len())]
    );
    let fish = stdout_of(&["completions", "fish"]);
    assert!(fish.contains("complete -c pendtilt"), "{fish}");
    let o = pendtilt(&["completions", "tcsh"]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("possible values"), "{}", stderr(&o));
}

#[test]
fn the_man_pages_describe_every_subcommand() {
    let page = stdout_of(&["man"]);
    assert!(
        page.contains(".TH pendtilt 1"),
        "{}",
        &page[..200.min(page.len())]
    );
    for c in SUBCOMMANDS {
        assert!(page.contains(c), "pendtilt(1) lacks {c}");
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("man");
    let o = pendtilt(&["man", "-o", s(&out)]);
    assert!(o.status.success(), "{}", stderr(&o));
    for c in ["estimate", "replay", "tune"] {
        let p = std::fs::read_to_string(out.join(format!("pendtilt-{c}.1"))).unwrap();
        assert!(p.contains(&format!("pendtilt\\-{c}")), "{p}");
    }
    let estimate = std::fs::read_to_string(out.join("pendtilt-estimate.1")).unwrap();
    assert!(estimate.contains("\\-\\-params"), "{estimate}");
}

#[test]
fn the_version_names_the_commit() {
    let v = stdout_of(&["--version"]);
    let want = format!("pendtilt {} (", env!("CARGO_PKG_VERSION"));
    assert!(v.starts_with(&want), "{v}");
    let commit = v
        .trim_end()
        .trim_end_matches(')')
        .rsplit('(')
        .next()
        .unwrap();
    assert!(
        commit == "unknown" || commit.trim_end_matches("-dirty").len() >= 7,
        "{v}"
    );
}

/// `pendtilt simulate ... -o - | head -1`: the reader goes after one line; the run ends
/// with success and says nothing (it used to end "error: ... Broken pipe", exit 1).
#[test]
fn a_reader_that_stops_early_ends_the_run_quietly() {
    for args in [
        &[
            "simulate",
            "--scenario",
            "scooter",
            "--duration",
            "30",
            "-q",
            "-o",
            "-",
        ][..],
        &[
            "simulate",
            "--scenario",
            "scooter3d",
            "--duration",
            "30",
            "-q",
            "-o",
            "-",
        ][..],
    ] {
        let mut child = bin()
            .args(args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let mut first = String::new();
        BufReader::new(child.stdout.take().unwrap())
            .read_line(&mut first)
            .unwrap();
        assert!(first.starts_with("t,"), "{first}");
        // The reader is dropped here: the pipe closes with rows still to come.
        let o = child.wait_with_output().unwrap();
        assert!(o.status.success(), "{args:?}: {}", stderr(&o));
        assert!(!stderr(&o).contains("error"), "{args:?}: {}", stderr(&o));
    }
}

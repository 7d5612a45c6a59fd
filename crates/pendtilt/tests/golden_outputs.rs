//! Guards refactors: the SHA-256 of `estimate`'s output (every estimator, f64,
//! with flags) on a fixed set of simulated logs, and of `reproduce`'s metrics JSON, must
//! equal the digests recorded in `tests/golden/sha256.txt`.
//!
//! A deliberate change of an output (a bug fixed) re-records them with
//! `PENDTILT_BLESS=1 cargo test --release -p pendtilt --test golden_outputs`; the commit
//! says which output changed and why.
mod common;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use common::{pendtilt, s, stderr};
use sha2::{Digest, Sha256};

const RECORD: &str = "tests/golden/sha256.txt";

/// (name, simulate arguments): short logs of every scenario, fixed seeds.
const LOGS: [(&str, &[&str]); 5] = [
    (
        "scooter",
        &["--scenario", "scooter", "--duration", "12", "--seed", "3"],
    ),
    ("sigmoid", &["--scenario", "sigmoid", "--seed", "5"]),
    ("step", &["--scenario", "step", "--seed", "7"]),
    (
        "chirp",
        &["--scenario", "chirp", "--duration", "10", "--seed", "11"],
    ),
    (
        "sine_offset",
        &[
            "--scenario",
            "sine",
            "--duration",
            "6",
            "--pivot-offset",
            "0.05",
        ],
    ),
];

fn digest(path: &Path) -> String {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    format!("{:x}", Sha256::digest(bytes))
}

fn record_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(RECORD)
}

fn recorded() -> BTreeMap<String, String> {
    let text = std::fs::read_to_string(record_path()).unwrap_or_default();
    text.lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
        .filter_map(|l| l.split_once("  "))
        .map(|(h, n)| (n.to_string(), h.to_string()))
        .collect()
}

/// The digest of `estimate log --params rig --flags` written to `est`; `what` names the
/// run when it fails.
fn estimate_digest(log: &Path, rig: &Path, est: &Path, what: &str) -> String {
    let o = pendtilt(&[
        "estimate",
        s(log),
        "--params",
        s(rig),
        "--flags",
        "-q",
        "-o",
        s(est),
    ]);
    assert!(o.status.success(), "{what}: {}", stderr(&o));
    digest(est)
}

/// `rig` with the ekf's adaptation off, as `dir/scooter_fixed.rig.toml`.
fn adaptation_off(rig: &Path, dir: &Path) -> PathBuf {
    let text = std::fs::read_to_string(rig).unwrap();
    let fixed = dir.join("scooter_fixed.rig.toml");
    let text = if text.contains("[ekf]") {
        text.replace("[ekf]", "[ekf]\nadapt = false")
    } else {
        format!("{text}\n[ekf]\nadapt = false\n")
    };
    std::fs::write(&fixed, text).unwrap();
    fixed
}

/// The digests of `estimate` on each of [`LOGS`] simulated in `dir`, and on the scooter's
/// with the ekf's adaptation off, into `now`.
fn estimate_digests(dir: &Path, now: &mut BTreeMap<String, String>) {
    for (name, args) in LOGS {
        let log = dir.join(format!("{name}.csv"));
        let mut a = vec!["simulate", "-o", s(&log)];
        a.extend_from_slice(args);
        let o = pendtilt(&a);
        assert!(o.status.success(), "simulate {name}: {}", stderr(&o));
        let rig = dir.join(format!("{name}.rig.toml"));
        let est = dir.join(format!("{name}.est.csv"));
        let what = format!("estimate {name}");
        now.insert(
            format!("estimate/{name}"),
            estimate_digest(&log, &rig, &est, &what),
        );
        if name == "scooter" {
            // The ekf's adaptation off: the outputs from before it, to the bit (the digest
            // equals estimate/scooter's as recorded before the adaptation).
            let fixed = adaptation_off(&rig, dir);
            let est = dir.join("scooter_fixed.est.csv");
            let what = "estimate scooter, adapt off";
            now.insert(
                "estimate/scooter_adapt_off".to_string(),
                estimate_digest(&log, &fixed, &est, what),
            );
        }
    }
}

/// The digests of each part's `report.json` that `reproduce` writes under `dir`, into
/// `now`.
fn reproduce_digests(dir: &Path, now: &mut BTreeMap<String, String>) {
    let rep = dir.join("reproduce");
    let o = pendtilt(&["reproduce", "--out", s(&rep)]);
    assert!(o.status.success(), "reproduce: {}", stderr(&o));
    for part in [
        "scooter",
        "sigmoid",
        "still3d",
        "scooter3d",
        "ship3d",
        "ride3d",
    ] {
        now.insert(
            format!("reproduce/{part}/report.json"),
            digest(&rep.join(part).join("report.json")),
        );
    }
}

/// Records `now` as the digests to keep (`PENDTILT_BLESS=1`).
fn bless(now: &BTreeMap<String, String>) {
    let mut text = String::from(
        "# SHA-256 of outputs that refactors must not change (tests/golden_outputs.rs)\n",
    );
    for (n, h) in now {
        text.push_str(&format!("{h}  {n}\n"));
    }
    std::fs::write(record_path(), text).unwrap();
}

#[test]
fn outputs_equal_the_recorded_digests() {
    let dir = tempfile::tempdir().unwrap();
    let mut now = BTreeMap::new();
    estimate_digests(dir.path(), &mut now);
    reproduce_digests(dir.path(), &mut now);
    if std::env::var_os("PENDTILT_BLESS").is_some() {
        bless(&now);
        return;
    }
    let old = recorded();
    let changed: Vec<String> = now
        .iter()
        .filter(|(n, h)| old.get(*n) != Some(*h))
        .map(|(n, h)| format!("{n}: now {h}, recorded {:?}", old.get(n)))
        .collect();
    assert!(
        changed.is_empty() && old.len() == now.len(),
        "outputs changed (re-record with PENDTILT_BLESS=1 only if deliberate):\n{}",
        changed.join("\n")
    );
}

//! `pendtilt rig --template`: a rig file with every default that the commands read back as
//! the defaults (the same estimates as no rig file at all).
mod common;
use common::{pendtilt, s, stderr};

#[test]
fn a_template_gives_the_estimates_of_the_defaults() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for (kind, scenario) in [("planar", "scooter"), ("3d", "scooter3d")] {
        let rig = d.join(format!("{kind}.toml"));
        let o = pendtilt(&["rig", "--template", kind, "-o", s(&rig)]);
        assert!(o.status.success(), "{}", stderr(&o));
        let text = std::fs::read_to_string(&rig).unwrap();
        assert!(text.starts_with("# pendtilt"), "{text}");
        let log = d.join(format!("{kind}.csv"));
        let o = pendtilt(&[
            "simulate",
            "--scenario",
            scenario,
            "--duration",
            "3",
            "-q",
            "--rig-out",
            s(&d.join("unused.toml")),
            "-o",
            s(&log),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        let (a, b) = (d.join("a.csv"), d.join("b.csv"));
        let o = pendtilt(&["estimate", s(&log), "--params", s(&rig), "-q", "-o", s(&a)]);
        assert!(o.status.success(), "{kind}: {}", stderr(&o));
        let o = pendtilt(&["estimate", s(&log), "-q", "-o", s(&b)]);
        assert!(o.status.success(), "{kind}: {}", stderr(&o));
        assert_eq!(
            std::fs::read(&a).unwrap(),
            std::fs::read(&b).unwrap(),
            "{kind}"
        );
    }
    // To standard output by default.
    let o = pendtilt(&["rig", "--template", "3d"]);
    assert!(String::from_utf8_lossy(&o.stdout).contains("[pendulum3d]\nmass = 0.05"));
}

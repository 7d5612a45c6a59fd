//! Shared by the cli_estimate tests: a small simulated log written under any names, the
//! written estimates read back, temporary paths.
use pendtilt::sim::planar::{simulate, Scenario};
use std::path::Path;

/// Writes a 3 s scooter log as `t,phi,gyro,ax,ay,theta` (or renamed / in degrees).
pub fn write_log(path: &Path, names: [&str; 6], degrees: bool, drop_gyro: bool) {
    let mut sc = Scenario::named("scooter").unwrap();
    sc.duration = 3.0;
    let rows = simulate(&sc, 7).unwrap();
    let k = if degrees {
        180.0 / std::f64::consts::PI
    } else {
        1.0
    };
    let mut text = String::new();
    let cols: Vec<&str> = names
        .iter()
        .enumerate()
        .filter(|(i, _)| !(drop_gyro && *i == 2))
        .map(|(_, n)| *n)
        .collect();
    text.push_str(&cols.join(","));
    text.push('\n');
    for r in &rows {
        let mut v = vec![r.t, r.phi * k, r.gyro * k, r.ax, r.ay, r.theta * k];
        if drop_gyro {
            v.remove(2);
        }
        let s: Vec<String> = v.iter().map(|x| format!("{x:?}")).collect();
        text.push_str(&s.join(","));
        text.push('\n');
    }
    std::fs::write(path, text).unwrap();
}

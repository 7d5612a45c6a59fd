//! The BROAD benchmark: every trial of a BROAD `data_mat` folder replayed through MODEL.md
//! 7.6's pendulum (`pendtilt replay` at its defaults) and every 3-D estimator at its
//! defaults scored from the first movement on (MODEL.md 7.9, 7.10), beside the reference
//! filters' figures in `docs/broad/reference.csv` (`tools/broad_reference.py`).
//!
//! ```sh
//! cargo run --release -p pendtilt --example broad -- BROAD/data_mat [OUT_DIR]
//! ```
//!
//! Writes `OUT_DIR/benchmark.csv` (one row per trial and estimator) and
//! `OUT_DIR/benchmark.md` (the tables); OUT_DIR defaults to `docs/broad`.
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::Context;
use pendtilt::bank3d::rig::Pendulum3dConfig;
use pendtilt::bank3d::Settings3d;
use pendtilt::replay::benchmark::{score, Score, TILT_LIMIT_DEG};
use pendtilt::replay::source::ImuOptions;
use pendtilt::replay::{replay, Recording, ReplaySettings};
use pendtilt::sim3d::Mounting;

/// The reference filters' RMS per trial and filter, from `reference.csv`.
fn reference(dir: &Path) -> BTreeMap<(String, String), [f64; 4]> {
    let mut out = BTreeMap::new();
    let Ok(text) = std::fs::read_to_string(dir.join("reference.csv")) else {
        return out;
    };
    for line in text.lines().skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        if f.len() >= 6 {
            let v = |i: usize| f[i].parse::<f64>().unwrap_or(f64::NAN);
            out.insert(
                (f[0].to_string(), f[1].to_string()),
                [v(2), v(3), v(4), v(5)],
            );
        }
    }
    out
}

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(data) = args.first().map(PathBuf::from) else {
        anyhow::bail!("usage: broad BROAD/data_mat [OUT_DIR]");
    };
    let out_dir = args
        .get(1)
        .map_or(PathBuf::from("docs/broad"), PathBuf::from);
    let mut files: Vec<PathBuf> = std::fs::read_dir(&data)
        .with_context(|| format!("cannot read {}", data.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "mat"))
        .collect();
    files.sort();
    let refs = reference(&out_dir);
    let mut csv =
        String::from("trial,estimator,rms_deg,max_deg,rms60_deg,max60_deg,rows,rows60,t_max_s\n");
    let mut table: Vec<(String, Vec<Score>)> = Vec::new();
    for f in &files {
        let trial = f
            .file_stem()
            .unwrap_or_default()
            .to_string_lossy()
            .to_string();
        let rec = Recording::open(f, &ImuOptions::default())?;
        let r = replay(&rec, &ReplaySettings::default())?;
        let params = Pendulum3dConfig::Physical(r.pendulum).params();
        let settings = Settings3d::new(params, Mounting::default(), None);
        let (scores, _) = score(&rec, &r, &settings, None).map_err(anyhow::Error::msg)?;
        for s in &scores {
            writeln!(
                csv,
                "{},{},{:.4},{:.4},{:.4},{:.4},{},{},{:.3}",
                &trial[..2],
                s.estimator,
                s.rms,
                s.max,
                s.rms_low_tilt,
                s.max_low_tilt,
                s.rows[0],
                s.rows[1],
                s.t_max
            )?;
        }
        let e = |n: &str| {
            scores
                .iter()
                .find(|s| s.estimator == n)
                .map_or(f64::NAN, |s| s.rms)
        };
        let vqf_ref = refs
            .get(&(trial[..2].to_string(), "vqf".to_string()))
            .map_or(f64::NAN, |v| v[0]);
        eprintln!(
            "{trial}: ekf3d {:.2}, ukf3d {:.2}, vqf {:.2} (reference {:.2}) deg RMS",
            e("ekf3d"),
            e("ukf3d"),
            e("vqf"),
            vqf_ref
        );
        table.push((trial, scores));
    }
    std::fs::create_dir_all(&out_dir)?;
    std::fs::write(out_dir.join("benchmark.csv"), &csv)?;
    let names: Vec<String> = table
        .first()
        .map(|(_, s)| s.iter().map(|s| s.estimator.clone()).collect())
        .unwrap_or_default();
    let mut md = String::new();
    for (title, pick) in [
        ("RMS (max) inclination error [deg], movement phase", 0),
        ("RMS (max) [deg] where the true tilt is under 60 deg", 1),
    ] {
        writeln!(md, "### {title}\n")?;
        writeln!(md, "| trial | {} | VQF reference |", names.join(" | "))?;
        writeln!(md, "|---|{}---|", "---|".repeat(names.len()))?;
        for (trial, scores) in &table {
            let cells: Vec<String> = scores
                .iter()
                .map(|s| {
                    let (rms, max) = if pick == 0 {
                        (s.rms, s.max)
                    } else {
                        (s.rms_low_tilt, s.max_low_tilt)
                    };
                    format!("{rms:.2} ({max:.0})")
                })
                .collect();
            let r = refs.get(&(trial[..2].to_string(), "vqf".to_string()));
            let rv = r.map_or("-".into(), |v| {
                let (rms, max) = if pick == 0 {
                    (v[0], v[1])
                } else {
                    (v[2], v[3])
                };
                format!("{rms:.2} ({max:.0})")
            });
            writeln!(md, "| {} | {} | {rv} |", &trial[..2], cells.join(" | "))?;
        }
        writeln!(md)?;
    }
    let _ = TILT_LIMIT_DEG;
    std::fs::write(out_dir.join("benchmark.md"), &md)?;
    eprintln!("wrote {}/benchmark.csv and benchmark.md", out_dir.display());
    Ok(())
}

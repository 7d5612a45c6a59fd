//! The BROAD benchmark: every trial of a BROAD `data_mat` folder replayed through MODEL.md
//! 7.6's pendulum (`pendtilt replay` at its defaults) and every 3-D estimator at its
//! defaults scored from the first movement on (MODEL.md 7.9, 7.10), beside the reference
//! filters' figures in `docs/broad/reference.csv` (`tools/broad_reference.py`).
//!
//! ```sh
//! cargo run --release -p pendtilt --example broad -- BROAD/data_mat [OUT_DIR]
//!     [--vibration scooter3d] [--only ekf3d,vqf] [--trials 02,10]
//! ```
//!
//! Writes `OUT_DIR/benchmark.csv` (one row per trial and estimator), `OUT_DIR/benchmark.md`
//! (the tables) and `OUT_DIR/benchmark.svg` (each trial's RMS); with `--vibration NAME`,
//! the replays have that scenario's vibration added (`replay --vibration`) and the files
//! are `benchmark_NAME.*`. OUT_DIR defaults to `docs/broad`. `--trials` takes a subset;
//! with `--only` (a quick look) nothing is written.
//!
//! As recorded, it also checks the peers against the reference filters and writes
//! `OUT_DIR/peers_check.csv`: the `vqf` column's RMS beside the reference VQF's, and
//! Madgwick and Mahony run through the same wrapper at the `ahrs` Python package's default
//! gains (the columns `madgwick3d` and `mahony3d` have pendtilt's) beside the reference's.
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::Context;
use pendtilt::bank::spatial::rig::Pendulum3dConfig;
use pendtilt::bank::spatial::Settings3d;
use pendtilt::peers::spatial::{madgwick3d, mahony3d, AHRS_PY_MADGWICK_BETA, AHRS_PY_MAHONY_GAINS};
use pendtilt::replay::benchmark::{score, score_one, Score, TILT_LIMIT_DEG};
use pendtilt::replay::source::ImuOptions;
use pendtilt::replay::{replay_with, AddedVibration, Recording, Replay, ReplaySettings};
use pendtilt::report::figures::{plot_curves, Curve, FigureSpec};
use pendtilt::report::palette::Palette;
use pendtilt::sim::spatial::Mounting;

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

/// The command line: the data folder, the output folder and the options.
struct Args {
    data: PathBuf,
    out_dir: PathBuf,
    only: Option<Vec<String>>,
    trials: Option<Vec<String>>,
    vibration: Option<String>,
}

/// The reference filters' RMS per (trial, filter): RMS, max, and both under 60 deg.
type References = BTreeMap<(String, String), [f64; 4]>;

/// One trial's scores and its count of clipped rows.
type TrialScores = (String, Vec<Score>, usize);

/// What the trials add up to: the CSV rows, the table, and the peers' check against the
/// reference filters with the largest difference per peer.
struct Tally {
    csv: String,
    table: Vec<TrialScores>,
    check: String,
    worst: BTreeMap<&'static str, (f64, String)>,
}

fn main() -> anyhow::Result<()> {
    let args = parse_args()?;
    let files = trial_files(&args)?;
    let refs = reference(&args.out_dir);
    let mut tally = Tally {
        csv: String::from(
            "trial,estimator,rms_deg,max_deg,rms60_deg,max60_deg,rows,rows60,t_max_s\n",
        ),
        table: Vec::new(),
        check: String::from("trial,filter,rms_deg,reference_rms_deg,difference_deg\n"),
        worst: BTreeMap::new(),
    };
    for f in &files {
        run_trial(f, &args, &refs, &mut tally)?;
    }
    for (name, (d, trial)) in &tally.worst {
        eprintln!(
            "{name}: largest |RMS - reference RMS| {:.4} deg (trial {trial})",
            d.abs()
        );
    }
    if args.only.is_some() {
        return Ok(());
    }
    write_outputs(&args, &refs, &tally)
}

/// Reads the command line (see the module documentation).
fn parse_args() -> anyhow::Result<Args> {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let mut option = |name: &str| -> Option<Vec<String>> {
        let i = args.iter().position(|a| a == name)?;
        let v = args.get(i + 1).cloned().unwrap_or_default();
        args.drain(i..(i + 2).min(args.len()));
        Some(v.split(',').map(String::from).collect())
    };
    let only = option("--only");
    let trials = option("--trials");
    let vibration = option("--vibration").map(|v| v.join(","));
    let Some(data) = args.first().map(PathBuf::from) else {
        anyhow::bail!("usage: broad BROAD/data_mat [OUT_DIR]");
    };
    let out_dir = args
        .get(1)
        .map_or(PathBuf::from("docs/broad"), PathBuf::from);
    Ok(Args {
        data,
        out_dir,
        only,
        trials,
        vibration,
    })
}

/// The trials' `.mat` files in the data folder (those `--trials` picks), sorted.
fn trial_files(args: &Args) -> anyhow::Result<Vec<PathBuf>> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(&args.data)
        .with_context(|| format!("cannot read {}", args.data.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "mat"))
        .filter(|p| {
            let stem = p.file_stem().unwrap_or_default().to_string_lossy();
            args.trials
                .as_ref()
                .is_none_or(|t| t.iter().any(|t| stem.starts_with(t.as_str())))
        })
        .collect();
    files.sort();
    Ok(files)
}

/// Replays trial `f` and scores every estimator on it: its CSV rows, the peers' check
/// (as recorded), a line on standard error, and its row of the table.
fn run_trial(f: &Path, args: &Args, refs: &References, tally: &mut Tally) -> anyhow::Result<()> {
    let trial = f
        .file_stem()
        .unwrap_or_default()
        .to_string_lossy()
        .to_string();
    let rec = Recording::open(f, &ImuOptions::default())?;
    let added = match &args.vibration {
        Some(name) => Some(AddedVibration::of_scenario(name, 1)?),
        None => None,
    };
    let r = replay_with(&rec, &ReplaySettings::default(), added.as_ref())?;
    let clipped = r.report.vibration.map_or(0, |v| v.clipped_rows);
    let params = Pendulum3dConfig::Physical(r.pendulum).params();
    let settings = Settings3d::new(params, Mounting::default(), None);
    let (scores, _) =
        score(&rec, &r, &settings, args.only.as_deref()).map_err(anyhow::Error::msg)?;
    write_scores(&mut tally.csv, &trial, &scores)?;
    let e = |n: &str| {
        scores
            .iter()
            .find(|s| s.estimator == n)
            .map_or(f64::NAN, |s| s.rms)
    };
    let m = |n: &str| {
        scores
            .iter()
            .find(|s| s.estimator == n)
            .map_or(f64::NAN, |s| s.max)
    };
    if args.vibration.is_none() {
        check_peers(&rec, &r, &trial, e("vqf"), refs, tally)?;
    }
    if args.vibration.is_some() {
        eprint!("[{clipped} rows clipped] ");
    }
    let vqf_ref = refs
        .get(&(trial[..2].to_string(), "vqf".to_string()))
        .map_or([f64::NAN; 4], |v| *v);
    eprintln!(
        "{trial:<36} ekf3d {:6.2} ({:5.1}) ukf3d {:6.2} imu3d {:6.2} ({:5.1}) vqf {:5.2} (reference {:.2} ({:.1})) deg RMS (max)",
        e("ekf3d"),
        m("ekf3d"),
        e("ukf3d"),
        e("imu3d"),
        m("imu3d"),
        e("vqf"),
        vqf_ref[0],
        vqf_ref[1],
    );
    tally.table.push((trial, scores, clipped));
    Ok(())
}

/// One CSV row per estimator of the trial.
fn write_scores(csv: &mut String, trial: &str, scores: &[Score]) -> std::fmt::Result {
    for s in scores {
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
    Ok(())
}

/// The peers against the reference filters, at the reference's parameters: `vqf`
/// (its RMS `vqf`) as scored, Madgwick and Mahony at the `ahrs` package's gains.
fn check_peers(
    rec: &Recording,
    r: &Replay,
    trial: &str,
    vqf: f64,
    refs: &References,
    tally: &mut Tally,
) -> anyhow::Result<()> {
    let mut madgwick = madgwick3d(AHRS_PY_MADGWICK_BETA);
    let mut mahony = mahony3d(AHRS_PY_MAHONY_GAINS[0], AHRS_PY_MAHONY_GAINS[1]);
    let ours = [
        ("vqf", vqf),
        (
            "madgwick",
            score_one(rec, r, "madgwick", &mut madgwick).0.rms,
        ),
        ("mahony", score_one(rec, r, "mahony", &mut mahony).0.rms),
    ];
    for (name, rms) in ours {
        let reference = refs
            .get(&(trial[..2].to_string(), name.to_string()))
            .map_or(f64::NAN, |v| v[0]);
        let d = rms - reference;
        writeln!(
            tally.check,
            "{},{name},{rms:.4},{reference:.4},{d:.4}",
            &trial[..2]
        )?;
        let w = tally.worst.entry(name).or_insert((0.0, String::new()));
        if d.is_finite() && d.abs() >= w.0.abs() {
            *w = (d, trial[..2].to_string());
        }
    }
    Ok(())
}

/// Writes the peers' check (as recorded), the CSV, the tables and the figure.
fn write_outputs(args: &Args, refs: &References, tally: &Tally) -> anyhow::Result<()> {
    let out_dir = &args.out_dir;
    if args.vibration.is_none() {
        std::fs::create_dir_all(out_dir)?;
        std::fs::write(out_dir.join("peers_check.csv"), &tally.check)?;
    }
    std::fs::create_dir_all(out_dir)?;
    let stem = args
        .vibration
        .as_ref()
        .map_or("benchmark".to_string(), |v| format!("benchmark_{v}"));
    std::fs::write(out_dir.join(format!("{stem}.csv")), &tally.csv)?;
    let md = tables(&tally.table, refs, args.vibration.is_some())?;
    let _ = TILT_LIMIT_DEG;
    std::fs::write(out_dir.join(format!("{stem}.md")), &md)?;
    figure(args, &stem, &tally.table, refs)?;
    eprintln!("wrote {}/{stem}.csv, .md and .svg", out_dir.display());
    Ok(())
}

/// The two Markdown tables (the movement phase, and under 60 deg of true tilt), with the
/// rows clipped when `vibration` was added.
fn tables(table: &[TrialScores], refs: &References, vibration: bool) -> anyhow::Result<String> {
    let names: Vec<String> = table
        .first()
        .map(|(_, s, _)| s.iter().map(|s| s.estimator.clone()).collect())
        .unwrap_or_default();
    let mut md = String::new();
    for (title, pick) in [
        ("RMS (max) inclination error [deg], movement phase", 0),
        ("RMS (max) [deg] where the true tilt is under 60 deg", 1),
    ] {
        writeln!(md, "### {title}\n")?;
        let clip_head = if vibration { " rows clipped |" } else { "" };
        writeln!(
            md,
            "| trial |{clip_head} {} | VQF reference |",
            names.join(" | ")
        )?;
        writeln!(
            md,
            "|---|{}{}---|",
            if vibration { "---|" } else { "" },
            "---|".repeat(names.len())
        )?;
        for row in table {
            table_row(&mut md, row, refs, pick, vibration)?;
        }
        writeln!(md)?;
    }
    Ok(md)
}

/// One trial's row of a table: RMS (max) per estimator and the reference VQF's, of the
/// movement phase (`pick` 0) or under 60 deg (1).
fn table_row(
    md: &mut String,
    (trial, scores, clipped): &TrialScores,
    refs: &References,
    pick: usize,
    vibration: bool,
) -> std::fmt::Result {
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
    let clip = if vibration {
        format!(" {clipped} |")
    } else {
        String::new()
    };
    writeln!(
        md,
        "| {} |{clip} {} | {rv} |",
        &trial[..2],
        cells.join(" | ")
    )
}

/// The figure: each trial's RMS, per estimator, beside the reference VQF's.
fn figure(args: &Args, stem: &str, table: &[TrialScores], refs: &References) -> anyhow::Result<()> {
    let x: Vec<f64> = table
        .iter()
        .map(|(t, _, _)| t[..2].parse().unwrap_or(f64::NAN))
        .collect();
    let rms_of = |n: &str| -> Vec<f64> {
        table
            .iter()
            .map(|(_, s, _)| {
                s.iter()
                    .find(|x| x.estimator == n)
                    .map_or(f64::NAN, |x| x.rms)
            })
            .collect()
    };
    let reference_name = if args.vibration.is_some() {
        "VQF reference (Python package), as recorded: no vibration".to_string()
    } else {
        "VQF reference (Python package)".to_string()
    };
    let reference: Vec<f64> = table
        .iter()
        .map(|(t, _, _)| {
            refs.get(&(t[..2].to_string(), "vqf".to_string()))
                .map_or(f64::NAN, |v| v[0])
        })
        .collect();
    let series: Vec<(String, Vec<f64>)> = ["ekf3d", "ukf3d", "vqf"]
        .iter()
        .map(|n| (n.to_string(), rms_of(n)))
        .chain(std::iter::once((reference_name, reference)))
        .collect();
    let curves: Vec<Curve> = series
        .iter()
        .map(|(n, y)| Curve::points(n, &x, y))
        .collect();
    let what = args
        .vibration
        .as_ref()
        .map_or("as recorded".to_string(), |v| {
            format!("with {v}'s vibration added")
        });
    let mut spec = FigureSpec::new(
        &format!("BROAD replayed through the pendulum, {what}: inclination error per trial"),
        "BROAD trial",
        "RMS inclination error [deg]",
    );
    spec.y_range = Some((0.0, 5.0));
    spec.robust = None;
    let files = plot_curves(&args.out_dir, stem, &spec, &curves, &Palette::default())?;
    let _ = std::fs::remove_file(files.png);
    Ok(())
}

//! `pendtilt replay IMU_LOG -o LOG`: a virtual pendulum on a recorded IMU (MODEL.md 7.10).
//! Writes a 3-D log (7.6) that `estimate` and `report` read, and its rig file beside it.
use std::io::BufWriter;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{bail, Context};

use crate::bank::spatial::rig::Rig3dConfig;
use crate::io::output::{self as safe, NamedPath, OutputFile};
use crate::io::{AccelUnit, TimeUnit};
use crate::replay::output::{accel_unit_doubt, added_vibration, physical, rig_text, write_log};
use crate::replay::source::{ImuOptions, IMU_COLUMNS};
use crate::replay::{replay_with, Recording, Replay, ReplaySettings, SUBSTEP_TOLERANCE};

/// Replay a recorded IMU through a virtual Cardan pendulum and write the 3-D log it
/// would have given (MODEL.md 7.10): would a pendulum help on this device?
#[derive(Debug, Clone, clap::Args)]
pub struct Args {
    /// The recording: an IMU CSV (t, gyro_x, gyro_y, gyro_z, ax, ay, az; optional truth as
    /// roll, pitch or qw, qx, qy, qz, world <- body) or a BROAD trial file (MATLAB v5).
    #[arg(value_name = "IMU_LOG")]
    pub input: PathBuf,
    /// The 3-D log to write (MODEL.md 7.6); `-` for standard output (the rig file then
    /// only with --rig-out).
    #[arg(short, long, visible_alias = "out", value_name = "LOG.csv")]
    pub output: PathBuf,
    /// Rig file whose `[pendulum3d]` is the virtual pendulum (its pivot_offset is r12 from
    /// the IMU). Default: MODEL.md 7.6's rig (2.19 Hz, zeta 0.30, pivot at the IMU).
    #[arg(long, value_name = "RIG.toml")]
    pub params: Option<PathBuf>,
    /// Where to write the rig TOML (default: beside the log, `LOG.rig.toml`). Its gravity
    /// is the recording's (the mean |a| at rest).
    #[arg(long, value_name = "FILE")]
    pub rig_out: Option<PathBuf>,
    /// Encoder resolution in bits (0: none).
    #[arg(long, value_name = "BITS", default_value_t = 14)]
    pub encoder_bits: u32,
    /// Encoder white noise, one sigma, in degrees.
    #[arg(long, value_name = "DEG", default_value_t = 0.01)]
    pub encoder_noise: f64,
    /// Mechanical stop of each joint at this angle in degrees: one value for both joints,
    /// or `X,Y`. Default: none, the pendulum swings freely.
    #[arg(long, value_name = "DEG[,DEG]")]
    pub travel: Option<String>,
    /// Restitution at a stop: the joint rate reverses and scales by this.
    #[arg(long, value_name = "E", default_value_t = 0.3)]
    pub restitution: f64,
    /// RK4 steps per sample interval (at least 4).
    #[arg(long, value_name = "N", default_value_t = 4)]
    pub substeps: u32,
    /// Seed of the encoder noise (and of the --vibration scenario's random tones).
    #[arg(long, value_name = "N", default_value_t = 1)]
    pub seed: u64,
    /// Add a vehicle's vibration to the recorded motion (MODEL.md 7.10): the scenario's
    /// engine and road vibration (scooter3d, ride3d, ship3d) and a tone 0.7 Hz below the
    /// log's rate that an accelerometer without an anti-alias filter folds to 0.7 Hz. The
    /// pendulum feels all of it; the accelerometer columns are read at the log's times and
    /// clipped at --accel-full-scale. Default: none, the motion as recorded.
    #[arg(long, value_name = "SCENARIO")]
    pub vibration: Option<String>,
    /// The accelerometer's full scale with --vibration, in m/s^2.
    #[arg(long, value_name = "M_S2", default_value_t = 2.0 * 9.80665)]
    pub accel_full_scale: f64,
    /// Other column names of an IMU CSV: `t=time,gyro_x=gx,...` (names: t, gyro_x,
    /// gyro_y, gyro_z, ax, ay, az, roll, pitch, qw, qx, qy, qz). Default: none, those
    /// names.
    #[arg(long, value_name = "NAME=COLUMN,...")]
    pub map: Option<String>,
    /// Columns in degrees: `gyro` (deg/s), `roll,pitch`, or alone for both. Default: none,
    /// rad and rad/s.
    #[arg(long, num_args = 0..=1, default_missing_value = "all", value_name = "COLUMNS")]
    pub deg: Option<String>,
    /// Unit of the `t` column: s, ms, us or ns. Default: s.
    #[arg(long, value_name = "UNIT")]
    pub time_unit: Option<TimeUnit>,
    /// Unit of the accelerometer columns: m/s2, g or mg. Default: m/s2.
    #[arg(long, value_name = "UNIT")]
    pub accel_unit: Option<AccelUnit>,
    /// No summary.
    #[arg(short, long)]
    pub quiet: bool,
}

/// The IMU CSV options the arguments give.
fn imu_options(args: &Args) -> anyhow::Result<ImuOptions> {
    let mut o = ImuOptions {
        time_scale: args.time_unit.map_or(1.0, |u| u.seconds()),
        accel_scale: args
            .accel_unit
            .map_or(1.0, |u| u.metres_per_second_squared()),
        ..ImuOptions::default()
    };
    if let Some(map) = &args.map {
        for pair in map.split(',').filter(|p| !p.trim().is_empty()) {
            let Some((name, source)) = pair.split_once('=') else {
                bail!("--map {pair}: give NAME=COLUMN, e.g. --map gyro_x=gx");
            };
            let name = name.trim();
            if !IMU_COLUMNS.contains(&name) {
                bail!(
                    "--map {pair}: `{name}` is not an IMU column (they are: {})",
                    IMU_COLUMNS.join(", ")
                );
            }
            o.map.push((name.to_string(), source.trim().to_string()));
        }
    }
    if let Some(deg) = &args.deg {
        for c in deg.split(',').map(str::trim).filter(|c| !c.is_empty()) {
            match c {
                "all" => (o.gyro_deg, o.angles_deg) = (true, true),
                "gyro" | "gyro_x" | "gyro_y" | "gyro_z" => o.gyro_deg = true,
                "roll" | "pitch" => o.angles_deg = true,
                _ => bail!("--deg {c}: the angular columns of an IMU log are gyro, roll and pitch"),
            }
        }
    }
    Ok(o)
}

/// Joint stops from `--travel`: one angle or two, in degrees.
fn travel(arg: &Option<String>) -> anyhow::Result<Option<[f64; 2]>> {
    let Some(text) = arg else { return Ok(None) };
    let v: Vec<f64> = text
        .split(',')
        .map(|x| x.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .with_context(|| format!("--travel {text}: give an angle in degrees, or X,Y"))?;
    match v[..] {
        [a] => Ok(Some([a.to_radians(); 2])),
        [a, b] => Ok(Some([a.to_radians(), b.to_radians()])),
        _ => bail!("--travel {text}: give one angle in degrees, or X,Y"),
    }
}

/// Runs `pendtilt replay`.
pub fn run(args: Args) -> anyhow::Result<()> {
    let started = Instant::now();
    let options = imu_options(&args)?;
    let rig = args
        .params
        .as_deref()
        .map(Rig3dConfig::load)
        .transpose()
        .map_err(anyhow::Error::msg)?;
    let mut settings = ReplaySettings {
        encoder_bits: args.encoder_bits,
        encoder_noise: args.encoder_noise.to_radians(),
        travel: travel(&args.travel)?,
        restitution: args.restitution,
        substeps: args.substeps,
        seed: args.seed,
        ..ReplaySettings::default()
    };
    if let Some(r) = &rig {
        settings.pendulum = physical(&r.pendulum3d);
    }
    let vibration = added_vibration(args.vibration.as_deref(), args.seed, args.accel_full_scale)?;
    // A BROAD trial of 10 MB takes about 2 s.
    let bar = super::options::progress(&args.input, "replaying {spinner} {elapsed}", args.quiet);
    let replayed = Recording::open(&args.input, &options)
        .map_err(anyhow::Error::from)
        .and_then(|rec| Ok((replay_with(&rec, &settings, vibration.as_ref())?, rec)));
    bar.finish_and_clear();
    let (out, rec) = replayed?;

    let log = args.output.clone();
    let rig_path = match &args.rig_out {
        Some(p) => Some(p.clone()),
        None => {
            (!safe::has_no_beside(&log)).then(|| crate::sim::planar::output::rig_path_for(&log))
        }
    };
    let mut inputs = vec![NamedPath::new("IMU_LOG", &args.input)];
    if let Some(p) = &args.params {
        inputs.push(NamedPath::new("--params", p));
    }
    let mut outputs = vec![NamedPath::new("-o", &log)];
    outputs.extend(rig_path.as_deref().map(|p| NamedPath::new("--rig-out", p)));
    safe::check_distinct(&inputs, &outputs)?;
    let files = outputs
        .iter()
        .map(|o| OutputFile::create(o.option, o.path))
        .collect::<Result<Vec<_>, _>>()?;
    let rig_text = rig_text(&args.input, &out, rig.as_ref())?;
    (|| -> anyhow::Result<()> {
        write_log(
            &out,
            rec.truth.is_some(),
            BufWriter::with_capacity(1 << 20, files[0].writer()?),
        )?;
        if let Some(f) = files.get(1) {
            f.write_all(rig_text.as_bytes())?;
        }
        Ok(())
    })()
    .with_context(|| {
        let not: Vec<String> = outputs.iter().map(|o| safe::not_written(o.path)).collect();
        not.join("; ")
    })?;
    for f in files {
        f.commit()?;
    }
    if let Some(w) = accel_unit_doubt(&args.input, out.report.gravity) {
        eprintln!("{w}");
    }
    if !args.quiet {
        summary(&args, &rec, &out, rig_path.as_deref(), started);
    }
    Ok(())
}

/// The initial rest the replay found (the gyro's bias and gravity), or its absence.
fn rest_summary(args: &Args, rec: &Recording, out: &Replay) {
    let r = &out.report;
    let n = out.rows.len();
    match r.rest {
        Some(rest) => super::summary::say_err!(
            "initial rest: {:.2} s; gyro bias removed ({:.3}, {:.3}, {:.3}) deg/s; gravity \
             {:.4} m/s^2",
            rec.t[rest.end.min(n - 1)] - rec.t[0],
            rest.gyro_bias[0].to_degrees(),
            rest.gyro_bias[1].to_degrees(),
            rest.gyro_bias[2].to_degrees(),
            r.gravity
        ),
        None => super::summary::say_err!(
            "warning: {}: no initial rest of {} s or more: the gyro's bias is not removed \
             (taken as 0) and gravity is {} m/s^2",
            args.input.display(),
            crate::replay::drive::MIN_REST_S,
            r.gravity
        ),
    }
}

/// What the replay found, on standard error (or in the `--summary` file).
fn summary(args: &Args, rec: &Recording, out: &Replay, rig: Option<&Path>, started: Instant) {
    let r = &out.report;
    let n = out.rows.len();
    let secs = rec.t[n - 1] - rec.t[0];
    super::summary::say_err!(
        "replayed {n} rows ({secs:.1} s at {:.1} Hz) of {} through the pendulum in {:.2} s; \
         wrote {} (rig: {})",
        (n - 1) as f64 / secs,
        args.input.display(),
        started.elapsed().as_secs_f64(),
        args.output.display(),
        rig.map_or("none: give --rig-out FILE".into(), |p| p
            .display()
            .to_string())
    );
    rest_summary(args, rec, out);
    if r.filled.iter().any(|&k| k > 0) {
        super::summary::say_err!(
            "warning: {}: {} gyro and {} accelerometer values missing, interpolated across \
             to drive the pendulum (written empty, as recorded)",
            args.input.display(),
            r.filled[0],
            r.filled[1]
        );
    }
    super::summary::say_err!(
        "largest swing: outer {:.1} deg, inner {:.1} deg{}",
        r.largest_swing[0].to_degrees(),
        r.largest_swing[1].to_degrees(),
        if r.stop_hits.iter().any(|&h| h > 0) {
            format!(
                "; stops hit {} and {} times",
                r.stop_hits[0], r.stop_hits[1]
            )
        } else {
            String::new()
        }
    );
    if r.substep_change > SUBSTEP_TOLERANCE {
        super::summary::say_err!(
            "warning: the pendulum moved by up to {:.2e} rad when the substeps were doubled \
             (more than {SUBSTEP_TOLERANCE:e}): give --substeps {}",
            r.substep_change,
            4 * args.substeps
        );
    }
    if let (Some(v), Some(name)) = (r.vibration, &args.vibration) {
        super::summary::say_err!(
            "vibration of {name} added (RMS {:.2}, {:.2}, {:.2} m/s^2 with the tone at {:.1} Hz, \
             read as {:.1} Hz); the pendulum integrated at {} steps a sample; accelerometer \
             clipped at {:.1} m/s^2 on {} of {n} rows",
            v.added_rms[0],
            v.added_rms[1],
            v.added_rms[2],
            v.tone_hz[0],
            v.tone_hz[1],
            r.substeps,
            args.accel_full_scale,
            v.clipped_rows
        );
    }
    if rec.truth.is_none() {
        super::summary::say_err!(
            "the recording has no truth: the log has no roll and pitch columns"
        );
    }
}

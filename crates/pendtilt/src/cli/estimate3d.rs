//! The 3-D branch of `pendtilt estimate` (MODEL.md 7.6): a log with the
//! columns t, phi_x, phi_y, gyro_x, gyro_y, gyro_z, ax, ay, az (speed, roll, pitch
//! optional) through the 3-D bank ([`crate::bank3d::REGISTRY3D`]).
//!
//! The rig is `--params` (`[pendulum3d]` physical or normalised, `[mounting]`), else the
//! rig of the `--scenario` file, else MODEL.md 7.6's. The sensors' noise figures come from
//! the `--scenario` file (the one `simulate` writes beside the log) when given. With
//! truth in the log, the inclination error (MODEL.md 7.9) of every estimator is printed,
//! over t >= t0 + `--score-from` (default: the scenario's `score_from`, else the rule of
//! [`crate::pipeline::Window::resolve`]: 5 s, or the whole of a log shorter than 10 s).
//!
//! Row handling: one output row per data row. A missing cell or a time that does not
//! increase reaches the estimators as NaN, which they flag and hold on; an encoder angle
//! beyond +-pi, a rate beyond 100 rad/s (or the rig's `[gyro] full_scale`; a reading at it is
//! kept and flagged `saturated`) or a specific force beyond 500 m/s^2 (the planar
//! reader's physical bounds) is impossible and read as missing too, with a warning naming
//! its place, and the estimators reading it flag the row `implausible`. A lone time stamp
//! ahead of the next row's (one glitched stamp between two good ones) is a bad time step of
//! that row alone, rather than making every following row up to it go back in time. A
//! clip of the gyro (when the rig gives no full scale) or of the accelerometer is found in
//! the readings themselves ([`crate::io::plateau`], [`LOOK_AHEAD_ROWS`] rows ahead of the
//! estimators), warned once per level, and every reading at it flagged `saturated` by the
//! estimators reading that sensor ([`Bank3d::update_clipped`]); a clip is no gap. A
//! sensor missing for longer than the bank's restart gap (0.5 s) restarts the estimators
//! reading it, with a warning. A cell that is not a number stops the run with its file,
//! line and column; so does a time column whose steps no sensor rate explains.
use std::collections::VecDeque;
use std::fs::File;
use std::io::BufReader;
use std::path::Path;

use anyhow::{bail, Context};
use pendtilt_core::spatial::SpatialSample;
use pendtilt_core::{Flags, StepGate};

use pendtilt_core::spatial::Attitude;

use super::estimate::Args;
use super::options::LogColumns;
use crate::bank::Inputs;
use crate::bank3d::rig::{mounting_doubts, Pendulum3dConfig, Rig3dConfig};
use crate::bank3d::score::Inclination;
use crate::bank3d::{Bank3d, Clips, Settings3d};
use crate::config::{doubt_gravity, doubt_gyro_full_scale};
use crate::io::input::{LogSource, STDIN_NAME};
use crate::io::output::{self, NamedPath, OutputFile};
use crate::io::plateau::{NewLevel, PlateauWatch, LOOK_AHEAD_ROWS};
use crate::io::plausibility::{
    implausible_given_unit, implausible_step, DEFAULT_ACCEL_LIMIT, DEFAULT_GYRO_LIMIT,
    FULL_SCALE_ROUNDING,
};
use crate::io::{Column3d, Estimates3dWriter, Log3dReader, Log3dRecord};
use crate::sim3d::Scenario3d;
use crate::units::Pair;

/// Rows read before the first estimate, for the time-unit check.
const HEAD_ROWS: usize = 64;

/// Largest plausible body rate \[rad/s\] (the planar reader's physical bound).
const MAX_RATE: f64 = DEFAULT_GYRO_LIMIT;

/// Largest plausible specific force \[m/s^2\] (the planar reader's physical bound).
const MAX_ACCEL: f64 = DEFAULT_ACCEL_LIMIT;

/// Refuses the options of `given` (name, whether given) that only 3-D logs take, on the
/// planar log `log`.
pub fn refuse_3d_options(given: &[(&str, bool)], log: &Path) -> anyhow::Result<()> {
    let given: Vec<&str> = given.iter().filter(|g| g.1).map(|g| g.0).collect();
    anyhow::ensure!(
        given.is_empty(),
        "{}: for 3-D logs only (MODEL.md 7.6 columns t, phi_x, phi_y, gyro_x, gyro_y, \
         gyro_z, ax, ay, az); {} is a planar log",
        given.join(", "),
        log.display()
    );
    Ok(())
}

/// True when the first header line of the file at `path` has every 3-D column (comment
/// and blank lines before it skipped). An unreadable file is not 3-D: the planar reader
/// then reports it. Only a regular file is peeked at: a pipe (`<(cat log.csv)`,
/// `/dev/stdin`, `-`) has its header peeked at instead ([`LogSource`]), as reading its
/// first lines here would take them from the reader that follows.
pub fn is_3d_log(path: &Path, map: &crate::io::ColumnMap) -> bool {
    if !std::fs::metadata(path).is_ok_and(|m| m.is_file()) {
        return false;
    }
    let Ok(f) = File::open(path) else {
        return false;
    };
    // The readers' own line reader: a byte-order mark (Excel's "CSV UTF-8"), CRLF, quotes
    // and comment lines are taken as the reader that follows takes them.
    let mut lines = crate::io::csv_lines::CsvLines::new(BufReader::new(f), b',');
    if !matches!(lines.next_row(), Ok(Some(()))) {
        return false;
    }
    let header: Vec<String> = (0..lines.field_count())
        .filter_map(|i| lines.field(i))
        .map(|f| String::from_utf8_lossy(&f).into_owned())
        .collect();
    crate::io::is_3d_header(&map.rename_spatial(&header))
}

/// What a 3-D run is given: the log and the options `estimate` and `report` share.
#[derive(Debug, Clone, Copy)]
pub struct Options3d<'a> {
    /// The log (to read: the file, or the copy of standard input).
    pub log: &'a Path,
    /// The log's name in messages, when not its path (`<stdin>`).
    pub log_name: Option<&'a str>,
    /// `--params`.
    pub params: Option<&'a Path>,
    /// `--scenario`.
    pub scenario: Option<&'a Path>,
    /// `--score-from` \[s\].
    pub score_from: Option<f64>,
    /// `--map` (refused on a 3-D log), `--deg`, `--time-unit`, `--accel-unit`.
    pub columns: &'a LogColumns,
    /// `--only`.
    pub only: Option<&'a [String]>,
    /// `--quiet`: no notices.
    pub quiet: bool,
}

impl<'a> Options3d<'a> {
    /// The options of `pendtilt estimate`: the log read from `log`, named `name` in
    /// messages (else by its path).
    pub fn of_estimate(args: &'a Args, log: &'a Path, name: Option<&'a str>) -> Self {
        let b = &args.bank;
        Self {
            log,
            log_name: name,
            params: b.params.as_deref(),
            scenario: args.scenario.as_deref(),
            score_from: args.score_from,
            columns: &b.columns,
            only: b.only.as_deref(),
            quiet: b.quiet,
        }
    }

    fn notice(&self, text: &str) {
        if !self.quiet {
            eprintln!("{text}");
        }
    }

    /// The input files, named as on the command line (for the output-safety check).
    pub fn inputs(&self) -> Vec<NamedPath<'_>> {
        let mut inputs = vec![NamedPath::new("LOG", self.log)];
        if let Some(p) = self.params {
            inputs.push(NamedPath::new("--params", p));
        }
        if let Some(p) = self.scenario {
            inputs.push(NamedPath::new("--scenario", p));
        }
        inputs
    }
}

/// What the options and files give the run.
#[derive(Debug, Clone)]
pub struct Setup {
    /// The estimators' settings.
    pub settings: Settings3d,
    /// Scoring starts this long after the first row \[s\], as `--score-from` or the
    /// scenario file says; None: the rule of [`crate::pipeline::Window::resolve`].
    pub score_from: Option<f64>,
    /// Seconds per unit of `t`.
    time_scale: f64,
    /// `t`'s unit, when given (checked as the physics would find it).
    time_given: Option<crate::io::TimeUnit>,
    /// Radians per unit of the angular columns.
    angle_scale: f64,
    /// `--accel-unit` (`None`: m/s^2).
    accel_unit: Option<crate::io::AccelUnit>,
    /// The rig or scenario placed O, the point whose speed `speed` gives (`[mounting]`).
    speed_at_given: bool,
}

/// Reads the rig and scenario files and checks the options.
pub fn setup(opts: &Options3d) -> anyhow::Result<Setup> {
    if let Some(c) = opts.columns.map.planar_only().first() {
        bail!(
            "--map {c}=...: a column of a planar log; a 3-D log's columns are t, phi_x, phi_y, \
             gyro_x, gyro_y, gyro_z, ax, ay, az, speed, roll, pitch (MODEL.md 7.6)"
        );
    }
    if opts.columns.negate.is_some() {
        bail!(
            "--negate: for planar logs only; a 3-D log's columns follow MODEL.md 7.6's axes \
             (FLU) and signs"
        );
    }
    let angle_scale = match opts.columns.deg {
        None => 1.0,
        Some(d) if d == crate::io::DegreeColumns::all() => std::f64::consts::PI / 180.0,
        Some(_) => bail!(
            "--deg with a list: for planar logs only; on a 3-D log --deg alone reads every \
             angular column (phi_x, phi_y, gyro_*, roll, pitch) in degrees"
        ),
    };
    let scenario = match opts.scenario {
        Some(p) => {
            let text = std::fs::read_to_string(p)
                .with_context(|| format!("cannot read --scenario {}", p.display()))?;
            Some(Scenario3d::from_toml(&text, &p.display().to_string())?.0)
        }
        None => None,
    };
    let mut speed_at_given = scenario.is_some();
    let mut rig_gives_noise = false;
    let settings = match (opts.params, &scenario) {
        (Some(p), s) => {
            let rig = Rig3dConfig::load(p).map_err(anyhow::Error::msg)?;
            speed_at_given = rig.mounting_given;
            rig_gives_noise = rig.ekf3d.gives_sensor_noise();
            let mut doubts = rig.pendulum3d.length_doubts("pendulum3d");
            doubts.extend(mounting_doubts(&rig.mounting, "mounting"));
            for d in doubts {
                opts.notice(&format!(
                    "warning: {}: {}",
                    p.display(),
                    d.in_file("rig file")
                ));
            }
            let g = rig.pendulum3d.gravity();
            if let Some(d) = doubt_gravity("pendulum3d.gravity", g) {
                opts.notice(&format!("warning: {}: {d}", p.display()));
            }
            let fs = rig.gyro.full_scale;
            if let Some(d) =
                fs.and_then(|f| doubt_gyro_full_scale("gyro.full_scale", f, "rig file"))
            {
                opts.notice(&format!("warning: {}: {d}", p.display()));
            }
            let mut settings = Settings3d::new(
                rig.pendulum3d.params(),
                rig.mounting,
                s.as_ref().map(|s| &s.sensors),
            );
            rig.ekf3d.apply(&mut settings.ekf);
            settings.ekf.gyro = rig.gyro;
            settings
        }
        (None, Some(s)) => {
            let file = opts
                .scenario
                .map(|p| p.display().to_string())
                .unwrap_or_default();
            let mut doubts =
                Pendulum3dConfig::Physical(s.rig.pendulum3d).length_doubts("rig.pendulum3d");
            doubts.extend(mounting_doubts(&s.rig.mounting, "rig.mounting"));
            for d in doubts {
                opts.notice(&format!("warning: {file}: {}", d.in_file("scenario file")));
            }
            if let Some(d) = doubt_gravity("rig.pendulum3d.gravity", s.rig.pendulum3d.gravity) {
                opts.notice(&format!("warning: {file}: {d}"));
            }
            Settings3d::of_scenario(s)
        }
        (None, None) => {
            opts.notice("note: no --params: using the default 3-D rig of MODEL.md 7.6");
            let rig = Rig3dConfig::default();
            Settings3d::new(rig.pendulum3d.params(), rig.mounting, None)
        }
    };
    if scenario.is_none() && !rig_gives_noise {
        opts.notice("note: no --scenario: ekf3d and ukf3d use their default sensor noise figures");
    }
    let score_from = opts.score_from.or(scenario.as_ref().map(|s| s.score_from));
    Ok(Setup {
        settings,
        score_from,
        time_scale: opts.columns.time_unit.map_or(1.0, |u| u.seconds()),
        time_given: opts.columns.time_unit,
        angle_scale,
        accel_unit: opts.columns.accel_unit,
        speed_at_given,
    })
}

/// `pendtilt estimate` on a 3-D log ([`super::estimate::estimate`]).
pub fn estimate(
    args: &Args,
    source: LogSource,
    name: &str,
) -> anyhow::Result<super::estimate::Outcome> {
    let path = match &source {
        LogSource::File(p) => p.clone(),
        LogSource::Stream { .. } => args.log.clone(),
    };
    let opts = Options3d::of_estimate(args, &path, Some(name));
    output::check_distinct(&opts.inputs(), &[NamedPath::new("-o", &args.output)])?;
    let setup = setup(&opts)?;
    let out = OutputFile::create("-o", &args.output)?;
    let result = estimate_into(args, &opts, &setup, source, &out)
        .with_context(|| output::not_written(&args.output))?;
    out.commit()?;
    Ok(super::estimate::Outcome {
        rows: result.rows,
        estimators: result.names.iter().map(|n| n.to_string()).collect(),
        warnings: result.warnings.len() as u64,
        notes: result
            .warnings
            .iter()
            .map(|w| format!("warning: {w}"))
            .collect(),
        table: result.truth.then(|| score_table(&result)),
        scores: if result.truth {
            (result.names.iter().zip(&result.scores))
                .map(|(n, s)| super::estimate::Score {
                    name: n.to_string(),
                    rms: s.rms(),
                    max: s.max(),
                    scored: s.count(),
                })
                .collect()
        } else {
            Vec::new()
        },
    })
}

/// What a pass over the log gave.
pub struct Pass {
    /// Rows read (one output row each).
    pub rows: u64,
    /// The estimators, in column order.
    pub names: Vec<&'static str>,
    /// Whether the log has the truth (roll and pitch).
    pub truth: bool,
    /// Their inclination error over the scored rows.
    pub scores: Vec<Inclination>,
    /// The rows scored.
    pub window: crate::pipeline::Window,
    /// Warnings on the input (places named).
    pub warnings: Vec<String>,
}

/// One row of a pass as the sink sees it.
pub struct Row<'a> {
    /// Time \[s\].
    pub t: f64,
    /// Every estimator's output, in [`Pass::names`] order.
    pub est: &'a [Attitude<f64>],
    /// Their quaternions (when asked for and they have one).
    pub quats: &'a [Option<[f64; 4]>],
    /// True roll and pitch \[rad\] (NaN when absent).
    pub truth: (f64, f64),
    /// The sample the estimators got (a ride report reads the speed and gyro from it).
    pub sample: &'a SpatialSample<f64>,
}

/// Warnings printed in full; the rest are counted.
const MAX_WARNINGS: usize = 10;

/// Rows with a missing cell, and rows whose time does not increase, listed each.
const ROW_ISSUES_LISTED: u64 = 3;

/// Where a pass puts its rows: the estimates file, or memory (`report`).
pub trait Sink3d {
    /// Called once, before the first row: the estimators, which of them give a
    /// quaternion, and whether the log has the truth.
    fn start(
        &mut self,
        names: &[&'static str],
        quaternion: &[bool],
        truth: bool,
    ) -> anyhow::Result<()>;
    /// One row.
    fn row(&mut self, r: Row) -> anyhow::Result<()>;
}

/// The estimates file's columns: each estimator, with its quaternion when asked for.
pub fn columns(names: &[&'static str], quaternion: &[bool]) -> Vec<Column3d> {
    names
        .iter()
        .zip(quaternion)
        .map(|(n, q)| Column3d {
            name: n.to_string(),
            quaternion: *q,
        })
        .collect()
}

/// The estimates CSV (header written by [`Sink3d::start`]).
struct FileSink<'a> {
    out: &'a OutputFile,
    options: crate::io::WriterOptions,
    writer: Option<Estimates3dWriter<Box<dyn std::io::Write + Send>>>,
    /// Rows written, for the progress line.
    rows: u64,
    bar: indicatif::ProgressBar,
}

impl Sink3d for FileSink<'_> {
    fn start(
        &mut self,
        names: &[&'static str],
        quaternion: &[bool],
        truth: bool,
    ) -> anyhow::Result<()> {
        self.writer = Some(Estimates3dWriter::new(
            self.out.writer()?,
            columns(names, quaternion),
            truth,
            self.options,
        )?);
        Ok(())
    }

    fn row(&mut self, r: Row) -> anyhow::Result<()> {
        if let Some(w) = &mut self.writer {
            w.write(r.t, r.est, r.quats, r.truth)?;
        }
        self.rows += 1;
        // Every 64k rows: a counter the bar reads, not a draw per row.
        if self.rows % 65_536 == 0 {
            self.bar.set_position(self.rows);
        }
        Ok(())
    }
}

/// Estimates into the (uncommitted) output file, flushed.
fn estimate_into(
    args: &Args,
    opts: &Options3d,
    setup: &Setup,
    source: LogSource,
    out: &OutputFile,
) -> anyhow::Result<Pass> {
    let mut sink = FileSink {
        out,
        options: args.bank.writer_options(),
        writer: None,
        rows: 0,
        bar: super::options::progress(
            opts.log,
            "estimating {spinner} {human_pos} rows, {elapsed}",
            opts.quiet,
        ),
    };
    let q = args.quaternion;
    let result = match source {
        LogSource::File(_) => pass(opts, setup, q, &mut sink),
        // A pipe is read as it comes (the header was peeked at), as a file is read.
        LogSource::Stream { reader, .. } => {
            let name = opts.log_name.unwrap_or(STDIN_NAME);
            let renames = opts.columns.map.spatial();
            Log3dReader::new_mapped(reader, name, renames)
                .map_err(anyhow::Error::from)
                .and_then(|log| pass_on(log, name, opts, setup, q, &mut sink, Feed::File))
        }
    };
    sink.bar.finish_and_clear();
    let result = result?;
    if let Some(mut w) = sink.writer.take() {
        w.flush()?;
    }
    Ok(result)
}

/// How a pass reads its log.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Feed {
    /// A file: rows are read ahead to find clips, and the time unit is checked on the
    /// first rows before any estimate is made. A malformed line ends the pass.
    File,
    /// A live stream: nothing is read ahead, every row goes to the sink as soon as its
    /// line arrived, the time unit is checked once enough rows went through, and a
    /// malformed line is skipped, said, and given one NaN row flagged `bad_line`.
    Live,
}

/// Reads the log's first rows, checks the time unit, then runs every row through the bank
/// into `sink`, scoring the inclination error when the log has the truth.
pub fn pass(
    opts: &Options3d,
    setup: &Setup,
    quaternion: bool,
    sink: &mut dyn Sink3d,
) -> anyhow::Result<Pass> {
    let file = opts
        .log_name
        .map_or_else(|| opts.log.display().to_string(), str::to_string);
    let log = Log3dReader::open_as(opts.log, &file, opts.columns.map.spatial())?;
    pass_on(log, &file, opts, setup, quaternion, sink, Feed::File)
}

/// [`pass`] over a log already open (`file` its name), read as `feed` says.
pub fn pass_on<R: std::io::BufRead>(
    mut log: Log3dReader<R>,
    file: &str,
    opts: &Options3d,
    setup: &Setup,
    quaternion: bool,
    sink: &mut dyn Sink3d,
    feed: Feed,
) -> anyhow::Result<Pass> {
    let file = file.to_string();
    let mut bank = Bank3d::new(&setup.settings, opts.only).map_err(anyhow::Error::msg)?;
    let names = bank.names();
    let truth = log.has("roll") && log.has("pitch");
    // A truth named with its unit (`roll_deg`) is not read: say so, with the fix.
    let line = log.header_line();
    if let Some(h) = crate::io::unit_named_3d_hint(&["roll", "pitch"], log.header(), &file, line) {
        opts.notice(&format!(
            "warning: {file}:{line}: {h}; until then no inclination error is scored"
        ));
    }
    // Said as the planar reader says it (`; ignored: ...`): a column under another name
    // than MODEL.md 7.6's was dropped without a word.
    let ignored: Vec<String> = (log.header().iter().enumerate())
        .filter(|(_, h)| !crate::io::LOG3D_COLUMNS.contains(&h.as_str()))
        .map(|(i, h)| {
            if h.is_empty() {
                format!("(unnamed field {})", i + 1)
            } else {
                format!("`{h}`")
            }
        })
        .collect();
    if !ignored.is_empty() {
        opts.notice(&format!(
            "note: {file}:{line}: ignored, not a column of a 3-D log (MODEL.md 7.6): {}",
            ignored.join(", ")
        ));
    }
    if !log.has("speed") {
        // Without the speed no estimator knows the vehicle's own acceleration.
        opts.notice(&format!(
            "note: {file} has no `speed` column: ekf3d and ukf3d take the vehicle as not \
             accelerating, so braking, pulling away and turns bias them (and every peer)"
        ));
    }
    if log.has("speed") && !setup.speed_at_given {
        // Measured: ride3d (120 s, seed 1) 0.149 deg RMS with its [mounting], 0.247 without.
        opts.notice(&format!(
            "note: {file} has a `speed` column and the rig names no [mounting]: the speed is \
             taken as P1's (speed_at = [0, 0, 0], the pendulum's point); on a vehicle give \
             speed_at, the point whose speed the wheel sensor gives, relative to P1 (on ride3d \
             this took ekf3d from 0.149 to 0.247 deg RMS)"
        ));
    }
    let with_q: Vec<bool> = (0..names.len())
        .map(|i| quaternion && bank.has_quaternion(i))
        .collect();
    sink.start(&names, &with_q, truth)?;
    let live = feed == Feed::Live;
    let (look_ahead, head_rows) = if live {
        (0, 0)
    } else {
        (LOOK_AHEAD_ROWS, HEAD_ROWS)
    };
    let mut head = Vec::with_capacity(head_rows);
    while head.len() < head_rows {
        match log.next_record()? {
            Some(r) => head.push(r),
            None => break,
        }
    }
    // Live: the first rows are kept as they go by, and judged when there are enough.
    let mut seen = Vec::with_capacity(if live { HEAD_ROWS } else { 0 });
    if !live {
        check_time_unit(&file, &head, setup.time_given)?;
    }
    let blank = vec![
        Attitude {
            roll: f64::NAN,
            pitch: f64::NAN,
            flags: Flags::BAD_LINE,
        };
        names.len()
    ];
    let header: Vec<String> = log.header().to_vec();
    let mut row = RowInput::new(setup, &file, &header);
    let mut gyro_units = GyroUnits::new(&setup.settings.ekf.params);
    let mut accel_unit = crate::units::AccelMagnitude::default();
    let accel_scale = setup
        .accel_unit
        .map_or(1.0, |u| u.metres_per_second_squared());
    let mut gate = StepGate::new();
    let mut scorer = crate::pipeline::Scorer::<Inclination>::new(setup.score_from, names.len());
    let mut quats = vec![None; names.len()];
    let mut rows = 0u64;
    // Rows with a speed reading, and those some estimator flagged as wheel slip.
    let (mut speed_rows, mut slip_rows) = (0u64, 0u64);
    // The rows after the current one: clips are found LOOK_AHEAD_ROWS ahead, lone time
    // stamps one row ahead.
    let mut ahead: VecDeque<Log3dRecord> = VecDeque::with_capacity(look_ahead + 1);
    let mut head = head.into_iter();
    loop {
        while ahead.len() <= look_ahead {
            let r = match head.next() {
                Some(r) => r,
                None => match log.next_record() {
                    Ok(Some(r)) => r,
                    Ok(None) => break,
                    // Live, nothing is held ahead: the bad line's row goes out in its place.
                    Err(e) if live && e.is_one_line() => {
                        opts.notice(&format!(
                            "warning: {file}:{}: {}: the line is skipped; its output row is \
                             NaN, flagged bad_line",
                            e.line.unwrap_or(0),
                            e.what()
                        ));
                        log.resume_after(&e);
                        sink.row(Row {
                            t: f64::NAN,
                            est: &blank,
                            quats: &vec![None; names.len()],
                            truth: (f64::NAN, f64::NAN),
                            sample: &SpatialSample::after(f64::NAN),
                        })?;
                        rows += 1;
                        continue;
                    }
                    Err(e) => return Err(e.into()),
                },
            };
            // In m/s^2 from here on (--accel-unit); before the bounds, for the unit check.
            let mut r = r;
            r.accel = r.accel.map(|a| a * accel_scale);
            accel_unit.add(r.accel.iter().map(|a| a * a).sum::<f64>().sqrt());
            row.find_clips(&r);
            ahead.push_back(r);
        }
        let Some(r) = ahead.pop_front() else {
            break;
        };
        if live && seen.len() < HEAD_ROWS {
            seen.push(r);
            if seen.len() == HEAD_ROWS {
                check_time_unit(&file, &seen, setup.time_given)?;
            }
        }
        let (t, s, roll, pitch) = row.sample(&r, &ahead, &mut gate);
        gyro_units.add(&r, s.dt, setup.angle_scale);
        bank.update_clipped(&s, row.clipped);
        if let Some((re, n)) = bank.restarted() {
            row.restart_warning(r.line, re, n);
        }
        bank.flag_implausible(row.implausible);
        let est = bank.outputs();
        speed_rows += u64::from(s.speed.is_finite());
        slip_rows += u64::from(est.iter().any(|e| e.flags.contains(Flags::SLIP)));
        for (i, q) in quats.iter_mut().enumerate() {
            *q = if quaternion { bank.quaternion(i) } else { None };
        }
        if truth {
            scorer.row(t, |i, sc| {
                sc.add((est[i].roll, est[i].pitch), (roll, pitch))
            });
        }
        sink.row(Row {
            t,
            est,
            quats: &quats,
            truth: (roll, pitch),
            sample: &s,
        })?;
        rows += 1;
    }
    if live && seen.len() < HEAD_ROWS {
        check_time_unit(&file, &seen, setup.time_given)?;
    }
    let mut warnings = row.warnings();
    if let Some((line, n)) = log.take_nul() {
        warnings.push(format!(
            "{file}:{line}: {}",
            crate::io::nul_message(line, n)
        ));
    }
    let mut found = gyro_units.findings(&file);
    found.extend(
        accel_unit
            .finding("ax, ay, az", setup.accel_unit)
            .map(|f| format!("{file}: {}", f.message)),
    );
    // A gyro in deg/s, or an accelerometer in g, makes the speed disagree with everything
    // too: the unit is the cause.
    if found.is_empty() {
        if let Some(w) = slip_warning(&file, slip_rows, speed_rows) {
            warnings.push(w);
        }
    }
    warnings.extend(found);
    let (window, scores) = scorer.finish();
    Ok(Pass {
        rows,
        names,
        truth,
        scores,
        window,
        warnings,
    })
}

/// The gyro's unit found from the physics, per axis, with the planar check
/// ([`crate::units::UnitCheck`]): below the pendulum's frequency the encoders follow the
/// tilt, so d(phi_x)/dt ~ gyro_x and d(phi_y)/dt ~ gyro_y (roll and pitch rates, for the
/// tilts of a vehicle); a gyro 57x that is in deg/s, 1/57 of it converted twice. The
/// sensor's height above the centre the body rotates about is fitted out
/// ([`crate::units::UnitCheck::lever_fit`]): on ship3d (IMU 5 m above it) the pendulum
/// swings 1.8x the pitch rate, so a gyro in deg/s read as 34x on pitch and was not found,
/// and as 45x on roll; with the height fitted (4.8 and 5.0 m) 56.8x and 56.6x.
struct GyroUnits {
    axes: [crate::units::UnitCheck; 2],
    /// Gravity \[m/s^2\], for the height.
    gravity: f64,
    /// The yaw rate against the turn, for a vehicle with a speed (see [`TurnCheck`]).
    turn: TurnCheck,
}

/// The gyro's unit from a vehicle's turns: in a turn the lateral specific force is the
/// speed times the yaw rate, `a_y ~ v gyro_z` (MODEL.md 7.7: `a_O = v' d + v d'`, FLU), up to
/// the roll's share of gravity. Both low-passed at [`TURN_HZ`]; on ride3d (60 s, seed 1)
/// with the gyro in deg/s the fit of `v gyro_z` on `a_y` gives 54.4 (0.95 x 57.3) at
/// r = 0.96. The encoders cannot tell there:
/// a car's turns swing its pendulum outward, so d(phi)/dt is not the gyro (a gyro in deg/s
/// on ride3d was found only by the slip warning, which blamed the speed first).
struct TurnCheck {
    /// `a_y` and `v gyro_z`, low-passed.
    lp: [crate::units::Smooth; 2],
    /// Time since the filters started \[s\] (pairs are taken after [`TURN_SETTLE`]).
    since: f64,
    pair: crate::units::Pair,
}

/// The low-pass of [`TurnCheck`] \[Hz\]: the turns, not the vibration or the road.
const TURN_HZ: f64 = 0.5;
/// The filters' settling time before pairs are taken \[s\].
const TURN_SETTLE: f64 = 2.0;
/// The least standard deviation of the low-passed lateral specific force for the turn
/// check \[m/s^2\]: ride3d's is 1.18; a ship's (0.07 of v gyro_z) has no turns to tell.
const TURN_MIN_LATERAL: f64 = 0.3;

impl TurnCheck {
    fn new() -> Self {
        Self {
            lp: [crate::units::Smooth::new(TURN_HZ); 2],
            since: 0.0,
            pair: Default::default(),
        }
    }

    /// One row: `gyro_z` \[as read, times the --deg factor\], `a_y` \[m/s^2\], `speed`.
    fn add(&mut self, dt: f64, gyro_z: f64, a_y: f64, speed: Option<f64>) {
        let Some(v) = speed else {
            return;
        };
        let (x, y) = (a_y, v * gyro_z);
        if !(x.is_finite() && y.is_finite() && dt > 0.0 && dt < 0.1) {
            return;
        }
        let (x, y) = (self.lp[0].update(x, dt), self.lp[1].update(y, dt));
        self.since += dt;
        if self.since >= TURN_SETTLE {
            self.pair.add(x, y);
        }
    }

    /// The factor of `v gyro_z` on `a_y` (1 in rad/s, 57.3 in deg/s), when the log turned.
    /// The noise is in `a_y` (the roll's share of gravity, the vibration left): the factor
    /// of the regression of `a_y` on `v gyro_z`, not the other way (ride3d, seeds 1-4, deg/s:
    /// 50.0, 41.2, 43.1, 48.2 the other way, against 57.3).
    fn fit(&self) -> Option<crate::units::Fit> {
        self.pair.fit_noisy_x_above(TURN_MIN_LATERAL)
    }
}

impl GyroUnits {
    /// For the rig's pendulum, each axis below its own natural frequency (the default
    /// planar rig's, 2.19 Hz, let a 0.49 Hz pendulum's swing into the comparison: a gyro in
    /// deg/s read as 43x on ship3d's roll and was not found on its pitch).
    fn new(params: &pendtilt_core::spatial::cardan::CardanParams<f64>) -> Self {
        // The accelerometer's tilt about each axis stands in for the planar check's angle:
        // its signs are checked against the encoder and the gyro.
        let inputs = crate::bank::Inputs {
            phi: true,
            gyro: true,
            accel: true,
        };
        let w = params.natural_frequencies();
        Self {
            turn: TurnCheck::new(),
            gravity: params.gravity,
            axes: std::array::from_fn(|i| {
                crate::units::UnitCheck::with_natural_frequency(
                    w[i] / std::f64::consts::TAU,
                    inputs,
                )
                .with_lever()
            }),
        }
    }

    /// One row as written (`k`: the --deg factor), before the plausibility bounds: a gyro
    /// in deg/s is beyond them.
    fn add(&mut self, r: &Log3dRecord, dt: f64, k: f64) {
        let f = r.accel;
        // The accelerometer's roll atan2(f_y, f_z) and pitch atan2(-f_x, |f_yz|) (MODEL.md
        // 7.1) as the planar check's atan2(ax, ay).
        let tilt = [(f[1], f[2]), (-f[0], f[1].hypot(f[2]))];
        // The true roll and pitch, when the log has them, tell one reversed column from
        // the two others both reversed.
        let truth = [r.roll, r.pitch];
        for (i, axis) in self.axes.iter_mut().enumerate() {
            let s = pendtilt_core::Sample {
                dt,
                phi: r.phi[i] * k,
                gyro: r.gyro[i] * k,
                ax: tilt[i].0,
                ay: tilt[i].1,
            };
            axis.add(&s, truth[i]);
        }
        self.turn.add(dt, r.gyro[2] * k, r.accel[1], r.speed);
    }

    /// A column of axis `i` (0: x, roll; 1: y, pitch) that counts the other way, from the
    /// signs of the encoder against the accelerometer's tilt, the gyro against the encoder's
    /// rate (`gyro`, the pair or the lever fit) and against the tilt's rate: which one is
    /// reversed, with the fix. One column against the other two is also the other two
    /// reversed together (an IMU turned half round reverses the gyro and the accelerometer):
    /// the true roll or pitch, when logged, decides; without it the message gives both. Measured on scooter3d (30 s, seed 2): gyro_x negated gave
    /// ekf3d 11.3 deg RMS and the warning `gyro_x is -1.0x ...: is the gyro in deg/s?`;
    /// phi_x negated, ekf3d 13.3 with the same wrong warning; ay negated, VQF 8.0 and
    /// nothing said; ax negated, only the wheel-slip warning.
    fn sign_finding(
        axis: &crate::units::UnitCheck,
        i: usize,
        gyro: &crate::units::Fit,
    ) -> Option<String> {
        use crate::units::Comparison;
        let (g, phi, tilt, a, name) = [
            ("gyro_x", "phi_x", "roll atan2(ay, az)", "ay", "roll"),
            (
                "gyro_y",
                "phi_y",
                "pitch atan2(-ax, |(ay, az)|)",
                "ax",
                "pitch",
            ),
        ][i];
        let sign = "MODEL.md 7.1-7.2: body axes FLU (x forward, y left, z up), the gyro \
                    right-handed about them, and a pendulum at rest reads phi_x = roll, \
                    phi_y = pitch";
        let by_accel = axis.reversed(Comparison::EncoderAccel);
        let gyro_accel = axis.reversed(Comparison::GyroAccelRate);
        // One column against two, or those two both reversed (an IMU turned half round
        // about z reverses gyro_x and ay together): the true angle, if logged, decides.
        let truth_phi = axis.reversed(Comparison::TruthEncoder);
        let truth_accel = axis.reversed(Comparison::TruthAccel);
        Some(match (by_accel, crate::units::reversed(gyro), gyro_accel) {
            (Some(true), Some(true), _) if truth_phi == Some(false) => format!(
                "{g} and the accelerometer's {tilt} both count the other way from {phi} and \
                 from the true {name}: is the IMU turned half round? negate {g} and {a} in \
                 the log ({sign})"
            ),
            (Some(true), Some(true), _) => format!(
                "{phi} counts the other way from the accelerometer's {tilt} and from {g}: is \
                 the encoder's axis reversed? negate {phi} in the log{or} ({sign})",
                or = if truth_phi.is_none() {
                    format!("; or, if the IMU is turned half round, negate {g} and {a}")
                } else {
                    String::new()
                }
            ),
            (Some(false) | None, Some(true), Some(true)) => format!(
                "{g} counts the other way from the encoder's d({phi})/dt and from the rate \
                 of the accelerometer's {tilt}: is the gyro's axis reversed? negate {g} in \
                 the log ({sign})"
            ),
            (Some(true), Some(false), Some(true)) if truth_accel == Some(false) => format!(
                "{phi} and {g} both count the other way from the accelerometer's {tilt} and \
                 from the true {name}: are the encoder and the gyro both reversed? negate \
                 {phi} and {g} in the log ({sign})"
            ),
            (Some(true), Some(false), Some(true)) => format!(
                "the accelerometer's {tilt} counts the other way from {phi} and {g}: is {a} \
                 reversed? negate {a} in the log{or} ({sign})",
                or = if truth_accel.is_none() {
                    format!("; or, if the encoder and the gyro both are, negate {phi} and {g}")
                } else {
                    String::new()
                }
            ),
            (None, Some(true), None) => format!(
                "{g} and the encoder's d({phi})/dt count opposite ways: one of them is \
                 reversed; negate it in the log ({sign})"
            ),
            _ => return None,
        })
    }

    /// One warning per gyro axis found in deg/s (or converted twice).
    fn findings(&self, file: &str) -> Vec<String> {
        let deg = crate::units::DEG;
        let mut out = Vec::new();
        for (i, axis) in self.axes.iter().enumerate() {
            let (gyro, phi) = [("gyro_x", "phi_x"), ("gyro_y", "phi_y")][i];
            // With the height fitted out, else the plain pair (too little curvature).
            let (f, how) = match axis.lever_fit(self.gravity) {
                Some(l) => (
                    l.fit,
                    format!(
                        "d({phi})/dt on the gyro and its second derivative, which takes out the \
                         swing of a sensor {:.1} m above the centre the body rotates about \
                         (phi ~ theta - (h / g) theta''), over {} rows below f_n / 4, R = {:.2}",
                        l.height, l.fit.samples, l.fit.correlation
                    ),
                ),
                None => match axis.fit(crate::units::Comparison::GyroEncoderRate) {
                    Some(f) => (
                        f,
                        format!(
                            "over {} rows below f_n / 4, r = {:.2}",
                            f.samples, f.correlation
                        ),
                    ),
                    None => continue,
                },
            };
            if let Some(m) = Self::sign_finding(axis, i, &f) {
                out.push(format!("{file}: {m} (least squares of {how})"));
                continue;
            }
            let unit = crate::units::unit_factor(&f);
            let what = if unit == Some(deg) {
                format!(
                    "{:.1}x the encoder's derivative d({phi})/dt: is the gyro in deg/s?",
                    f.factor
                )
            } else if unit == Some(1.0 / deg) {
                format!(
                    "1/{:.1} of the encoder's derivative d({phi})/dt: was the gyro converted \
                     to rad/s twice?",
                    1.0 / f.factor
                )
            } else {
                continue;
            };
            out.push(format!(
                "{file}: {gyro} is {what} Every estimator reading it is wrong by as much: \
                 write gyro_x, gyro_y, gyro_z in rad/s, or give --deg if every angular column \
                 (phi_x, phi_y, gyro_*, roll, pitch) is in degrees (least squares of {how})"
            ));
        }
        // Said once: what the encoders found, else what the turns say.
        if out.is_empty() {
            if let Some(f) = self.turn.fit() {
                if crate::units::unit_factor(&f) == Some(deg) {
                    out.push(format!(
                        "{file}: gyro_z is {:.1}x the yaw rate the turns imply (the lateral \
                         acceleration over the speed, a_y / v): is the gyro in deg/s? Every \
                         estimator reading it is wrong by as much: write gyro_x, gyro_y, gyro_z \
                         in rad/s, or give --deg if every angular column (phi_x, phi_y, gyro_*, \
                         roll, pitch) is in degrees (least squares over {} rows below {TURN_HZ} \
                         Hz, r = {:.2})",
                        f.factor, f.samples, f.correlation
                    ));
                }
            }
        }
        out
    }
}

/// The median step of the first rows must be a sensor rate (as the planar reader checks).
/// Most of a log flagged as wheel slip is a speed in the wrong unit, not slip: a wheel
/// slips for seconds, and a speed in km/h (3.6x) or mph (2.24x) disagrees with the
/// accelerometer on every change of speed. Measured on ride3d (seed 1, 120 s): 77 % of the
/// rows flagged with the speed in km/h (ekf3d 31.8 deg RMS); in m/s none, 3 % on
/// ride3d_slip, 1.6 % with the speed on one row in 20.
const SLIP_SHARE_WARNING: f64 = 0.1;

/// The warning for a log whose rows with a speed reading are flagged as slip beyond
/// [`SLIP_SHARE_WARNING`].
fn slip_warning(file: &str, slip_rows: u64, speed_rows: u64) -> Option<String> {
    let share = slip_rows as f64 / speed_rows.max(1) as f64;
    (speed_rows > 0 && share > SLIP_SHARE_WARNING).then(|| {
        format!(
            "{file}: wheel slip flagged on {slip_rows} of {speed_rows} rows with a speed \
             ({:.0} %): the `speed` column disagrees with the accelerometer almost \
             everywhere; is it in m/s? (km/h reads 3.6x, mph 2.24x; ekf3d and ukf3d skip it \
             while they flag slip); a gyro in deg/s or an accelerometer in g does the same",
            share * 100.0
        )
    })
}

fn check_time_unit(
    file: &str,
    head: &[Log3dRecord],
    given: Option<crate::io::TimeUnit>,
) -> anyhow::Result<()> {
    let mut steps: Vec<f64> = head
        .windows(2)
        .map(|p| p[1].t - p[0].t)
        .filter(|d| d.is_finite() && *d > 0.0)
        .collect();
    if steps.is_empty() {
        return Ok(());
    }
    steps.sort_by(f64::total_cmp);
    let median = steps[steps.len() / 2];
    let why = match given {
        Some(u) => implausible_given_unit(median, u),
        None => implausible_step(median),
    };
    match why {
        Some(why) => {
            let line = head.get(1).map_or(0, |r| r.line);
            bail!("{file}:{line}: column 1 (`t`): {why}")
        }
        None => Ok(()),
    }
}

/// A value as the log wrote it: 1e308, not 309 digits.
fn written(x: f64) -> String {
    if x.abs() >= 1e6 {
        format!("{x:e}")
    } else {
        x.to_string()
    }
}

/// Turns records into samples: units, plausibility, the time step.
struct RowInput<'a> {
    time_scale: f64,
    angle_scale: f64,
    file: &'a str,
    header: &'a [String],
    warnings: Vec<String>,
    more: u64,
    /// The sensors of the current row with an impossible reading.
    implausible: Inputs,
    /// The rig's gyro full scale \[rad/s\], if given: the gyro's bound instead of
    /// [`MAX_RATE`] (a reading at it, to [`FULL_SCALE_ROUNDING`], is clipped but real).
    gyro_full_scale: Option<f64>,
    /// The clips found in the current row.
    clipped: Clips,

    /// Clips of the gyro (when the rig gives no full scale) and of the accelerometer.
    gyro_clips: PlateauWatch<3>,
    accel_clips: PlateauWatch<3>,
    /// Truth cells (roll, pitch) beyond their range, read as missing.
    truth_refused: [u64; 2],
    /// Rows with a missing sensor cell, rows whose time does not increase, and the first
    /// [`ROW_ISSUES_LISTED`] of each said (apart from [`MAX_WARNINGS`], which they would
    /// fill before a restart is said).
    row_issues: [u64; 2],
    row_notes: Vec<String>,
    /// The truth (roll, pitch) against the encoder (phi_x, phi_y), for its unit.
    truth_fit: [Pair; 2],
}

/// The truth columns, their range in radians (MODEL.md 7: roll in -pi..pi, pitch in
/// -pi/2..pi/2) and the encoder that follows each below the pendulum's frequency.
const TRUTH: [(&str, f64, &str, &str); 2] = [
    ("roll", std::f64::consts::PI, "pi", "phi_x"),
    ("pitch", std::f64::consts::FRAC_PI_2, "pi/2", "phi_y"),
];

impl<'a> RowInput<'a> {
    fn new(setup: &Setup, file: &'a str, header: &'a [String]) -> Self {
        Self {
            time_scale: setup.time_scale,
            angle_scale: setup.angle_scale,
            file,
            header,
            warnings: Vec::new(),
            more: 0,
            implausible: Inputs::default(),
            gyro_full_scale: setup.settings.ekf.gyro.checked_full_scale(),
            clipped: Clips::default(),

            gyro_clips: PlateauWatch::new(),
            accel_clips: PlateauWatch::new(),
            truth_refused: [0; 2],
            row_issues: [0; 2],
            row_notes: Vec::new(),
            truth_fit: [Pair::default(); 2],
        }
    }

    /// True angle `x` \[rad\] of truth column `k` (0 roll, 1 pitch) when within its range,
    /// else NaN (not scored), the first one per column warned with its place. A value that
    /// would be in range in degrees says that the column looks like degrees: its cells in
    /// range would be scored as radians.
    fn truth(&mut self, line: u64, k: usize, x: f64) -> f64 {
        let (name, bound, bound_name, _) = TRUTH[k];
        if x.is_nan() || x.abs() <= bound * (1.0 + 1e-9) {
            return x;
        }
        self.truth_refused[k] += 1;
        if self.truth_refused[k] > 1 {
            return f64::NAN;
        }
        let col = self.column(name);
        let degrees = if self.angle_scale == 1.0 && x.to_radians().abs() <= bound {
            format!(
                "; the column looks like degrees, and its cells within {bound_name} would be \
                 scored as radians: the inclination errors are not to be trusted; write \
                 roll and pitch in radians (--deg reads every angular column in degrees)"
            )
        } else {
            String::new()
        };
        self.warn(format!(
            "{}:{line}: column {col} (`{name}`): {} rad is beyond {bound_name}, no {name} \
             angle (MODEL.md 7): read as missing, not scored{degrees}",
            self.file,
            written(x)
        ));
        f64::NAN
    }

    fn warn(&mut self, w: String) {
        if self.warnings.len() < MAX_WARNINGS {
            self.warnings.push(w);
        } else {
            self.more += 1;
        }
    }

    /// Says that the bank restarted `n` estimators at `line`.
    fn restart_warning(&mut self, line: u64, r: crate::bank3d::gaps::Restart3d, n: usize) {
        self.warn(format!(
            "{}:{line}: {} back after a gap of {:.3} s (longer than the restart gap {} s): \
             {n} estimators reading it restart from this row",
            self.file,
            sensor_names(r.sensors),
            r.gap,
            crate::bank::RESTART_GAP
        ));
    }

    /// Degrees found from the physics: below the pendulum's frequency the encoders follow
    /// the tilt (roll ~ phi_x, pitch ~ phi_y), so a truth 57x the encoder is in degrees
    /// (and 1/57 of it read with --deg in radians), however small the tilt.
    fn truth_unit(&self) -> Vec<String> {
        let deg = crate::units::DEG;
        let mut w = Vec::new();
        for (k, (name, _, _, phi)) in TRUTH.iter().enumerate() {
            // The encoder must move (units::MIN_MOTION) for the slope to say anything.
            let Some(f) = self.truth_fit[k].fit() else {
                continue;
            };
            let (slope, r) = (f.factor, f.correlation);
            let unit = crate::units::unit_factor(&f);
            let what = if unit == Some(deg) {
                format!("{slope:.1}x the encoder's {phi}: is `{name}` in degrees?")
            } else if unit == Some(1.0 / deg) {
                format!("1/{:.1} of the encoder's {phi}: was `{name}` read in degrees (--deg) but written in radians?", 1.0 / slope)
            } else {
                continue;
            };
            w.push(format!(
                "{}: {name} is {what} The inclination errors are not to be trusted: write roll \
                 and pitch in radians (--deg reads every angular column in degrees) (least \
                 squares over {} rows, r = {r:.2})",
                self.file,
                self.truth_fit[k].samples()
            ));
        }
        w
    }

    /// The 1-based column of `name` in the header (0 if absent), for warnings.
    fn column(&self, name: &str) -> usize {
        self.header
            .iter()
            .position(|h| h == name)
            .map_or(0, |p| p + 1)
    }

    /// `x` when plausible, else NaN and a warning naming its place.
    fn plausible(&mut self, line: u64, name: &str, x: f64, bound: f64, unit: &str) -> f64 {
        if unit == "rad/s" {
            if let Some(fs) = self.gyro_full_scale {
                return self.beyond_full_scale(line, name, x, fs);
            }
        }
        if x.abs() <= bound || x.is_nan() {
            return x;
        }
        let col = self.column(name);
        // Degrees only where the reading in degrees would be possible (1e6 is impossible
        // either way: the hint would point the user the wrong way).
        let hint = if unit == "m/s^2" || x.to_radians().abs() > bound {
            ""
        } else {
            " (in degrees? give --deg)"
        };
        let x = written(x);
        self.warn(format!(
            "{}:{line}: column {col} (`{name}`): {x} {unit} is beyond {bound} {unit}, \
             impossible: read as missing{hint}",
            self.file
        ));
        f64::NAN
    }

    /// Gyro reading `x` when within the rig's full scale `fs`, else NaN and a warning.
    fn beyond_full_scale(&mut self, line: u64, name: &str, x: f64, fs: f64) -> f64 {
        if x.abs() <= fs * (1.0 + FULL_SCALE_ROUNDING) || x.is_nan() {
            return x;
        }
        let col = self.column(name);
        self.warn(format!(
            "{}:{line}: column {col} (`{name}`): {} rad/s exceeds the full scale {fs} rad/s \
             (rig [gyro] full_scale): read as missing",
            self.file,
            written(x)
        ));
        f64::NAN
    }

    /// The sample, with its time \[s\] and the truth (NaN when absent); `next_t` is the
    /// next row's time stamp (in the log's unit), if there is one.
    fn sample(
        &mut self,
        r: &Log3dRecord,
        ahead: &VecDeque<Log3dRecord>,
        gate: &mut StepGate<f64>,
    ) -> (f64, SpatialSample<f64>, f64, f64) {
        let next_t = ahead.front().map(|n| n.t);
        let t = r.t * self.time_scale;
        let k = self.angle_scale;
        let line = r.line;
        let phi: [f64; 2] = std::array::from_fn(|i| hair_beyond_pi(r.phi[i] * k));
        let phi = [
            self.plausible(line, "phi_x", phi[0], std::f64::consts::PI, "rad"),
            self.plausible(line, "phi_y", phi[1], std::f64::consts::PI, "rad"),
        ];
        let gyro: [f64; 3] = std::array::from_fn(|i| r.gyro[i] * k);
        let gyro = [
            self.plausible(line, "gyro_x", gyro[0], MAX_RATE, "rad/s"),
            self.plausible(line, "gyro_y", gyro[1], MAX_RATE, "rad/s"),
            self.plausible(line, "gyro_z", gyro[2], MAX_RATE, "rad/s"),
        ];
        let accel = [
            self.plausible(line, "ax", r.accel[0], MAX_ACCEL, "m/s^2"),
            self.plausible(line, "ay", r.accel[1], MAX_ACCEL, "m/s^2"),
            self.plausible(line, "az", r.accel[2], MAX_ACCEL, "m/s^2"),
        ];
        // NaN out of a finite cell: the bound refused it.
        let refused =
            |raw: &[f64], v: &[f64]| raw.iter().zip(v).any(|(a, b)| !a.is_nan() && b.is_nan());
        self.implausible = Inputs {
            phi: refused(&r.phi, &phi),
            gyro: refused(&r.gyro, &gyro),
            accel: refused(&r.accel, &accel),
        };
        // A reading at the rig's full scale is its known clip, not one found here.
        let (k, fs) = (self.angle_scale, self.gyro_full_scale);
        let found = self.gyro_clips.clipped(r.gyro);
        self.clipped = Clips {
            gyro: core::array::from_fn(|i| {
                found[i] && fs.is_none_or(|fs| (r.gyro[i] * k).abs() < fs)
            }),
            accel: self.accel_clips.clipped(r.accel).contains(&true),
        };
        self.row_issues(r, t, gate);
        let dt = if self.lone_stamp(t, next_t.map(|n| n * self.time_scale), gate, line) {
            f64::NAN
        } else {
            gate.step(t)
        };
        let s = SpatialSample {
            dt,
            phi,
            gyro,
            accel,
            speed: r.speed.unwrap_or(f64::NAN),
        };
        let (roll, pitch) = (r.roll.map(|v| v * k), r.pitch.map(|v| v * k));
        let roll = roll.map_or(f64::NAN, |v| self.truth(line, 0, v));
        let pitch = pitch.map_or(f64::NAN, |v| self.truth(line, 1, v));
        self.truth_fit[0].add(s.phi[0], roll);
        self.truth_fit[1].add(s.phi[1], pitch);
        (t, s, roll, pitch)
    }

    /// Looks for clips in record `r`, read [`LOOK_AHEAD_ROWS`] before it reaches the
    /// estimators. A reading at the rig's gyro full scale is a known clip (kept, flagged by
    /// the estimators); gyro clips at an unknown full scale, or below the rig's (a range
    /// smaller than the rig says), are found in the readings.
    fn find_clips(&mut self, r: &Log3dRecord) {
        // An impossible reading (read as missing) is no clip level: a burst of them is a
        // run of identical readings that the finder would otherwise take for one.
        let possible = |x: f64, bound: f64| if x.abs() <= bound { x } else { f64::NAN };
        let k = self.angle_scale;
        let fs = self.gyro_full_scale;
        let gyro = r.gyro.map(|x| possible(x, fs.unwrap_or(MAX_RATE) / k));
        if let Some(f) = self.gyro_clips.observe(gyro) {
            let name = ["gyro_x", "gyro_y", "gyro_z"][f.axis];
            let x = f.reading * self.angle_scale;
            // A clip at the rig's full scale is the one the rig told.
            if fs.is_none_or(|fs| x.abs() < fs) {
                self.clip_warning(r.line, name, f, x, "rad/s", "[gyro] full_scale", fs);
            }
        }
        if let Some(f) = self
            .accel_clips
            .observe(r.accel.map(|x| possible(x, MAX_ACCEL)))
        {
            let name = ["ax", "ay", "az"][f.axis];
            self.clip_warning(r.line, name, f, f.reading, "m/s^2", "", None);
        }
    }

    /// Says that a run of identical readings `x` of column `name` is a clip, at an unknown
    /// full scale or below the rig's `told`.
    #[allow(clippy::too_many_arguments)]
    fn clip_warning(
        &mut self,
        line: u64,
        name: &str,
        f: NewLevel,
        x: f64,
        unit: &str,
        rig: &str,
        told: Option<f64>,
    ) {
        let col = self.column(name);
        let hint = if rig.is_empty() {
            String::new()
        } else {
            format!("; if it is the range of the sensor, give it as the rig's {rig}")
        };
        let what = match told {
            Some(fs) => format!(
                "a clip below the rig's {rig} {fs} {unit}: the sensor's range is smaller \
                 than the rig says"
            ),
            None => "a clip at an unknown full scale".to_string(),
        };
        self.warn(format!(
            "{}:{line}: column {col} (`{name}`): {x} {unit} on {} rows in a row up to here, \
             which a sensor with noise never writes: {what}; readings at +-{} {unit} are \
             clipped (flagged saturated){hint}",
            self.file,
            f.rows,
            x.abs()
        ));
    }

    /// Whether `t` is a lone glitched stamp: after the next row's, which itself follows the
    /// last accepted one (so the next row, not this one, continues the clock).
    /// Says what the reader flagged on row `r` (time `t` \[s\]): a missing sensor cell, a
    /// time that does not increase; as the planar reader says it (the rows are flagged
    /// either way, but `--flags` is not every user's first look).
    fn row_issues(&mut self, r: &Log3dRecord, t: f64, gate: &StepGate<f64>) {
        if r.issues.missing {
            let cells = [
                ("t", r.t),
                ("phi_x", r.phi[0]),
                ("phi_y", r.phi[1]),
                ("gyro_x", r.gyro[0]),
                ("gyro_y", r.gyro[1]),
                ("gyro_z", r.gyro[2]),
                ("ax", r.accel[0]),
                ("ay", r.accel[1]),
                ("az", r.accel[2]),
            ];
            let names: Vec<String> = cells
                .iter()
                .filter(|(_, v)| v.is_nan())
                .map(|(n, _)| format!("`{n}`"))
                .collect();
            self.row_issues[0] += 1;
            if self.row_issues[0] <= ROW_ISSUES_LISTED {
                self.row_notes.push(format!(
                    "{}:{}: {} empty, nan, infinite or absent: read as missing, the \
                     estimators reading it hold and flag the sample",
                    self.file,
                    r.line,
                    names.join(", ")
                ));
            }
        }
        if let (true, Some(last)) = (r.issues.time_not_increasing, gate.last()) {
            // After a lone stamp (held, said) the row is behind it but not behind `last`.
            if t.is_finite() && t <= last {
                let what = if t == last { "repeated" } else { "goes back" };
                self.row_issues[1] += 1;
                if self.row_issues[1] > ROW_ISSUES_LISTED {
                    return;
                }
                self.row_notes.push(format!(
                    "{}:{}: column {} (`t`): time {what} ({last} then {t} s): the row is kept, \
                     the estimators holding their estimate, flagged bad_time_step, until the \
                     time passes {last} s again",
                    self.file,
                    r.line,
                    self.column("t")
                ));
            }
        }
    }

    fn lone_stamp(&mut self, t: f64, next: Option<f64>, gate: &StepGate<f64>, line: u64) -> bool {
        let (Some(next), Some(last)) = (next, gate.last()) else {
            return false;
        };
        let lone = t > next && next > last;
        if lone {
            self.warn(format!(
                "{}:{line}: column 1 (`t`): {t} s is after the next row's {next} s: a lone \
                 bad time stamp, this row is held (flagged bad_time_step)",
                self.file
            ));
        }
        lone
    }

    fn warnings(&self) -> Vec<String> {
        let mut w = self.warnings.clone();
        w.extend(self.row_notes.iter().cloned());
        for (n, what) in self.row_issues.iter().zip([
            "with a missing sensor cell (flagged sample_missing)",
            "whose time does not increase (flagged bad_time_step)",
        ]) {
            if *n > ROW_ISSUES_LISTED {
                w.push(format!(
                    "{}: {n} rows {what}, the first {ROW_ISSUES_LISTED} listed",
                    self.file
                ));
            }
        }
        for (k, (name, _, bound_name, _)) in TRUTH.iter().enumerate() {
            if self.truth_refused[k] > 1 {
                w.push(format!(
                    "{}: {} cells of `{name}` beyond {bound_name} read as missing, not scored",
                    self.file, self.truth_refused[k]
                ));
            }
        }
        w.extend(self.truth_unit());
        if self.more > 0 {
            w.push(format!(
                "{} more warnings (impossible readings, restarts, bad time stamps)",
                self.more
            ));
        }
        w
    }
}

/// The 3-D log's columns of `sensors`, for messages.
fn sensor_names(sensors: Inputs) -> String {
    [
        (sensors.phi, "phi_x/phi_y"),
        (sensors.gyro, "gyro_x/y/z"),
        (sensors.accel, "ax/ay/az"),
    ]
    .iter()
    .filter(|(on, _)| *on)
    .map(|(_, n)| *n)
    .collect::<Vec<_>>()
    .join(", ")
}

/// The inclination error table (MODEL.md 7.9) in degrees.
fn score_table(p: &Pass) -> String {
    let n = p.scores.first().map_or(0, |s| s.count() + s.missing());
    let score_from = p.window.from;
    let mut t = format!(
        "inclination error [deg], {}:\n\
         {:<12} {:>10} {:>10} {:>10} {:>8}\n",
        p.window.heading(n),
        "estimator",
        "RMS",
        "max",
        "mean",
        "missing"
    );
    for (name, s) in p.names.iter().zip(&p.scores) {
        t.push_str(&format!(
            "{name:<12} {:>10.5} {:>10.5} {:>10.5} {:>8}\n",
            s.rms().to_degrees(),
            s.max().to_degrees(),
            s.mean().to_degrees(),
            s.missing()
        ));
    }
    if p.scores.iter().any(|s| s.missing() > 0) {
        t.push_str(
            "missing: rows with the truth but no estimate (flagged; e.g. a sensor missing for \
             longer than the restart gap), left out of RMS, max and mean\n",
        );
    }
    if n == 0 {
        t.push_str(&format!(
            "no row scored: the truth ends before t0 + {score_from} s; score earlier with \
             --score-from SECONDS\n"
        ));
    }
    t.pop();
    t
}

/// How far beyond +-pi \[rad\] an encoder reading is taken for +-pi as a logger rounded
/// it (`-3.1416` is 7e-6 beyond; `3.142`, 4e-4): such a reading is wrapped into (-pi, pi],
/// not read as missing.
const PI_ROUNDING: f64 = 1e-3;

/// An encoder angle a hair beyond +-pi (within [`PI_ROUNDING`]) wrapped into (-pi, pi];
/// any other value as it is.
fn hair_beyond_pi(x: f64) -> f64 {
    use std::f64::consts::{PI, TAU};
    if x.abs() > PI && x.abs() <= PI + PI_ROUNDING {
        x - x.signum() * TAU
    } else {
        x
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// -pi printed to four decimals is wrapped, not dropped; a reading well beyond stays
    /// beyond (the plausibility check reads it as missing and says so).
    #[test]
    fn an_encoder_a_hair_beyond_pi_is_wrapped() {
        let pi = std::f64::consts::PI;
        // As a logger prints -pi and pi rounded.
        let (four, three): (f64, f64) = ("-3.1416".parse().unwrap(), "3.142".parse().unwrap());
        let w = hair_beyond_pi(four);
        assert!(w > pi - 1e-4 && w <= pi, "{w}");
        let w = hair_beyond_pi(three);
        assert!(w < -pi + 1e-3 && w > -pi, "{w}");
        assert_eq!(hair_beyond_pi(pi), pi);
        assert_eq!(hair_beyond_pi(0.5), 0.5);
        assert_eq!(hair_beyond_pi(pi + 0.1), pi + 0.1);
        assert!(hair_beyond_pi(f64::NAN).is_nan());
    }
}

//! The 3-D pass (MODEL.md 7.6), shared by `estimate`, `report`, `stream` and `batch`: a
//! log with the columns t, phi_x, phi_y, gyro_x, gyro_y, gyro_z, ax, ay, az (speed, roll, pitch
//! optional) through the 3-D bank ([`crate::bank::spatial::REGISTRY3D`]).
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
//! the readings themselves ([`crate::io::plateau`],
//! [`LOOK_AHEAD_ROWS`](crate::io::plateau::LOOK_AHEAD_ROWS) rows ahead of the estimators),
//! warned once per level, and every reading at it flagged `saturated` by the estimators
//! reading that sensor ([`Bank3d::update_clipped`]); a clip is no gap. A
//! sensor missing for longer than the bank's restart gap (0.5 s) restarts the estimators
//! reading it, with a warning. A cell that is not a number stops the run with its file,
//! line and column; so does a time column whose steps no sensor rate explains.
use std::fs::File;
use std::io::{BufRead, BufReader};
use std::path::Path;

use pendtilt_core::spatial::{Attitude, SpatialSample};

use super::LogColumns;
use crate::bank::spatial::score::Inclination;
use crate::bank::spatial::Bank3d;
use crate::io::output::NamedPath;
use crate::io::plausibility::{DEFAULT_ACCEL_LIMIT, DEFAULT_GYRO_LIMIT};
use crate::io::{Column3d, Log3dReader, Log3dRecord};

mod checks;
mod gyro_units;
mod rows;
mod run;
mod scales;
mod setup;
mod turn;

use checks::check_time_unit;
use run::Run;
pub use scales::{read_si, Scales3d};
pub use setup::{setup, Setup};

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

/// True when the first header line of the file at `path` has every 3-D column (comment and blank
/// lines before it skipped). An unreadable file is not 3-D: the planar reader then reports it. Only
/// a regular file is peeked at: a pipe (`<(cat log.csv)`, `/dev/stdin`, `-`) has its header peeked
/// at instead ([`LogSource`](crate::io::input::LogSource)), as reading its first lines here would
/// take them from the reader that follows.
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

impl Options3d<'_> {
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
pub fn pass_on<R: BufRead>(
    mut log: Log3dReader<R>,
    file: &str,
    opts: &Options3d,
    setup: &Setup,
    quaternion: bool,
    sink: &mut dyn Sink3d,
    feed: Feed,
) -> anyhow::Result<Pass> {
    let bank = Bank3d::new(&setup.settings, opts.only).map_err(anyhow::Error::msg)?;
    let names = bank.names();
    let truth = log.has("roll") && log.has("pitch");
    header_notices(&log, file, opts, setup);
    let with_q: Vec<bool> = (0..names.len())
        .map(|i| quaternion && bank.has_quaternion(i))
        .collect();
    sink.start(&names, &with_q, truth)?;
    let live = feed == Feed::Live;
    let head = read_head(&mut log, if live { 0 } else { HEAD_ROWS })?;
    if !live {
        check_time_unit(file, &head, setup.time_given)?;
    }
    let header: Vec<String> = log.header().to_vec();
    let mut run = Run::new(bank, truth, setup, file, &header, quaternion, live);
    let mut head = head.into_iter();
    loop {
        run.read_ahead(&mut log, &mut head, opts, sink)?;
        let Some(r) = run.ahead.pop_front() else {
            break;
        };
        run.row(r, sink)?;
    }
    run.finish(&mut log)
}

/// Says what the header tells before any row: a truth named with its unit, the columns
/// ignored, and what the speed column (or its absence) means for the estimators.
fn header_notices<R: BufRead>(log: &Log3dReader<R>, file: &str, opts: &Options3d, setup: &Setup) {
    // A truth named with its unit (`roll_deg`) is not read: say so, with the fix.
    let line = log.header_line();
    if let Some(h) = crate::io::unit_named_3d_hint(&["roll", "pitch"], log.header(), file, line) {
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
}

/// The first `n` records of `log` (fewer if it ends first).
fn read_head<R: BufRead>(log: &mut Log3dReader<R>, n: usize) -> anyhow::Result<Vec<Log3dRecord>> {
    let mut head = Vec::with_capacity(n);
    while head.len() < n {
        match log.next_record()? {
            Some(r) => head.push(r),
            None => break,
        }
    }
    Ok(head)
}

/// The inclination error table (MODEL.md 7.9) in degrees.
pub fn score_table(p: &Pass) -> String {
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

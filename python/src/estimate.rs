//! `pendtilt.estimate`: a log (a file, or columns in memory) through the estimators, as
//! `pendtilt estimate` runs it, into NumPy arrays.
//!
//! The options are the command's (its command line, parsed by its definitions). A planar
//! log goes through [`pendtilt::pipeline::run_parallel`] with the reader, the bank and
//! the checks the command builds; the estimates are kept rather than formatted. A 3-D log
//! goes through [`pendtilt::pipeline::spatial::pass`] (the command's pass) into arrays, a
//! table in memory through [`pendtilt::pipeline::spatial::pass_on`] over its columns read
//! as CSV text. Either way every estimate is the command's, bit for bit.
use std::path::{Path, PathBuf};

use numpy::{IntoPyArray, PyReadonlyArray1};
use pendtilt::cli::estimate3d;
use pendtilt::cli::Command;
use pendtilt::io::{Column, Log3dReader, LogReader, LogRecord, LogWarning, ReaderOptions};
use pendtilt::pipeline;
use pendtilt::pipeline::spatial::{self, Feed, Row, Sink3d};
use pendtilt_core::Estimate;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::source::ColumnsSource;
use crate::{parse, py_err, PendtiltError};

/// The `estimate` arguments of a parsed command line.
fn estimate_args(argv: &[String]) -> PyResult<pendtilt::cli::estimate::Args> {
    match parse(argv)?.command {
        Command::Estimate(a) => Ok(a),
        _ => Err(PendtiltError::new_err("not an estimate command line")),
    }
}

/// Runs `pendtilt estimate` as parsed from `argv` (`["pendtilt", "estimate", LOG, "-o",
/// "-", ...]`; the output is not written) and returns what it computed as a dict. With
/// `names` and `columns` the log is that table (LOG only names it in messages), else the
/// file LOG.
#[pyfunction]
#[pyo3(signature = (argv, names=None, columns=None))]
pub fn estimate<'py>(
    py: Python<'py>,
    argv: Vec<String>,
    names: Option<Vec<String>>,
    columns: Option<Vec<PyReadonlyArray1<'py, f64>>>,
) -> PyResult<Bound<'py, PyDict>> {
    let args = estimate_args(&argv)?;
    let Some((names, columns)) = names.zip(columns) else {
        let map = &args.bank.columns.map;
        return if spatial::is_3d_log(&args.log, map) || !map.spatial_only().is_empty() {
            spatial(py, &args, None)
        } else {
            planar(py, &args, None)
        };
    };
    if names.len() != columns.len() {
        return Err(PendtiltError::new_err(format!(
            "{} column names for {} columns",
            names.len(),
            columns.len()
        )));
    }
    let slices = columns
        .iter()
        .map(|c| c.as_slice())
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| PendtiltError::new_err(format!("a column is not contiguous: {e}")))?;
    if let Some(c) = slices.iter().find(|c| c.len() != slices[0].len()) {
        return Err(PendtiltError::new_err(format!(
            "the columns differ in length ({} and {} rows)",
            slices[0].len(),
            c.len()
        )));
    }
    let map = &args.bank.columns.map;
    if pendtilt::io::is_3d_header(&map.rename_spatial(&names)) || !map.spatial_only().is_empty() {
        return spatial(py, &args, Some((&names, slices)));
    }
    planar(py, &args, Some((&names, slices)))
}

/// Writes a table as the CSV the readers read (the numbers in their shortest exact form).
fn write_table(path: &Path, names: &[String], columns: &[&[f64]]) -> std::io::Result<()> {
    use std::io::Write;
    let mut src = ColumnsSource::new(names, columns.to_vec());
    let mut out = std::io::BufWriter::new(std::fs::File::create(path)?);
    std::io::copy(&mut src, &mut out)?;
    out.flush()
}

/// Writes columns as a CSV log at `path`: a header of `names`, each number in the
/// shortest form that reads back to the same value (`NaN` when missing), as the
/// command writes its outputs.
#[pyfunction]
pub fn write_csv(
    py: Python<'_>,
    path: PathBuf,
    names: Vec<String>,
    columns: Vec<PyReadonlyArray1<'_, f64>>,
) -> PyResult<()> {
    let slices = columns
        .iter()
        .map(|c| c.as_slice())
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| PendtiltError::new_err(format!("a column is not contiguous: {e}")))?;
    py.detach(|| write_table(&path, &names, &slices))
        .map_err(|e| {
            py_err(anyhow::Error::from(e).context(format!("cannot write {}", path.display())))
        })
}

/// What a planar pass gave, before it becomes Python objects.
struct PlanarOut {
    names: Vec<&'static str>,
    t: Vec<f64>,
    theta: Option<Vec<f64>>,
    estimates: Vec<Vec<f64>>,
    flags: Vec<Vec<u16>>,
    summary: pipeline::PassSummary,
    warnings: Vec<String>,
    notes: Vec<String>,
    warning_count: u64,
}

/// The planar branch of `pendtilt estimate`: the command's rig, reader, bank and pass
/// ([`pendtilt::cli::estimate`]), the estimates kept in memory. `table`: the log's
/// columns, else the file `args.log`.
fn planar<'py>(
    py: Python<'py>,
    args: &pendtilt::cli::estimate::Args,
    table: Option<(&[String], Vec<&[f64]>)>,
) -> PyResult<Bound<'py, PyDict>> {
    spatial::refuse_3d_options(
        &[
            ("--quaternion", args.quaternion),
            ("--scenario", args.scenario.is_some()),
        ],
        &args.log,
    )
    .map_err(py_err)?;
    let out = py
        .detach(|| -> anyhow::Result<PlanarOut> {
            let opts = &args.bank;
            let mut notes = Vec::new();
            // The rig's doubts: warnings, as the command prints them.
            let mut warnings = Vec::new();
            let rig = match &opts.params {
                Some(p) => {
                    let rig = pendtilt::config::RigConfig::load(p)?;
                    for d in rig.doubts() {
                        warnings.push(format!("{}: {d}", p.display()));
                    }
                    rig
                }
                None => {
                    notes.push(
                        "note: no --params: using the default rig of MODEL.md section 5".into(),
                    );
                    pendtilt::config::RigConfig::default()
                }
            };
            let ropts = opts.reader_options(&rig);
            match table {
                Some((names, cols)) => {
                    // Only the columns the reader reads are formatted: the rest would be
                    // ignored anyway.
                    let origin = args.log.display().to_string();
                    let source = ColumnsSource::new(names, cols.clone());
                    let log = LogReader::new(source, &origin, ropts.clone())?;
                    run_planar(log, args, &rig, (notes, warnings), Some(&cols), &ropts)
                }
                None => {
                    let log = LogReader::open(&args.log, ropts.clone())?;
                    // (A file, not standard input: the Python layer gives paths.)
                    run_planar(log, args, &rig, (notes, warnings), None, &ropts)
                }
            }
        })
        .map_err(py_err)?;
    planar_dict(py, out)
}

/// The bank over `log` (as [`pendtilt::cli::options::BankOptions::bank`] builds it, its
/// notices kept), then the command's pass with the estimates kept.
fn run_planar<R: std::io::BufRead + Send>(
    mut log: LogReader<R>,
    args: &pendtilt::cli::estimate::Args,
    rig: &pendtilt::config::RigConfig,
    (mut notes, mut warnings): (Vec<String>, Vec<String>),
    table: Option<&Vec<&[f64]>>,
    ropts: &ReaderOptions,
) -> anyhow::Result<PlanarOut> {
    let opts = &args.bank;
    let mut bank =
        pendtilt::cli::options::bank_for(rig, &log, opts.only.as_deref(), |n| notes.push(n))?;
    let names: Vec<&'static str> = bank.names().to_vec();
    let width = names.len();
    let with_theta = log.columns().has(Column::Theta);
    let scale = if opts.out_deg {
        180.0 / std::f64::consts::PI
    } else {
        1.0
    };
    let mut estimates: Vec<Vec<f64>> = vec![Vec::new(); width];
    let mut flags: Vec<Vec<u16>> = vec![Vec::new(); width];
    // From a file, t and theta as the pass read them (a table has them already).
    let from_file = table.is_none();
    let (mut t_read, mut theta_read) = (Vec::new(), Vec::new());
    let summary = {
        let warn = |w: &LogWarning| warnings.push(w.to_string());
        let each = |_: u64, rec: &LogRecord, est: &[Estimate<f64>]| {
            for ((e, v), f) in est.iter().zip(&mut estimates).zip(&mut flags) {
                v.push(e.theta * scale);
                f.push(e.flags.bits());
            }
            if from_file {
                t_read.push(rec.t);
                if with_theta {
                    theta_read.push(rec.theta.unwrap_or(f64::NAN));
                }
            }
        };
        let score_from = args.score_from;
        pipeline::run_parallel(
            &mut log,
            &mut bank,
            None::<&mut pendtilt::io::EstimatesWriter<std::io::Sink>>,
            score_from,
            warn,
            each,
        )?
    };
    let rows = summary.rows as usize;
    // t and theta as the reader read them: with the table's columns, in SI units (and
    // read as missing where the reader reads them so); from a file, as the pass read them.
    let (t, theta) = match table {
        Some(cols) => table_time_and_truth(&log, cols, rows, ropts),
        None => (t_read, with_theta.then_some(theta_read)),
    };
    let theta = theta.map(|v| v.into_iter().map(|x| x * scale).collect());
    Ok(PlanarOut {
        names,
        t,
        theta,
        estimates,
        flags,
        warning_count: log.summary().total_warnings(),
        summary,
        warnings,
        notes,
    })
}

/// `t` and `theta` (when the log has it) of the table's columns `cols`, their first
/// `rows` in SI units, read as missing where the reader reads them so.
fn table_time_and_truth<R: std::io::BufRead>(
    log: &LogReader<R>,
    cols: &[&[f64]],
    rows: usize,
    ropts: &ReaderOptions,
) -> (Vec<f64>, Option<Vec<f64>>) {
    let col = |c: Column| -> Option<Vec<f64>> {
        let pos = log.columns().status(c).position?;
        Some(
            cols[pos][..rows]
                .iter()
                .map(|&x| si(log, ropts, c, x))
                .collect(),
        )
    };
    let with_theta = log.columns().has(Column::Theta);
    (
        col(Column::T).unwrap_or_default(),
        if with_theta { col(Column::Theta) } else { None },
    )
}

/// `raw` of column `c` as the reader reads it: in SI units (`--time-unit`, `--deg`,
/// `--negate`), NaN when not finite or impossible (its plausibility bounds).
fn si<R: std::io::BufRead>(log: &LogReader<R>, ropts: &ReaderOptions, c: Column, raw: f64) -> f64 {
    if !raw.is_finite() {
        return f64::NAN;
    }
    let mut scale = 1.0;
    if c == Column::T {
        if let Some(u) = ropts.time_unit {
            scale = u.seconds();
        }
    }
    if log.columns().status(c).degrees {
        scale = std::f64::consts::PI / 180.0;
    }
    if ropts.negate.contains(c) {
        scale = -scale;
    }
    let value = raw * scale;
    if ropts.limits.check(c, value, raw).is_some() {
        f64::NAN
    } else {
        value
    }
}

fn planar_dict(py: Python<'_>, out: PlanarOut) -> PyResult<Bound<'_, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("model", "planar")?;
    d.set_item("names", out.names.clone())?;
    d.set_item("rows", out.summary.rows)?;
    d.set_item("t", out.t.into_pyarray(py))?;
    d.set_item("theta", out.theta.map(|v| v.into_pyarray(py)))?;
    let est = PyDict::new(py);
    let flags = PyDict::new(py);
    for ((n, v), f) in out.names.iter().zip(out.estimates).zip(out.flags) {
        est.set_item(n, v.into_pyarray(py))?;
        flags.set_item(n, f.into_pyarray(py))?;
    }
    d.set_item("estimates", est)?;
    d.set_item("flags", flags)?;
    let errors = out.summary.errors.as_ref().map(|errors| {
        errors
            .iter()
            .map(|(n, e)| (n.clone(), (e.rms(), e.max_abs, e.count, e.missing)))
            .collect::<Vec<_>>()
    });
    d.set_item("errors", errors)?;
    d.set_item(
        "error_table",
        out.summary
            .errors
            .as_ref()
            .map(|e| pipeline::error_table(e, &out.summary.window)),
    )?;
    d.set_item("score_from", out.summary.window.from)?;
    d.set_item("restarts", out.summary.restarts)?;
    d.set_item("warnings", out.warnings)?;
    d.set_item("warning_count", out.warning_count)?;
    d.set_item("notes", out.notes)?;
    Ok(d)
}

/// The 3-D pass's rows, kept.
#[derive(Default)]
struct Memory {
    names: Vec<&'static str>,
    quaternion: Vec<bool>,
    truth: bool,
    scale: f64,
    t: Vec<f64>,
    roll: Vec<Vec<f64>>,
    pitch: Vec<Vec<f64>>,
    quats: Vec<[Vec<f64>; 4]>,
    flags: Vec<Vec<u16>>,
    true_roll: Vec<f64>,
    true_pitch: Vec<f64>,
}

impl Sink3d for Memory {
    fn start(
        &mut self,
        names: &[&'static str],
        quaternion: &[bool],
        truth: bool,
    ) -> anyhow::Result<()> {
        self.names = names.to_vec();
        self.quaternion = quaternion.to_vec();
        self.truth = truth;
        let n = names.len();
        self.roll = vec![Vec::new(); n];
        self.pitch = vec![Vec::new(); n];
        self.quats = (0..n).map(|_| Default::default()).collect();
        self.flags = vec![Vec::new(); n];
        Ok(())
    }

    fn row(&mut self, r: Row) -> anyhow::Result<()> {
        // As the 3-D estimates writer writes them.
        self.t.push(r.t);
        for (i, e) in r.est.iter().enumerate() {
            self.roll[i].push(e.roll * self.scale);
            self.pitch[i].push(e.pitch * self.scale);
            self.flags[i].push(e.flags.bits());
            if self.quaternion[i] {
                for (k, x) in r.quats[i].unwrap_or([f64::NAN; 4]).into_iter().enumerate() {
                    self.quats[i][k].push(x);
                }
            }
        }
        if self.truth {
            self.true_roll.push(r.truth.0 * self.scale);
            self.true_pitch.push(r.truth.1 * self.scale);
        }
        Ok(())
    }
}

/// Each 3-D estimator's roll, pitch, flags and quaternion (when it has one), moved from
/// `mem` into `d` as arrays.
fn estimator_arrays(py: Python<'_>, d: &Bound<'_, PyDict>, mem: &mut Memory) -> PyResult<()> {
    let roll = PyDict::new(py);
    let pitch = PyDict::new(py);
    let flags = PyDict::new(py);
    let quats = PyDict::new(py);
    for (i, n) in mem.names.iter().enumerate() {
        roll.set_item(n, std::mem::take(&mut mem.roll[i]).into_pyarray(py))?;
        pitch.set_item(n, std::mem::take(&mut mem.pitch[i]).into_pyarray(py))?;
        flags.set_item(n, std::mem::take(&mut mem.flags[i]).into_pyarray(py))?;
        if mem.quaternion[i] {
            let q = std::mem::take(&mut mem.quats[i]);
            let [w, x, y, z] = q.map(|v| v.into_pyarray(py));
            quats.set_item(n, (w, x, y, z))?;
        }
    }
    d.set_item("roll", roll)?;
    d.set_item("pitch", pitch)?;
    d.set_item("flags", flags)?;
    d.set_item("quaternion", quats)?;
    Ok(())
}

/// The 3-D branch of `pendtilt estimate` ([`pendtilt::cli::estimate3d`]): its setup and
/// pass, the rows kept in memory.
fn spatial<'py>(
    py: Python<'py>,
    args: &pendtilt::cli::estimate::Args,
    table: Option<(&[String], Vec<&[f64]>)>,
) -> PyResult<Bound<'py, PyDict>> {
    let b = &args.bank;
    // The setup's notices go to standard error, as the command's.
    let opts = estimate3d::options(args, &args.log, None);
    let (pass, mut mem, score_from) = py
        .detach(|| -> anyhow::Result<_> {
            let setup = spatial::setup(&opts)?;
            let mut mem = Memory {
                scale: if b.out_deg {
                    180.0 / std::f64::consts::PI
                } else {
                    1.0
                },
                ..Memory::default()
            };
            let pass = match table {
                // The columns read as the 3-D reader reads a file of them.
                Some((names, cols)) => {
                    let file = args.log.display().to_string();
                    let renames = b.columns.map.spatial();
                    let source = ColumnsSource::new(names, cols);
                    let log = Log3dReader::new_mapped(source, &file, renames)?;
                    let q = args.quaternion;
                    spatial::pass_on(log, &file, &opts, &setup, q, &mut mem, Feed::File)?
                }
                None => spatial::pass(&opts, &setup, args.quaternion, &mut mem)?,
            };
            let from = pass.window.from;
            Ok((pass, mem, from))
        })
        .map_err(py_err)?;
    let d = PyDict::new(py);
    d.set_item("model", "3d")?;
    d.set_item("names", mem.names.clone())?;
    d.set_item("rows", pass.rows)?;
    d.set_item("t", std::mem::take(&mut mem.t).into_pyarray(py))?;
    estimator_arrays(py, &d, &mut mem)?;
    if mem.truth {
        d.set_item(
            "truth",
            (
                mem.true_roll.into_pyarray(py),
                mem.true_pitch.into_pyarray(py),
            ),
        )?;
        let scores: Vec<_> = pass
            .names
            .iter()
            .zip(&pass.scores)
            .map(|(n, s)| {
                (
                    n.to_string(),
                    (s.rms(), s.max(), s.mean(), s.count(), s.missing()),
                )
            })
            .collect();
        d.set_item("scores", scores)?;
    } else {
        d.set_item("truth", py.None())?;
        d.set_item("scores", py.None())?;
    }
    d.set_item("score_from", score_from)?;
    d.set_item("warning_count", pass.warnings.len())?;
    d.set_item("warnings", pass.warnings)?;
    d.set_item("notes", Vec::<String>::new())?;
    Ok(d)
}

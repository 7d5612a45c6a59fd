//! The planar pass: a planar log through the bank ([`crate::bank`]), one estimate row per
//! log row, on this thread ([`run`]) or with reading, estimating and writing on three
//! ([`run_parallel`]).
//!
//! A clip of the gyro or the accelerometer at a full scale the rig does not give is found
//! in the readings themselves ([`crate::io::plateau`], as on 3-D logs), warned once per
//! level with its line and column, and every reading at it taken as at a known full scale
//! ([`Bank::update_clipped`]): flagged `saturated` by the estimators reading it.
use std::io::{BufRead, Write};
use std::sync::mpsc;

use pendtilt_core::Estimate;

use super::{ClipFinder, ErrorStats, PassSummary, Scorer};
use crate::bank::planar::check_settings_against_rate;
use crate::bank::planar::{Bank, Inputs, Restart};
use crate::io::plateau::LOOK_AHEAD_ROWS;
use crate::io::{Column, EstimatesWriter, LogError, LogReader, LogRecord, LogWarning, WarningKind};
use crate::units::Finding;

/// Reads every row of `log`, runs `bank` on it, writes one row per input row to `out` (when given,
/// flushing after each row if `flush_each`), hands each reader warning to `warn`, and accumulates
/// errors against `theta` when the log has it, from `score_from` \[s\] after the first row's time
/// on (None: the rule of [`Window::resolve`](super::Window::resolve)). Clips are found
/// [`LOOK_AHEAD_ROWS`] rows ahead of the estimators, or, when `flush_each` (live input: nothing is
/// read ahead), from the row that completes their run on. `each` is called after each row with the
/// rows so far, the row as read and the estimates (not for a malformed line of a live stream).
pub fn run<R: BufRead, W: Write>(
    log: &mut LogReader<R>,
    bank: &mut Bank,
    mut out: Option<&mut EstimatesWriter<W>>,
    flush_each: bool,
    score_from: Option<f64>,
    mut warn: impl FnMut(&LogWarning),
    mut each: impl FnMut(u64, &LogRecord, &[Estimate<f64>]),
) -> Result<PassSummary, PassError> {
    let mut pass = Pass::new(bank, log, score_from);
    let look_ahead = if flush_each { 0 } else { LOOK_AHEAD_ROWS };
    let mut clips = ClipFinder::new(log, bank.settings(), look_ahead);
    // A read error ends the log: the rows held before it are still run and written.
    let mut error = None;
    let mut end = false;
    loop {
        // Past the end (or an error) only the rows held are left.
        let read = if end { Ok(None) } else { log.next_record() };
        let read = match read {
            Ok(r) => r,
            // A live stream goes on after a malformed line: it is said, and its output row
            // is NaN, flagged bad_line (one output row per input line still).
            Err(e) if flush_each && e.is_one_line() => {
                warn(&LogWarning {
                    file: e.file.clone(),
                    line: e.line.unwrap_or(0),
                    column: None,
                    header: None,
                    kind: WarningKind::BadLine,
                    message: format!(
                        "{}: the line is skipped; its output row is NaN, flagged bad_line",
                        e.what()
                    ),
                });
                log.resume_after(&e);
                pass.bad_line(bank, out.as_deref_mut())?;
                continue;
            }
            Err(e) => {
                error = Some(e);
                None
            }
        };
        for w in log.drain_warnings() {
            warn(&w);
        }
        end = read.is_none();
        let next = match read {
            Some(rec) => clips.push(rec),
            None => clips.pop(),
        };
        for w in clips.drain_warnings() {
            warn(&w);
        }
        let Some((rec, clipped)) = next else {
            if end {
                break;
            }
            continue;
        };
        pass.row(
            &rec,
            clipped,
            bank,
            out.as_deref_mut(),
            flush_each,
            &mut each,
            &mut warn,
        )?;
    }
    if let Some(e) = error {
        return Err(e.into());
    }
    pass.finish(bank, out, &mut warn, log.unit_findings().to_vec())
}

/// Rows the reader thread of [`run_parallel`] hands over at a time.
const BATCH_ROWS: usize = 4096;

/// Rows read by the reader thread, with the warnings they raised and the error that
/// stopped it, if one did.
struct Batch {
    records: Vec<LogRecord>,
    warnings: Vec<LogWarning>,
    error: Option<LogError>,
    /// No batch follows (the end of the log, or an error).
    last: bool,
}

/// Estimates of a batch of rows on their way to the writer thread of [`run_parallel`].
#[derive(Default)]
struct Rows {
    t: Vec<f64>,
    theta: Vec<Option<f64>>,
    // `t.len()` rows of one estimate per bank output.
    estimates: Vec<Estimate<f64>>,
}

impl Rows {
    fn clear(&mut self) {
        self.t.clear();
        self.theta.clear();
        self.estimates.clear();
    }

    fn push(&mut self, rec: &LogRecord, est: &[Estimate<f64>]) {
        self.t.push(rec.t);
        self.theta.push(rec.theta);
        self.estimates.extend_from_slice(est);
    }
}

/// [`run`] on three threads, for files: one reads and parses the log, one runs the bank,
/// one formats and writes the estimates. Each of the three is about a third of the work,
/// so on two cores the pass takes about half the time of [`run`]. Memory stays bounded
/// (a few batches of 4096 rows in flight, their vectors recycled). The rows,
/// estimates and errors are the same as [`run`]'s (test
/// `the_parallel_pass_gives_the_same_rows_errors_and_statistics`); a reader warning
/// reaches `warn` before the rows of its batch rather than between rows.
pub fn run_parallel<R: BufRead + Send, W: Write + Send>(
    log: &mut LogReader<R>,
    bank: &mut Bank,
    out: Option<&mut EstimatesWriter<W>>,
    score_from: Option<f64>,
    mut warn: impl FnMut(&LogWarning),
    mut each: impl FnMut(u64, &LogRecord, &[Estimate<f64>]),
) -> Result<PassSummary, PassError> {
    let mut pass = Pass::new(bank, log, score_from);
    let mut clips = ClipFinder::new(log, bank.settings(), LOOK_AHEAD_ROWS);
    let width = bank.names().len();
    let reader = &mut *log;
    std::thread::scope(|scope| {
        let (tx, rx) = mpsc::sync_channel::<Batch>(2);
        let (recycle, recycled) = mpsc::channel::<Vec<LogRecord>>();
        scope.spawn(move || read_batches(reader, &tx, &recycled));
        let (to_writer, rows_in) = mpsc::sync_channel::<Rows>(2);
        let (rows_back, spare_rows) = mpsc::channel::<Rows>();
        let writer = out.map(|w| scope.spawn(move || write_rows(w, rows_in, &rows_back, width)));
        let mut result = Ok(());
        for batch in rx {
            for w in &batch.warnings {
                warn(w);
            }
            let mut rows = spare_rows.try_recv().unwrap_or_default();
            rows.clear();
            estimate_batch::<W>(
                &batch, &mut clips, &mut pass, bank, &mut rows, &mut warn, &mut each,
            )?;
            // A send fails when the writer stopped on an error: it is reported below.
            if writer.is_some() && to_writer.send(rows).is_err() {
                break;
            }
            if let Some(e) = batch.error {
                result = Err(PassError::Read(e));
                break;
            }
            // The reader may have finished already: then the vector is simply dropped.
            let _ = recycle.send(batch.records);
        }
        drop(to_writer);
        if let Some(h) = writer {
            match h.join() {
                Ok(Ok(())) => {}
                Ok(Err(e)) => return Err(PassError::Write(e)),
                Err(panic) => std::panic::resume_unwind(panic),
            }
        }
        result
    })?;
    pass.finish(
        bank,
        None::<&mut EstimatesWriter<W>>,
        &mut warn,
        log.unit_findings().to_vec(),
    )
}

/// One batch of [`run_parallel`] through the clip finder and the bank into `rows`; the
/// last batch also hands on the rows the finder still holds.
fn estimate_batch<W: Write>(
    batch: &Batch,
    clips: &mut ClipFinder,
    pass: &mut Pass,
    bank: &mut Bank,
    rows: &mut Rows,
    warn: &mut impl FnMut(&LogWarning),
    each: &mut impl FnMut(u64, &LogRecord, &[Estimate<f64>]),
) -> Result<(), PassError> {
    // The last batch (the end of the log, or a read error) hands on every row held.
    let last = batch.last;
    let held = std::iter::from_fn(|| if last { Some(None) } else { None });
    let records = batch.records.iter().map(|r| Some(*r)).chain(held);
    for rec in records {
        let next = match rec {
            Some(rec) => clips.push(rec),
            None => match clips.pop() {
                Some(r) => Some(r),
                None => break,
            },
        };
        for w in clips.drain_warnings() {
            warn(&w);
        }
        let Some((rec, clipped)) = next else {
            continue;
        };
        pass.row(
            &rec,
            clipped,
            bank,
            None::<&mut EstimatesWriter<W>>,
            false,
            each,
            warn,
        )?;
        rows.push(&rec, &pass.est);
    }
    Ok(())
}

/// The reading thread of [`run_parallel`]: the log in batches of [`BATCH_ROWS`] rows (in
/// recycled vectors), each with the reader's warnings, until the end, an error, or the
/// consumer stops.
fn read_batches<R: BufRead>(
    log: &mut LogReader<R>,
    tx: &mpsc::SyncSender<Batch>,
    recycled: &mpsc::Receiver<Vec<LogRecord>>,
) {
    loop {
        let mut records = recycled
            .try_recv()
            .unwrap_or_else(|_| Vec::with_capacity(BATCH_ROWS));
        records.clear();
        let mut error = None;
        let mut end = false;
        while records.len() < BATCH_ROWS {
            match log.next_record() {
                Ok(Some(r)) => records.push(r),
                Ok(None) => {
                    end = true;
                    break;
                }
                Err(e) => {
                    error = Some(e);
                    break;
                }
            }
        }
        let last = end || error.is_some();
        let warnings = log.drain_warnings().collect();
        // A send fails when the consumer stopped (a write error): stop reading too.
        if tx
            .send(Batch {
                records,
                warnings,
                error,
                last,
            })
            .is_err()
            || last
        {
            return;
        }
    }
}

/// The writing thread of [`run_parallel`]: each batch of rows (`width` estimates a row)
/// to `w`, the vectors sent back for reuse.
fn write_rows<W: Write>(
    w: &mut EstimatesWriter<W>,
    rows_in: mpsc::Receiver<Rows>,
    rows_back: &mpsc::Sender<Rows>,
    width: usize,
) -> std::io::Result<()> {
    for rows in rows_in {
        for ((t, theta), est) in rows
            .t
            .iter()
            .zip(&rows.theta)
            .zip(rows.estimates.chunks_exact(width.max(1)))
        {
            w.write(*t, &est[..width], *theta)?;
        }
        // The bank thread may have finished: then the rows are dropped.
        let _ = rows_back.send(rows);
    }
    w.flush()
}

/// Time steps whose median is checked against the bank's frequency settings.
const RATE_STEPS: usize = 15;
/// Restart warnings listed before the rest are only counted.
const MAX_RESTART_WARNINGS: u64 = 10;

/// The per-row work of a pass, shared by [`run`] and [`run_parallel`].
struct Pass {
    file: String,
    with_theta: bool,
    /// Error statistics per estimator, of the rows scored.
    scorer: Scorer<ErrorStats>,
    est: Vec<Estimate<f64>>,
    rows: u64,
    /// The first positive time steps, until the settings are checked against their median.
    steps: Vec<f64>,
    last_t: f64,
    rate_checked: bool,
    restarts: u64,
    /// Restart warnings held until the time steps are known to be plausible (in a log in
    /// ms every step restarts; the reader's error on the unit says it all).
    held: Vec<LogWarning>,
}

impl Pass {
    fn new<R: BufRead>(bank: &Bank, log: &LogReader<R>, score_from: Option<f64>) -> Self {
        Self {
            scorer: Scorer::new(score_from, bank.names().len()),
            file: log.file().to_string(),
            with_theta: log.columns().has(Column::Theta),
            est: Vec::with_capacity(bank.names().len()),
            rows: 0,
            steps: Vec::with_capacity(RATE_STEPS),
            last_t: f64::NAN,
            rate_checked: false,
            restarts: 0,
            held: Vec::new(),
        }
    }

    /// Checks the bank's frequency settings against the log's rate once its median step
    /// is known (or at the end of a short log).
    fn check_rate(&mut self, t: f64, bank: &Bank, end: bool) -> Result<(), PassError> {
        if self.rate_checked {
            return Ok(());
        }
        let dt = t - self.last_t;
        if !end {
            if t.is_finite() {
                self.last_t = t;
            }
            if dt > 0.0 {
                self.steps.push(dt);
            }
            if self.steps.len() < RATE_STEPS {
                return Ok(());
            }
        }
        self.rate_checked = true;
        if self.steps.len() < 3 {
            return Ok(());
        }
        let mut sorted = self.steps.clone();
        sorted.sort_by(f64::total_cmp);
        check_settings_against_rate(bank.settings(), sorted[sorted.len() / 2])
            .map_err(|m| PassError::Settings(format!("{}: {m}", self.file)))
    }

    fn restart_warning(&mut self, line: u64, r: Restart, limit: f64) -> Option<LogWarning> {
        self.restarts += 1;
        (self.restarts <= MAX_RESTART_WARNINGS).then(|| LogWarning {
            file: self.file.clone(),
            line,
            column: None,
            header: None,
            kind: WarningKind::Restarted,
            message: format!(
                "{} back after a gap of {:.3} s (longer than the restart gap {limit} s): \
                 {} estimators reading it restart from this row",
                r.sensors.names().join(", "),
                r.gap,
                r.outputs
            ),
        })
    }

    #[inline]
    #[allow(clippy::too_many_arguments)] // the row, what is known of it, where it goes
    fn row<W: Write>(
        &mut self,
        rec: &LogRecord,
        clipped: Inputs,
        bank: &mut Bank,
        out: Option<&mut EstimatesWriter<W>>,
        flush_each: bool,
        each: &mut impl FnMut(u64, &LogRecord, &[Estimate<f64>]),
        warn: &mut impl FnMut(&LogWarning),
    ) -> Result<(), PassError> {
        self.check_rate(rec.t, bank, false)?;
        bank.update_clipped(&rec.sample, clipped, &mut self.est);
        let i = &rec.issues;
        let bad = (Column::ALL.into_iter())
            .filter(|c| i.is_implausible(*c))
            .filter_map(Column::sensor)
            .fold(Inputs::NONE, Inputs::with);
        bank.flag_implausible(bad, &mut self.est);
        if let Some(r) = bank.restarted() {
            if let Some(w) = self.restart_warning(rec.line, r, bank.settings().restart_gap) {
                self.held.push(w);
            }
        }
        if self.rate_checked || self.held.len() > RATE_STEPS {
            for w in self.held.drain(..) {
                warn(&w);
            }
        }
        if self.with_theta {
            let (est, theta) = (&self.est, rec.theta);
            self.scorer.row(rec.t, |i, s| {
                if let Some(th) = theta {
                    s.add(est[i].theta, th);
                }
            });
        }
        if let Some(w) = out {
            w.write(rec.t, &self.est, rec.theta)
                .map_err(PassError::Write)?;
            if flush_each {
                w.flush().map_err(PassError::Write)?;
            }
        }
        self.rows += 1;
        each(self.rows, rec, &self.est);
        Ok(())
    }

    /// The output row of a line that could not be read: t and every estimate NaN, each
    /// flagged [`Flags::BAD_LINE`](pendtilt_core::Flags::BAD_LINE); the bank does not see
    /// it (the next row's step spans it).
    fn bad_line<W: Write>(
        &mut self,
        bank: &Bank,
        out: Option<&mut EstimatesWriter<W>>,
    ) -> Result<(), PassError> {
        let blank = Estimate {
            theta: f64::NAN,
            flags: pendtilt_core::Flags::BAD_LINE,
        };
        self.est.clear();
        self.est.resize(bank.names().len(), blank);
        if let Some(w) = out {
            let theta = self.with_theta.then_some(f64::NAN);
            w.write(f64::NAN, &self.est, theta)
                .map_err(PassError::Write)?;
            w.flush().map_err(PassError::Write)?;
        }
        self.rows += 1;
        Ok(())
    }

    fn finish<W: Write>(
        mut self,
        bank: &Bank,
        out: Option<&mut EstimatesWriter<W>>,
        warn: &mut impl FnMut(&LogWarning),
        unit_findings: Vec<Finding>,
    ) -> Result<PassSummary, PassError> {
        self.check_rate(f64::NAN, bank, true)?;
        for w in self.held.drain(..) {
            warn(&w);
        }
        if let Some(w) = out {
            w.flush().map_err(PassError::Write)?;
        }
        if self.restarts > MAX_RESTART_WARNINGS {
            warn(&LogWarning {
                file: self.file.clone(),
                line: 0,
                column: None,
                header: None,
                kind: WarningKind::Restarted,
                message: format!(
                    "{} restarts after sensor gaps in all ({} not listed)",
                    self.restarts,
                    self.restarts - MAX_RESTART_WARNINGS
                ),
            });
        }
        let (window, stats) = self.scorer.finish();
        Ok(PassSummary {
            rows: self.rows,
            restarts: self.restarts,
            unit_findings,
            window,
            errors: self.with_theta.then(|| {
                bank.names()
                    .iter()
                    .map(|n| n.to_string())
                    .zip(stats)
                    .collect()
            }),
        })
    }
}

/// Why a planar pass stopped.
#[derive(Debug, thiserror::Error)]
pub enum PassError {
    /// The log could not be read further.
    #[error(transparent)]
    Read(#[from] LogError),
    /// The output could not be written.
    #[error("cannot write the estimates")]
    Write(#[source] std::io::Error),
    /// A setting cannot work at the log's rate (a cutoff above Nyquist).
    #[error("{0}")]
    Settings(String),
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bank::planar::BankSettings;
    use crate::io::{ReaderOptions, WriterOptions};
    use crate::pipeline::{error_table, inputs_of};
    use pendtilt_core::PendulumParams;
    use std::io::Cursor;

    /// A log of `rows` rows (more than two batches), with a bad cell at `bad` if given.
    fn log(rows: usize, bad: Option<usize>) -> Vec<u8> {
        let mut s = String::from("t,phi,gyro,ax,ay,theta\n");
        for k in 0..rows {
            let t = k as f64 * 1e-3;
            let th = 0.2 * (1.7 * t).sin();
            if Some(k) == bad {
                s.push_str(&format!("{t},abc,0,0,9.8,{th}\n"));
            } else {
                s.push_str(&format!(
                    "{t},{},{},{},{},{th}\n",
                    0.9 * th,
                    0.34 * (1.7 * t).cos(),
                    9.8 * th.sin(),
                    9.8 * th.cos()
                ));
            }
        }
        s.into_bytes()
    }

    /// Output bytes, rows and the error text of one pass, threaded or not.
    fn pass(input: &[u8], parallel: bool) -> (Vec<u8>, u64, Option<String>, Option<f64>) {
        let mut r = LogReader::new(
            Cursor::new(input.to_vec()),
            "mem.csv",
            ReaderOptions::default(),
        )
        .unwrap();
        let s = BankSettings::from_params(PendulumParams::default());
        let mut bank = Bank::new(&s, inputs_of(&r), None).unwrap();
        let mut w =
            EstimatesWriter::new(Vec::new(), bank.names(), true, WriterOptions::default()).unwrap();
        let mut seen = 0;
        let res = if parallel {
            run_parallel(
                &mut r,
                &mut bank,
                Some(&mut w),
                Some(1.0),
                |_| {},
                |n, _, _| seen = n,
            )
        } else {
            run(
                &mut r,
                &mut bank,
                Some(&mut w),
                false,
                Some(1.0),
                |_| {},
                |n, _, _| seen = n,
            )
        };
        let (err, rms) = match res {
            Ok(p) => (None, Some(p.errors.unwrap()[2].1.rms())),
            Err(e) => (Some(e.to_string()), None),
        };
        (w.into_inner().unwrap(), seen, err, rms)
    }

    #[test]
    fn the_parallel_pass_gives_the_same_rows_errors_and_statistics() {
        let good = log(3 * BATCH_ROWS + 17, None);
        let (a, b) = (pass(&good, false), pass(&good, true));
        assert_eq!(a.1, 3 * BATCH_ROWS as u64 + 17);
        assert_eq!(a.0, b.0);
        assert_eq!((a.1, a.2.clone(), a.3), (b.1, b.2, b.3));
        assert!(a.2.is_none() && a.3.unwrap().is_finite());

        // A bad cell in the third batch: the rows before it are written, then the error.
        let bad = log(3 * BATCH_ROWS, Some(2 * BATCH_ROWS + 5));
        let (a, b) = (pass(&bad, false), pass(&bad, true));
        assert_eq!(a.0, b.0);
        assert_eq!(a.1, 2 * BATCH_ROWS as u64 + 5);
        assert_eq!(a.1, b.1);
        let msg = a.2.unwrap();
        assert_eq!(Some(msg.clone()), b.2);
        assert!(msg.contains("mem.csv") && msg.contains("abc"), "{msg}");
    }

    #[test]
    fn errors_are_scored_from_score_from_after_the_first_row() {
        // 3 s at 1 kHz from t0 = 10 s; the accelerometer's estimate is off by 0.1 rad
        // before t = 11 s and exact after, so scoring from 1 s sees no error from it.
        let mut text = String::from("t,ax,ay,theta\n");
        for k in 0..3000 {
            let t = 10.0 + k as f64 * 1e-3;
            let th: f64 = 0.2;
            let read = if t < 11.0 { th + 0.1 } else { th };
            let (ax, ay) = (9.8 * read.sin(), 9.8 * read.cos());
            text.push_str(&format!("{t},{ax},{ay},{th}\n"));
        }
        let score = |from: Option<f64>| {
            let mut r = LogReader::new(text.as_bytes(), "m.csv", ReaderOptions::default()).unwrap();
            let s = BankSettings::from_params(PendulumParams::default());
            let only = vec!["accel".to_string()];
            let mut bank = Bank::new(&s, inputs_of(&r), Some(&only)).unwrap();
            let p = run(
                &mut r,
                &mut bank,
                None::<&mut EstimatesWriter<Vec<u8>>>,
                false,
                from,
                |_| {},
                |_, _, _| {},
            )
            .unwrap();
            assert_eq!(p.rows, 3000);
            (p.window, p.errors.unwrap()[0].1)
        };
        let (window, all) = score(Some(0.0));
        assert_eq!(window.from, 0.0);
        assert_eq!(all.count, 3000);
        assert!((all.max_abs - 0.1).abs() < 1e-9, "{}", all.max_abs);
        // t >= 11 s: rows 1000..3000 (10 + 1000e-3 rounds to 11 exactly).
        let (window, late) = score(Some(1.0));
        assert_eq!(late.count, 2000);
        assert!(late.max_abs < 1e-9 && late.rms() < 1e-9, "{late:?}");
        let table = error_table(&[("accel".into(), late)], &window);
        assert!(
            table.contains("t >= t0 + 1 s (2000 rows scored)"),
            "{table}"
        );
        // No start given: a 3 s log is scored whole, and the table says why.
        let (window, short) = score(None);
        assert_eq!((window.from, short.count), (0.0, 3000));
        let table = error_table(&[("accel".into(), short)], &window);
        assert!(
            table.contains("the whole log, which lasts 3.0 s"),
            "{table}"
        );
    }
}

//! `pendtilt filter`: the paper's FIR low-pass over columns of any CSV.
//!
//! ```text
//! pendtilt filter IN.csv --order 50 --cutoff 20 [--columns a,b] [--window hamming] -o OUT.csv
//! ```
//!
//! The paper smooths every result with a 50th-order, 20 Hz FIR low-pass
//! ([`pendtilt_core::filters::fir`]); this command applies the same filter to a log or an
//! estimates file so that results can be compared the paper's way.
//!
//! - The sample rate comes from the time column (`t`, or `--time-column`): it must be
//!   strictly increasing and uniform to within `--max-jitter` (the FIR's frequency axis is
//!   in samples, so a gap would silently move the cut-off). The rate is
//!   `(rows - 1) / (t_last - t_first)`.
//! - The chosen columns (default: every column whose first data cell is a number, except
//!   the time column) are filtered; every other column is copied byte for byte. One output
//!   row per input row, in the same order, with the same header.
//! - The output is **delayed by order/2 samples** (25 ms for the paper's filter at 1 kHz), as
//!   every causal linear-phase filter is, unless `--compensate-delay` is given: then each
//!   row gets the filter output from order/2 samples later, and the end of the file is
//!   extended by holding the last value (the mirror of the start, where the history is
//!   pre-filled with the first value). That needs an even order (a whole-sample delay).
//! - An empty cell or `NaN` in a filtered column is a missing sample: it makes the next
//!   order + 1 outputs of that column `NaN`, then the filter recovers. Any other cell that
//!   is not a number is an error naming the file, line and column.
//! - The file is read by the log reader's line reader (`io::csv_lines`): blank
//!   lines and `#` comment lines are skipped but counted in line numbers, whitespace
//!   around a field is trimmed, a quoted field may not span lines.
//! - Streaming: the file is read twice (once to check the time column and the cells and
//!   find the rate, once to filter), and memory holds only the filter histories, not the
//!   file. Standard input (`-`) or a pipe is copied to a temporary file first. The output goes to a temporary file beside it, renamed into place only when the
//!   second pass succeeded: a failed run leaves an earlier output as it was.

use anyhow::{bail, Context, Result};
use csv::ByteRecord;
use pendtilt_core::filters::fir::{design_lowpass, FirSlice, Window, PAPER_CUTOFF_HZ, PAPER_ORDER};
use std::collections::VecDeque;
use std::fmt::Write as _;
use std::io::Write;
use std::path::{Path, PathBuf};

use crate::io::input::InputLog;
use crate::io::output::{NamedPath, OutputFile};

mod cells;
use cells::{find_column, open_reader, parse_cell, read_header, read_record};

/// The largest `--order` accepted. Far beyond any useful low-pass for these logs; the limit
/// exists so that a typo (an extra zero or three) is an error, not an attempt to allocate
/// gigabytes of filter history.
pub const MAX_ORDER: usize = 100_000;

/// Options of `pendtilt filter`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Input CSV, with a header row and a time column; `-` for standard input.
    pub input: PathBuf,
    /// Output CSV (`-` for standard output).
    #[arg(short, long, visible_alias = "out")]
    pub output: PathBuf,
    /// FIR order; the filter has order + 1 taps and delays by order/2 samples.
    /// The paper's filter is 50.
    #[arg(long, default_value_t = PAPER_ORDER)]
    pub order: usize,
    /// Cut-off frequency in Hz (where scipy's firwin puts it); must be below half the
    /// sample rate. The paper's filter is 20 Hz.
    #[arg(long, default_value_t = PAPER_CUTOFF_HZ)]
    pub cutoff: f64,
    /// Columns to filter, comma-separated. Default: every column whose first data cell is
    /// a number, except the time column.
    #[arg(long, value_delimiter = ',')]
    pub columns: Option<Vec<String>>,
    /// Window of the windowed-sinc design: hamming, hann, blackman or rectangular.
    #[arg(long, default_value = "hamming", value_parser = parse_window)]
    pub window: Window,
    /// Name of the time column (seconds).
    #[arg(long, default_value = "t")]
    pub time_column: String,
    /// Largest accepted deviation of any time step from the mean step, as a fraction of the
    /// mean (0.1 = 10%). A larger one is an error naming its line.
    #[arg(long, default_value_t = 0.1)]
    pub max_jitter: f64,
    /// Undo the filter's delay: row k gets the output of row k + order/2, the end is
    /// extended by holding the last value. Needs an even order.
    #[arg(long)]
    pub compensate_delay: bool,
}

fn parse_window(s: &str) -> Result<Window, String> {
    s.parse::<Window>().map_err(|e| e.to_string())
}

/// Settings of [`scan`] (the library form of [`Args`], without the file names).
#[derive(Debug, Clone, PartialEq)]
pub struct FilterOptions {
    /// FIR order (taps = order + 1), at most [`MAX_ORDER`].
    pub order: usize,
    /// Cut-off frequency \[Hz\].
    pub cutoff_hz: f64,
    /// Columns to filter; `None` for every numeric column except time.
    pub columns: Option<Vec<String>>,
    /// Window of the design.
    pub window: Window,
    /// Name of the time column.
    pub time_column: String,
    /// Largest relative deviation of a time step from the mean step.
    pub max_jitter: f64,
    /// Shift the output back by order/2 samples (even order only).
    pub compensate_delay: bool,
}

impl Default for FilterOptions {
    /// The paper's filter: order 50, 20 Hz, Hamming, all numeric columns, time in `t`, 10%
    /// jitter allowed, delay not compensated.
    fn default() -> Self {
        Self {
            order: PAPER_ORDER,
            cutoff_hz: PAPER_CUTOFF_HZ,
            columns: None,
            window: Window::Hamming,
            time_column: "t".to_string(),
            max_jitter: 0.1,
            compensate_delay: false,
        }
    }
}

impl From<&Args> for FilterOptions {
    fn from(a: &Args) -> Self {
        Self {
            order: a.order,
            cutoff_hz: a.cutoff,
            columns: a.columns.clone(),
            window: a.window,
            time_column: a.time_column.clone(),
            max_jitter: a.max_jitter,
            compensate_delay: a.compensate_delay,
        }
    }
}

/// What [`scan`] found and decided: everything [`Plan::apply`] needs to filter the file,
/// validated, so that applying it writes a complete output or fails only on I/O.
#[derive(Debug, Clone)]
pub struct Plan {
    /// Where to read the input (the file, or the copy of standard input).
    input: PathBuf,
    /// Its name in messages.
    name: PathBuf,
    /// Header names as read (lossily decoded, trimmed).
    pub names: Vec<String>,
    /// Field indices of the filtered columns, in file order.
    pub filtered: Vec<usize>,
    /// Number of data rows.
    pub rows: u64,
    /// Sample rate from the time column \[Hz\].
    pub rate_hz: f64,
    /// The FIR coefficients (order + 1 of them).
    pub taps: Vec<f64>,
    /// Samples by which the output is shifted back (0, or order/2 with
    /// `--compensate-delay`).
    pub shift: usize,
}

impl Plan {
    /// Names of the filtered columns, in file order.
    pub fn filtered_names(&self) -> Vec<&str> {
        self.filtered
            .iter()
            .map(|&i| self.names[i].as_str())
            .collect()
    }

    /// Names of the columns copied unchanged, in file order.
    pub fn passed_names(&self) -> Vec<&str> {
        (0..self.names.len())
            .filter(|i| !self.filtered.contains(i))
            .map(|i| self.names[i].as_str())
            .collect()
    }

    /// Delay of the filtered columns relative to the pass-through ones, in samples:
    /// order/2, or 0 when compensated.
    pub fn output_delay_samples(&self) -> f64 {
        (self.taps.len() as f64 - 1.0) / 2.0 - self.shift as f64
    }

    /// Second pass: filters the input into `out` (CSV with the input's header), one row per
    /// input row. Returns the rows written and, per filtered column, how many missing cells
    /// went in and how many `NaN` rows came out.
    ///
    /// # Errors
    /// I/O errors, and the input changing between [`scan`] and here (a row that no longer
    /// parses is reported with its line as in the first pass).
    pub fn apply<W: Write>(&self, out: W) -> Result<Applied> {
        let path = self.name.as_path();
        let mut rdr = open_reader(&self.input, path)?;
        let header = ByteRecord::from(read_header(path, &mut rdr)?);
        let mut wtr = RowWriter::new(out, &header, &self.names, &self.filtered)?;
        let n_cols = self.filtered.len();
        let mut histories = vec![vec![0.0f64; self.taps.len()]; n_cols];
        let mut filters = Vec::with_capacity(n_cols);
        for h in histories.iter_mut() {
            filters.push(FirSlice::new(&self.taps, h).context("FIR filter")?);
        }
        let step = |filters: &mut [FirSlice<'_, f64>], x: &[f64], y: &mut [f64]| {
            for ((f, x), y) in filters.iter_mut().zip(x).zip(y) {
                *y = f.update(*x);
            }
        };
        let mut x = vec![f64::NAN; n_cols];
        let mut y = vec![f64::NAN; n_cols];
        let mut pending: VecDeque<ByteRecord> = VecDeque::with_capacity(self.shift + 1);
        let mut rec = ByteRecord::new();
        let mut missing_in = vec![0u64; n_cols];
        while let Some(line) = read_record(path, &mut rdr, &self.names, &mut rec)? {
            for (j, &i) in self.filtered.iter().enumerate() {
                x[j] = parse_cell(path, line, &self.names, i, rec.get(i))?;
                missing_in[j] += u64::from(x[j].is_nan());
            }
            step(&mut filters, &x, &mut y);
            if self.shift == 0 {
                wtr.write(&rec, &y)?;
            } else {
                pending.push_back(rec.clone());
                if pending.len() > self.shift {
                    if let Some(row) = pending.pop_front() {
                        wtr.write(&row, &y)?;
                    }
                }
            }
        }
        // Delay compensation: the last `shift` rows need outputs from beyond the end of the
        // file; hold the last input (as the start holds the first). With fewer rows than
        // `shift`, first run the filter on until the first pending row's output is reached.
        for _ in pending.len()..self.shift {
            step(&mut filters, &x, &mut y);
        }
        while let Some(row) = pending.pop_front() {
            step(&mut filters, &x, &mut y);
            wtr.write(&row, &y)?;
        }
        let (written, nan_out) = wtr.finish()?;
        let columns = self
            .filtered
            .iter()
            .enumerate()
            .map(|(j, &i)| NanSpread {
                name: self.names[i].clone(),
                missing_in: missing_in[j],
                nan_out: nan_out[j],
            })
            .collect();
        Ok(Applied {
            rows: written,
            columns,
        })
    }
}

/// The output of [`Plan::apply`]: each input row with its filtered cells replaced, the
/// `NaN` outputs counted per filtered column.
struct RowWriter<W: Write> {
    wtr: csv::Writer<W>,
    /// For each input field, its index among the filtered columns.
    is_filtered: Vec<Option<usize>>,
    out_rec: ByteRecord,
    cell: String,
    written: u64,
    nan_out: Vec<u64>,
}

impl<W: Write> RowWriter<W> {
    /// Writes `header` and gets ready for the rows (`filtered`: the filtered fields).
    fn new(out: W, header: &ByteRecord, names: &[String], filtered: &[usize]) -> Result<Self> {
        let mut wtr = csv::WriterBuilder::new().from_writer(out);
        wtr.write_byte_record(header)
            .with_context(|| "cannot write the output header".to_string())?;
        let mut is_filtered = vec![None; names.len()];
        for (j, &i) in filtered.iter().enumerate() {
            is_filtered[i] = Some(j);
        }
        Ok(Self {
            wtr,
            is_filtered,
            out_rec: ByteRecord::new(),
            cell: String::new(),
            written: 0,
            nan_out: vec![0; filtered.len()],
        })
    }

    /// Writes `row` with its filtered cells replaced by `y` (one per filtered column).
    fn write(&mut self, row: &ByteRecord, y: &[f64]) -> Result<()> {
        self.out_rec.clear();
        for (i, field) in row.iter().enumerate() {
            match self.is_filtered.get(i).copied().flatten() {
                Some(j) => {
                    self.nan_out[j] += u64::from(y[j].is_nan());
                    format_f64(&mut self.cell, y[j]);
                    self.out_rec.push_field(self.cell.as_bytes());
                }
                None => self.out_rec.push_field(field),
            }
        }
        self.wtr
            .write_byte_record(&self.out_rec)
            .context("cannot write an output row")?;
        self.written += 1;
        Ok(())
    }

    /// Flushes the output: the rows written and the `NaN` outputs per filtered column.
    fn finish(mut self) -> Result<(u64, Vec<u64>)> {
        self.wtr.flush().context("cannot write the output")?;
        Ok((self.written, self.nan_out))
    }
}

/// What [`Plan::apply`] wrote.
#[derive(Debug, Clone, PartialEq)]
pub struct Applied {
    /// Rows written (one per input row).
    pub rows: u64,
    /// Per filtered column, in file order: how far missing samples spread.
    pub columns: Vec<NanSpread>,
}

/// How far the missing samples of one filtered column spread through the filter.
#[derive(Debug, Clone, PartialEq)]
pub struct NanSpread {
    /// The column's name.
    pub name: String,
    /// Empty or `NaN` cells in the input.
    pub missing_in: u64,
    /// `NaN` cells in the output (each missing input makes up to order + 1 of them).
    pub nan_out: u64,
}

/// Writes `x` into `out` as the shortest text that parses back to the same `f64` (Rust's
/// `{}` and `{:e}` both are): plain for ordinary magnitudes, exponent form for tiny or huge
/// ones, where `{}` would write dozens of zeros (a filter's output in the stop band is often
/// 1e-20).
fn format_f64(out: &mut String, x: f64) {
    out.clear();
    let a = x.abs();
    let _ = if a == 0.0 || !a.is_finite() || (1e-5..1e16).contains(&a) {
        write!(out, "{x}")
    } else {
        write!(out, "{x:e}")
    };
}

/// First pass: checks the options, the header, the time column (strictly increasing,
/// uniform within `max_jitter`) and every cell of the filtered columns, measures the rate
/// and designs the filter. Reads the file once, in constant memory; writes nothing.
///
/// # Errors
/// Every problem with the file or the options, as `FILE:LINE: what`, naming the column.
pub fn scan(log: &InputLog, opts: &FilterOptions) -> Result<Plan> {
    let input = Path::new(log.name());
    let file = input.display();
    let shift = check_options(opts)?;
    let mut rdr = open_reader(log.path(), input)?;
    let names = read_header(input, &mut rdr)?;
    let time_idx = find_column(input, &names, &opts.time_column, "time")?;
    // Explicit columns are checked against the header now; the default set needs the first
    // data row.
    let mut filtered = match &opts.columns {
        None => None,
        Some(cols) => Some(requested_columns(input, &names, cols, time_idx)?),
    };
    let mut rec = ByteRecord::new();
    let mut steps = TimeSteps::default();
    while let Some(line) = read_record(input, &mut rdr, &names, &mut rec)? {
        let t = parse_cell(input, line, &names, time_idx, rec.get(time_idx))?;
        if !t.is_finite() {
            bail!(
                "{file}:{line}: time column '{}' is empty or not finite",
                opts.time_column
            );
        }
        if filtered.is_none() {
            filtered = Some(default_columns(input, line, &names, &rec, opts, time_idx)?);
        }
        steps.push(&file, t, line, &opts.time_column)?;
        if let Some(idx) = &filtered {
            for &i in idx {
                parse_cell(input, line, &names, i, rec.get(i))?;
            }
        }
    }
    let rate_hz = steps.uniform_rate(&file, opts.max_jitter)?;
    let mut taps = vec![0.0f64; opts.order + 1];
    design_lowpass(opts.cutoff_hz, rate_hz, opts.window, &mut taps).with_context(|| {
        format!(
            "--cutoff {} Hz at the sample rate {rate_hz} Hz of {file}",
            opts.cutoff_hz
        )
    })?;
    Ok(Plan {
        input: log.path().to_path_buf(),
        name: input.to_path_buf(),
        names,
        filtered: filtered.unwrap_or_default(),
        rows: steps.rows,
        rate_hz,
        taps,
        shift,
    })
}

/// Checks the options that do not depend on the file; returns the output shift (order/2
/// with `--compensate-delay`, else 0).
fn check_options(opts: &FilterOptions) -> Result<usize> {
    if opts.order > MAX_ORDER {
        bail!(
            "--order {} is larger than the maximum {MAX_ORDER}",
            opts.order
        );
    }
    let shift = if opts.compensate_delay {
        if opts.order % 2 != 0 {
            bail!(
                "--compensate-delay needs an even --order (got {}): an odd order delays by a \
                 half sample, which cannot be undone by shifting rows",
                opts.order
            );
        }
        opts.order / 2
    } else {
        0
    };
    if !(opts.max_jitter.is_finite() && opts.max_jitter >= 0.0) {
        bail!(
            "--max-jitter {} must be a finite fraction >= 0",
            opts.max_jitter
        );
    }
    if opts.cutoff_hz.is_nan() || opts.cutoff_hz <= 0.0 {
        bail!("--cutoff {} Hz must be positive", opts.cutoff_hz);
    }

    Ok(shift)
}

/// The field indices of `--columns` (sorted, without repeats); an error for an empty
/// name, a name not in the header, or the time column.
fn requested_columns(
    input: &Path,
    names: &[String],
    cols: &[String],
    time_idx: usize,
) -> Result<Vec<usize>> {
    let mut idx = Vec::new();
    for c in cols.iter().map(|c| c.trim()) {
        if c.is_empty() {
            bail!("--columns: empty column name in the list");
        }
        let i = find_column(input, names, c, "requested")?;
        if i == time_idx {
            bail!(
                "--columns: '{c}' is the time column; it is passed through, not \
                 filtered"
            );
        }
        if !idx.contains(&i) {
            idx.push(i);
        }
    }
    if idx.is_empty() {
        bail!("--columns: no column named");
    }
    idx.sort_unstable();
    Ok(idx)
}

/// The default columns to filter: every column but time whose cell on the first data row
/// (`rec`, on `line`) is a number.
fn default_columns(
    input: &Path,
    line: u64,
    names: &[String],
    rec: &ByteRecord,
    opts: &FilterOptions,
    time_idx: usize,
) -> Result<Vec<usize>> {
    let file = input.display();
    let idx: Vec<usize> = (0..names.len())
        .filter(|&i| i != time_idx)
        .filter(|&i| {
            rec.get(i)
                .and_then(|f| std::str::from_utf8(f).ok())
                .map(str::trim)
                .is_some_and(|s| !s.is_empty() && s.parse::<f64>().is_ok())
        })
        .collect();
    if idx.is_empty() {
        bail!(
            "{file}:{line}: no numeric column to filter besides the time column \
             '{}' (name them with --columns)",
            opts.time_column
        );
    }
    Ok(idx)
}

/// The time column's steps as a pass reads them: rows, first and last time, and the
/// shortest and longest step with their lines.
#[derive(Debug, Clone, Copy)]
struct TimeSteps {
    rows: u64,
    t_first: f64,
    t_prev: f64,
    prev_line: u64,
    dt_min: (f64, u64),
    dt_max: (f64, u64),
}

impl Default for TimeSteps {
    fn default() -> Self {
        Self {
            rows: 0,
            t_first: 0.0,
            t_prev: 0.0,
            prev_line: 0,
            dt_min: (f64::INFINITY, 0),
            dt_max: (0.0, 0),
        }
    }
}

impl TimeSteps {
    /// Adds the finite time `t` of `line` of `file`: an error when it is not after the
    /// previous one.
    fn push(
        &mut self,
        file: &dyn std::fmt::Display,
        t: f64,
        line: u64,
        column: &str,
    ) -> Result<()> {
        if self.rows == 0 {
            self.t_first = t;
        } else {
            let t_prev = self.t_prev;
            if t <= t_prev {
                bail!(
                    "{file}:{line}: time {t} is not after {t_prev} (line {}): the time \
                     column '{column}' must be strictly increasing",
                    self.prev_line
                );
            }
            let dt = t - t_prev;
            if dt < self.dt_min.0 {
                self.dt_min = (dt, line);
            }
            if dt > self.dt_max.0 {
                self.dt_max = (dt, line);
            }
        }
        self.t_prev = t;
        self.prev_line = line;
        self.rows += 1;
        Ok(())
    }

    /// The rate `(rows - 1) / (t_last - t_first)` \[Hz\] of `file`: an error with fewer
    /// than 2 rows or a step further than `max_jitter` (a fraction) from the mean.
    fn uniform_rate(&self, file: &dyn std::fmt::Display, max_jitter: f64) -> Result<f64> {
        let rows = self.rows;
        if rows < 2 {
            bail!("{file}: {rows} data row(s): at least 2 are needed to find the sample rate");
        }
        let mean_dt = (self.t_prev - self.t_first) / (rows - 1) as f64;
        let rate_hz = 1.0 / mean_dt;
        for (dt, line) in [self.dt_max, self.dt_min] {
            let dev = (dt - mean_dt).abs() / mean_dt;
            if dev > max_jitter {
                bail!(
                    "{file}:{line}: time step {dt} s differs from the mean step {mean_dt} s by {:.1}% \
                     (more than --max-jitter {:.1}%): the FIR needs uniformly sampled data; \
                     resample the log or raise --max-jitter",
                    dev * 100.0,
                    max_jitter * 100.0
                );
            }
        }
        Ok(rate_hz)
    }
}

/// Runs `pendtilt filter`: [`scan`], then [`Plan::apply`] into a temporary file renamed
/// onto the output only when the whole file was filtered; an output that is the input
/// (also through a link) is refused first.
pub fn run(args: Args) -> Result<()> {
    let opts = FilterOptions::from(&args);
    crate::io::output::check_distinct(
        &[NamedPath::new("INPUT", &args.input)],
        &[NamedPath::new("-o", &args.output)],
    )?;
    // Read twice (checked, then filtered): standard input or a pipe is copied first.
    let input = InputLog::open(&args.input)?;
    let bar = super::options::progress(input.path(), "filtering {spinner} {elapsed}", false);
    let plan = scan(&input, &opts).with_context(|| crate::io::output::not_written(&args.output));
    let plan = plan.inspect_err(|_| bar.finish_and_clear())?;
    let out = OutputFile::create("-o", &args.output)?;
    let applied = plan
        .apply(std::io::BufWriter::new(out.writer()?))
        .with_context(|| crate::io::output::not_written(&args.output));
    bar.finish_and_clear();
    let applied = applied?;
    out.commit()?;
    let delay = plan.output_delay_samples();
    crate::cli::summary::say_err!(
        "pendtilt filter: {} rows at {:.6} Hz; {}-tap {} low-pass at {} Hz on: {}; \
         passed through: {}; output delay {} samples ({:.3} ms){}",
        applied.rows,
        plan.rate_hz,
        plan.taps.len(),
        args.window,
        args.cutoff,
        plan.filtered_names().join(", "),
        plan.passed_names().join(", "),
        delay,
        delay / plan.rate_hz * 1e3,
        if plan.shift > 0 { " (compensated)" } else { "" }
    );
    // A log shorter than the filter is all start-up: 3 rows of the paper's filter gave the
    // first value back three times, without a word.
    if (applied.rows as usize) < plan.taps.len() {
        eprintln!(
            "warning: {}: {} rows, fewer than the filter's {} taps: every output row is within \
             its start-up (the history before the first row is the first value held; the \
             output follows the input only from row {} on): filter a longer log",
            args.input.display(),
            applied.rows,
            plan.taps.len(),
            plan.taps.len()
        );
    }
    for c in applied.columns.iter().filter(|c| c.missing_in > 0) {
        eprintln!(
            "note: column '{}': {} missing or NaN cell(s) made {} output row(s) NaN (each \
             spreads to the {} rows the filter spans)",
            c.name,
            c.missing_in,
            c.nan_out,
            plan.taps.len()
        );
    }
    Ok(())
}

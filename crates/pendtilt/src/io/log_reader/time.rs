//! The time column: its steps (gaps, jitter, repeats, steps back), the rate they imply,
//! and a new time base.
use std::io::BufRead;

use super::{CellRef, LogError, LogErrorKind, LogReader, RowIssues};
use crate::io::columns::Column;
use crate::io::diagnostics::WarningKind;
use crate::io::plausibility::{implausible_given_unit, implausible_step};

/// The error for a time column whose stamps repeat more often than they step: `zero`
/// zero steps and `positive` steps of `dt` \[s\] (0 when none).
fn rounded_time(zero: u64, positive: u64, dt: f64) -> String {
    if positive == 0 {
        return format!(
            "the time never increases ({} rows at one stamp): is `t` the time column \
             (--map t=NAME)?",
            zero + 1
        );
    }
    let run = (zero + positive) as f64 / positive as f64;
    let step = crate::io::plausibility::fmt_sig(dt);
    format!(
        "{zero} of the first {} time steps are zero: each stamp repeats for about {:.0} rows \
         and then steps by {step} s, at about {} rows per second: the time was written \
         rounded (to {step} s) or rows share a stamp; write `t` with more digits, one time \
         per row",
        zero + positive,
        run,
        crate::io::plausibility::fmt_sig(run / dt)
    )
}

/// A time that goes back by more than this \[s\] (the bank's restart gap) and runs on from
/// there is a new time base, an error ([`new_time_base`]); a shorter step back holds the
/// estimators for as long, flagged, as before.
pub const TIME_BASE_JUMP: f64 = crate::sensors::RESTART_GAP;

/// Where the time went back by more than [`TIME_BASE_JUMP`]: the line and the times
/// before and at it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimeBack {
    /// The line whose time went back.
    pub line: u64,
    /// The last time before it that the estimators took \[s\].
    pub from: f64,
    /// Its time \[s\].
    pub to: f64,
}

impl TimeBack {
    /// The step back at `line` from `from` to `to`, when it is longer than
    /// [`TIME_BASE_JUMP`].
    pub fn of(line: u64, from: Option<f64>, to: f64) -> Option<Self> {
        let from = from?;
        (from - to > TIME_BASE_JUMP).then_some(Self { line, from, to })
    }

    /// True when `t`, on the row after, runs on from this new time (after it, and still
    /// before `from`, so the estimators would hold until the old time came back).
    pub fn runs_on(&self, t: f64) -> bool {
        t > self.to && t <= self.from
    }
}

/// What to say when the time went back (`back`) and the row at `t` runs on from there:
/// the estimators, which refuse a time before the last one they took, would hold the rest
/// of the log (every row flagged `bad_time_step`, scored as held) until the old time came
/// back. `file` and `header_line` give the commands that split the log.
pub fn new_time_base(back: &TimeBack, t: f64, file: &str, header_line: u64) -> String {
    let n = back.line;
    let split = if file.starts_with('<') {
        String::new()
    } else {
        format!(
            ": `head -n {} {file} > first.csv; (sed -n {header_line}p {file}; tail -n +{n} \
             {file}) > second.csv`",
            n - 1
        )
    };
    format!(
        "the time went back on line {n} ({} then {} s) and runs on from there ({t} s here): \
         two logs joined, or a logger whose clock restarted? The estimators would hold the \
         estimate of the row before line {n} until the time passed {} s again; split the \
         log at line {n}{split}",
        back.from, back.to, back.from,
    )
}

/// Positive time steps used for the nominal step (their median).
pub(super) const NOMINAL_DT_SAMPLES: usize = 15;

impl<R: BufRead> LogReader<R> {
    /// Once the nominal step is known (or at the end of a short log): an error when no
    /// sensor rate explains it, unless `--time-unit` was given.
    pub(super) fn check_rate(&mut self) -> Result<(), LogError> {
        if self.rate_checked {
            return Ok(());
        }
        let positive = self.first_dts.len() as u64;
        // More repeated stamps than steps: the time is rounded (`%.1f` at 1 kHz repeats
        // each stamp 100 times) or rows share a stamp, whatever its unit. Its steps are
        // those of the rounding, which the rate check would take for a unit (1 s: "in ms?").
        let found = if self.zero_steps > positive && self.zero_steps >= 2 {
            Some(rounded_time(
                self.zero_steps,
                positive,
                self.summary.nominal_dt.unwrap_or(0.0),
            ))
        } else if let Some(u) = self.options.time_unit {
            // A unit given is judged as one found: nominal_dt is in seconds already.
            self.summary
                .nominal_dt
                .and_then(|dt| implausible_given_unit(dt / u.seconds(), u))
        } else {
            let Some(dt) = self.summary.nominal_dt else {
                return Ok(());
            };
            implausible_step(dt)
        };
        self.rate_checked = positive > 0 || found.is_some();
        match found {
            None => Ok(()),
            Some(msg) => {
                let line = Some(self.lines.line());
                let h = self.header[self.positions[Column::T.index()].unwrap_or(0)].clone();
                let cell = CellRef {
                    position: self.positions[Column::T.index()].unwrap_or(0) + 1,
                    header: h,
                };
                Err(self.error(line, Some(cell), LogErrorKind::ImplausibleTimeStep(msg)))
            }
        }
    }

    /// An error when the previous row's time went back by more than [`TIME_BASE_JUMP`]
    /// and this one runs on from it ([`new_time_base`]); notes a step back at this row.
    pub(super) fn check_time_base(&mut self, t: f64) -> Result<(), LogError> {
        if t.is_nan() {
            return Ok(());
        }
        if let Some(back) = self.went_back.take() {
            if back.runs_on(t) {
                let msg = new_time_base(&back, t, &self.file, self.header_line);
                let pos = self.positions[Column::T.index()].unwrap_or(0);
                let cell = CellRef {
                    position: pos + 1,
                    header: self.header[pos].clone(),
                };
                let line = Some(self.lines.line());
                return Err(self.error(line, Some(cell), LogErrorKind::NewTimeBase(msg)));
            }
        }
        self.went_back = TimeBack::of(self.lines.line(), self.gate.last(), t);
        Ok(())
    }

    /// Checks the row's time `t`: missing, repeated or going back, a gap or jitter against
    /// the nominal step (the median of the first steps, found here); each said, flagged in
    /// `issues`.
    pub(super) fn check_time(&mut self, t: f64, issues: &mut RowIssues) {
        if t.is_nan() {
            issues.bad_time = true;
            let h = self.header[self.positions[Column::T.index()].unwrap_or(0)].clone();
            self.warn(
                WarningKind::TimeMissing,
                Some(Column::T),
                Some(h),
                "no time: the sample is kept and the estimators flag bad_time_step".to_string(),
            );
            return;
        }
        if self.summary.first_t.is_none() {
            self.summary.first_t = Some(t);
        }
        self.summary.last_t = Some(t);
        let Some(prev) = self.last_t.replace(t) else {
            return;
        };
        let dt = t - prev;
        if dt <= 0.0 {
            issues.bad_time = true;
            self.time_not_increasing(prev, t);
            return;
        }
        self.summary.max_dt = Some(self.summary.max_dt.map_or(dt, |m| m.max(dt)));
        self.summary.min_dt = Some(self.summary.min_dt.map_or(dt, |m| m.min(dt)));
        if self.first_dts.len() < NOMINAL_DT_SAMPLES {
            self.first_dts.push(dt);
            if self.first_dts.len() >= 3 {
                let mut sorted = self.first_dts.clone();
                sorted.sort_by(f64::total_cmp);
                self.summary.nominal_dt = Some(sorted[sorted.len() / 2]);
            }
        }
        let Some(nominal) = self.summary.nominal_dt else {
            return;
        };
        if dt > self.options.gap_factor * nominal {
            issues.time_gap = true;
            self.warn(
                WarningKind::TimeGap,
                Some(Column::T),
                None,
                format!(
                    "gap in time: {prev} to {t} s, {:.1} times the nominal step {} s",
                    dt / nominal,
                    seconds(nominal)
                ),
            );
        } else if (dt - nominal).abs() > self.options.jitter_tolerance * nominal {
            self.warn(
                WarningKind::TimeJitter,
                Some(Column::T),
                None,
                format!(
                    "time step {} s against a nominal {} s (jitter)",
                    seconds(dt),
                    seconds(nominal)
                ),
            );
        }
    }

    /// Warns of a time `t` that repeats or goes back from the previous row's `prev`.
    fn time_not_increasing(&mut self, prev: f64, t: f64) {
        let dt = t - prev;
        if dt == 0.0 && !self.rate_checked {
            self.zero_steps += 1;
        }
        let what = if dt == 0.0 { "repeated" } else { "goes back" };
        // The gate holds the latest time taken: every row until the time passes it
        // again is held, not only this one.
        let held = match self.gate.last() {
            Some(last) if dt < 0.0 => format!(
                "this sample and every one until the time passes {last} s again are kept, \
                 the estimators holding their estimate, flagged bad_time_step"
            ),
            _ => "the sample is kept and the estimators flag bad_time_step".to_string(),
        };
        self.warn(
            WarningKind::TimeNotIncreasing,
            Some(Column::T),
            None,
            format!("time {what} ({prev} then {t}): {held}"),
        );
    }
}

/// A time step \[s\] as a reader writes it: to the nanosecond, without the rounding noise
/// of a difference of two stamps (`0.0010000000000000009` is `0.001`).
fn seconds(x: f64) -> String {
    format!("{}", (x * 1e9).round() / 1e9)
}

//! A 3-D pass between its rows: the records read ahead, the bank, the checks that watch
//! every row, and the scores.
use std::collections::VecDeque;
use std::io::BufRead;

use pendtilt_core::spatial::{Attitude, SpatialSample};
use pendtilt_core::{Flags, StepGate};

use super::checks::{check_time_unit, slip_warning};
use super::gyro_units::GyroUnits;
use super::rows::RowInput;
use super::{Options3d, Pass, Row, Setup, Sink3d, HEAD_ROWS};
use crate::bank::spatial::score::Inclination;
use crate::bank::spatial::Bank3d;
use crate::io::plateau::LOOK_AHEAD_ROWS;
use crate::io::{Log3dReader, Log3dRecord};
use crate::pipeline::Scorer;
use crate::units::AccelMagnitude;

/// The state of a pass from one row to the next.
pub(super) struct Run<'a> {
    file: &'a str,
    setup: &'a Setup,
    quaternion: bool,
    live: bool,
    bank: Bank3d,
    names: Vec<&'static str>,
    truth: bool,
    row: RowInput<'a>,
    gyro_units: GyroUnits,
    accel_unit: AccelMagnitude,
    /// m/s^2 per unit of the accelerometer's columns (`--accel-unit`).
    accel_scale: f64,
    gate: StepGate<f64>,
    scorer: Scorer<Inclination>,
    quats: Vec<Option<[f64; 4]>>,
    rows: u64,
    /// Rows with a speed reading, and those some estimator flagged as wheel slip.
    speed_rows: u64,
    slip_rows: u64,
    /// The rows after the current one: clips are found [`LOOK_AHEAD_ROWS`] ahead, lone
    /// time stamps one row ahead.
    pub(super) ahead: VecDeque<Log3dRecord>,
    look_ahead: usize,
    /// Live: the first rows, kept as they go by and judged when there are enough.
    seen: Vec<Log3dRecord>,
}

impl<'a> Run<'a> {
    /// A pass of `bank` over the log `file` (header `header`), `live` or not.
    pub(super) fn new(
        bank: Bank3d,
        truth: bool,
        setup: &'a Setup,
        file: &'a str,
        header: &'a [String],
        quaternion: bool,
        live: bool,
    ) -> Self {
        let names = bank.names();
        let look_ahead = if live { 0 } else { LOOK_AHEAD_ROWS };
        Self {
            file,
            setup,
            quaternion,
            live,
            row: RowInput::new(setup, file, header),
            gyro_units: GyroUnits::new(&setup.settings.ekf.params),
            accel_unit: AccelMagnitude::default(),
            accel_scale: setup
                .accel_unit
                .map_or(1.0, |u| u.metres_per_second_squared()),
            gate: StepGate::new(),
            scorer: Scorer::new(setup.score_from, names.len()),
            quats: vec![None; names.len()],
            rows: 0,
            speed_rows: 0,
            slip_rows: 0,
            ahead: VecDeque::with_capacity(look_ahead + 1),
            look_ahead,
            seen: Vec::with_capacity(if live { HEAD_ROWS } else { 0 }),
            bank,
            names,
            truth,
        }
    }

    /// Reads rows (the `head` already read first) until [`Self::ahead`] holds the rows
    /// the next one needs, or the log ends. Live, a malformed line is said, skipped and
    /// given its NaN row in place.
    pub(super) fn read_ahead<R: BufRead>(
        &mut self,
        log: &mut Log3dReader<R>,
        head: &mut impl Iterator<Item = Log3dRecord>,
        opts: &Options3d,
        sink: &mut dyn Sink3d,
    ) -> anyhow::Result<()> {
        while self.ahead.len() <= self.look_ahead {
            let r = match head.next() {
                Some(r) => r,
                None => match log.next_record() {
                    Ok(Some(r)) => r,
                    Ok(None) => break,
                    // Live, nothing is held ahead: the bad line's row goes out in its place.
                    Err(e) if self.live && e.is_one_line() => {
                        opts.notice(&format!(
                            "warning: {}:{}: {}: the line is skipped; its output row is \
                             NaN, flagged bad_line",
                            self.file,
                            e.line.unwrap_or(0),
                            e.what()
                        ));
                        log.resume_after(&e);
                        self.bad_line(sink)?;
                        continue;
                    }
                    Err(e) => return Err(e.into()),
                },
            };
            // In m/s^2 from here on (--accel-unit); before the bounds, for the unit check.
            let mut r = r;
            r.accel = r.accel.map(|a| a * self.accel_scale);
            (self.accel_unit).add(r.accel.iter().map(|a| a * a).sum::<f64>().sqrt());
            self.row.find_clips(&r);
            self.ahead.push_back(r);
        }
        Ok(())
    }

    /// The NaN row, flagged `bad_line`, of a malformed line of a live stream.
    fn bad_line(&mut self, sink: &mut dyn Sink3d) -> anyhow::Result<()> {
        let n = self.names.len();
        let blank = vec![
            Attitude {
                roll: f64::NAN,
                pitch: f64::NAN,
                flags: Flags::BAD_LINE,
            };
            n
        ];
        sink.row(Row {
            t: f64::NAN,
            est: &blank,
            quats: &vec![None; n],
            truth: (f64::NAN, f64::NAN),
            sample: &SpatialSample::after(f64::NAN),
        })?;
        self.rows += 1;
        Ok(())
    }

    /// Record `r` through the bank into `sink`, scored when the log has the truth.
    pub(super) fn row(&mut self, r: Log3dRecord, sink: &mut dyn Sink3d) -> anyhow::Result<()> {
        let setup = self.setup;
        if self.live && self.seen.len() < HEAD_ROWS {
            self.seen.push(r);
            if self.seen.len() == HEAD_ROWS {
                check_time_unit(self.file, &self.seen, setup.time_given)?;
            }
        }
        let (t, s, roll, pitch) = self.row.sample(&r, &self.ahead, &mut self.gate);
        self.gyro_units.add(&r, s.dt, setup.angle_scale);
        let bank = &mut self.bank;
        bank.update_clipped(&s, self.row.clipped);
        if let Some((re, n)) = bank.restarted() {
            self.row.restart_warning(r.line, re, n);
        }
        bank.flag_implausible(self.row.implausible);
        let est = bank.outputs();
        self.speed_rows += u64::from(s.speed.is_finite());
        self.slip_rows += u64::from(est.iter().any(|e| e.flags.contains(Flags::SLIP)));
        for (i, q) in self.quats.iter_mut().enumerate() {
            *q = if self.quaternion {
                bank.quaternion(i)
            } else {
                None
            };
        }
        if self.truth {
            (self.scorer).row(t, |i, sc| {
                sc.add((est[i].roll, est[i].pitch), (roll, pitch))
            });
        }
        sink.row(Row {
            t,
            est,
            quats: &self.quats,
            truth: (roll, pitch),
            sample: &s,
        })?;
        self.rows += 1;
        Ok(())
    }

    /// What the pass gave, with the warnings over the whole log.
    pub(super) fn finish<R: BufRead>(self, log: &mut Log3dReader<R>) -> anyhow::Result<Pass> {
        let (file, setup) = (self.file, self.setup);
        if self.live && self.seen.len() < HEAD_ROWS {
            check_time_unit(file, &self.seen, setup.time_given)?;
        }
        let mut warnings = self.row.warnings();
        if let Some((line, n)) = log.take_nul() {
            warnings.push(format!(
                "{file}:{line}: {}",
                crate::io::nul_message(line, n)
            ));
        }
        let mut found = self.gyro_units.findings(file);
        found.extend(
            (self.accel_unit)
                .finding("ax, ay, az", setup.accel_unit)
                .map(|f| format!("{file}: {}", f.message)),
        );
        // A gyro in deg/s, or an accelerometer in g, makes the speed disagree with everything
        // too: the unit is the cause.
        if found.is_empty() {
            if let Some(w) = slip_warning(file, self.slip_rows, self.speed_rows) {
                warnings.push(w);
            }
        }
        warnings.extend(found);
        let (window, scores) = self.scorer.finish();
        Ok(Pass {
            rows: self.rows,
            names: self.names,
            truth: self.truth,
            scores,
            window,
            warnings,
        })
    }
}

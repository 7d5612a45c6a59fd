//! Clips of a planar log's gyro and accelerometer found in the readings themselves
//! ([`crate::io::plateau`], as on 3-D logs), for the sensors whose full scale the rig does
//! not give: rows are handed on a number of rows after they are read, so that a clip found
//! on a row marks the readings at its level from that many rows before it.
use std::collections::VecDeque;

use crate::bank::{BankSettings, Inputs};
use crate::io::plateau::{NewLevel, PlateauWatch};
use crate::io::{Column, LogReader, LogRecord, LogWarning, WarningKind};

/// A watched column: where it is, for the warning.
struct Watched {
    /// 1-based position in the header.
    position: usize,
    header: String,
}

/// Finds clips in a planar log's rows and delays the rows by its look-ahead.
pub(crate) struct ClipFinder {
    file: String,
    /// The gyro, when the log has one and the rig gives no `[gyro] full_scale`.
    gyro: Option<(PlateauWatch<1>, Watched)>,
    /// ax and ay, when the log has them and the rig gives no `[accel] full_scale`.
    accel: Option<(PlateauWatch<2>, [Watched; 2])>,
    look_ahead: usize,
    queue: VecDeque<LogRecord>,
    found: Vec<LogWarning>,
}

impl ClipFinder {
    /// The finder for `log` run with `settings`, handing rows on `look_ahead` rows late.
    pub(crate) fn new<R: std::io::BufRead>(
        log: &LogReader<R>,
        settings: &BankSettings,
        look_ahead: usize,
    ) -> Self {
        let c = log.columns();
        let watched = |col: Column| {
            c.status(col).position.map(|p| Watched {
                position: p + 1,
                header: log.header().get(p).cloned().unwrap_or_default(),
            })
        };
        let rig = &settings.rig;
        let gyro = watched(Column::Gyro)
            .filter(|_| rig.gyro.checked_full_scale().is_none())
            .map(|w| (PlateauWatch::new(), w));
        let accel = match (watched(Column::Ax), watched(Column::Ay)) {
            (Some(x), Some(y)) if rig.accel.checked_full_scale().is_none() => {
                Some((PlateauWatch::new(), [x, y]))
            }
            _ => None,
        };
        Self {
            file: log.file().to_string(),
            gyro,
            accel,
            look_ahead,
            queue: VecDeque::with_capacity(look_ahead + 1),
            found: Vec::new(),
        }
    }

    /// Takes the next row read; the row whose turn it is, with its clipped sensors.
    pub(crate) fn push(&mut self, rec: LogRecord) -> Option<(LogRecord, Inputs)> {
        let s = &rec.sample;
        if let Some((w, col)) = &mut self.gyro {
            if let Some(f) = w.observe([s.gyro]) {
                let w = warning(&self.file, rec.line, col, f, "rad/s", "[gyro]");
                self.found.push(w);
            }
        }
        if let Some((w, cols)) = &mut self.accel {
            if let Some(f) = w.observe([s.ax, s.ay]) {
                let w = warning(&self.file, rec.line, &cols[f.axis], f, "m/s^2", "[accel]");
                self.found.push(w);
            }
        }
        self.queue.push_back(rec);
        if self.queue.len() > self.look_ahead {
            self.pop()
        } else {
            None
        }
    }

    /// The next row still held (at the end of the log), with its clipped sensors.
    pub(crate) fn pop(&mut self) -> Option<(LogRecord, Inputs)> {
        let rec = self.queue.pop_front()?;
        let s = &rec.sample;
        let clipped = Inputs {
            phi: false,
            gyro: self
                .gyro
                .as_ref()
                .is_some_and(|(w, _)| w.clipped([s.gyro])[0]),
            accel: self
                .accel
                .as_ref()
                .is_some_and(|(w, _)| w.clipped([s.ax, s.ay]).contains(&true)),
        };
        Some((rec, clipped))
    }

    /// The warnings of the clips found since the last call (one per level).
    pub(crate) fn drain_warnings(&mut self) -> std::vec::Drain<'_, LogWarning> {
        self.found.drain(..)
    }
}

/// Says that a run of identical readings of `col` is a clip.
fn warning(file: &str, line: u64, col: &Watched, f: NewLevel, unit: &str, rig: &str) -> LogWarning {
    LogWarning {
        file: file.to_string(),
        line,
        column: None,
        header: None,
        kind: WarningKind::Clipped,
        message: format!(
            "column {} (`{}`): {} {unit} on {} rows in a row up to here, which a sensor with \
             noise never writes: a clip at an unknown full scale; readings at +-{} {unit} are \
             clipped (flagged saturated, taken as at the full scale); if it is the range of \
             the sensor, give it as the rig's {rig} full_scale",
            col.position,
            col.header,
            f.reading,
            f.rows,
            f.reading.abs()
        ),
    }
}

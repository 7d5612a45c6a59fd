//! Clips of a planar log's gyro and accelerometer found in the readings themselves
//! ([`crate::io::plateau`], as on 3-D logs): at an unknown full scale when the rig gives
//! none, or below the full scale the rig gives (the sensor's range is smaller than the
//! rig says). Rows are handed on a number of rows after they are read, so that a clip found
//! on a row marks the readings at its level from that many rows before it.
use std::collections::VecDeque;

use crate::bank::planar::{BankSettings, Inputs};
use crate::io::plateau::{NewLevel, PlateauWatch};
use crate::io::{Column, LogReader, LogRecord, LogWarning, WarningKind};
use crate::sensors::Sensor;

/// A watched column: where it is, for the warning.
struct Watched {
    /// 1-based position in the header.
    position: usize,
    header: String,
    /// The rig's full scale of its sensor, if it gives one.
    full_scale: Option<f64>,
}

/// Finds clips in a planar log's rows and delays the rows by its look-ahead.
pub(crate) struct ClipFinder {
    file: String,
    /// The gyro, when the log has one.
    gyro: Option<(PlateauWatch<1>, Watched)>,
    /// ax and ay, when the log has them.
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
        let rig = &settings.rig;
        let watched = |col: Column, full_scale: Option<f64>| {
            c.status(col).position.map(|p| Watched {
                position: p + 1,
                header: log.header().get(p).cloned().unwrap_or_default(),
                full_scale,
            })
        };
        let gyro =
            watched(Column::Gyro, rig.gyro.checked_full_scale()).map(|w| (PlateauWatch::new(), w));
        let fs = rig.accel.checked_full_scale();
        let accel = match (watched(Column::Ax, fs), watched(Column::Ay, fs)) {
            (Some(x), Some(y)) => Some((PlateauWatch::new(), [x, y])),
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
                self.found
                    .extend(warning(&self.file, rec.line, col, f, "rad/s", "[gyro]"));
            }
        }
        if let Some((w, cols)) = &mut self.accel {
            if let Some(f) = w.observe([s.ax, s.ay]) {
                let col = &cols[f.axis];
                self.found
                    .extend(warning(&self.file, rec.line, col, f, "m/s^2", "[accel]"));
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
        let gyro = (self.gyro.as_ref()).is_some_and(|(w, _)| w.clipped([s.gyro])[0]);
        let accel =
            (self.accel.as_ref()).is_some_and(|(w, _)| w.clipped([s.ax, s.ay]).contains(&true));
        let clipped = Inputs::from_fn(|sensor| match sensor {
            Sensor::Gyro => gyro,
            Sensor::Accel => accel,
            _ => false,
        });
        Some((rec, clipped))
    }

    /// The warnings of the clips found since the last call (one per level).
    pub(crate) fn drain_warnings(&mut self) -> std::vec::Drain<'_, LogWarning> {
        self.found.drain(..)
    }
}

/// Says that a run of identical readings of `col` is a clip: at an unknown full scale, or
/// below the rig's. None for a clip at the rig's full scale, which the rig already told.
fn warning(
    file: &str,
    line: u64,
    col: &Watched,
    f: NewLevel,
    unit: &str,
    rig: &str,
) -> Option<LogWarning> {
    let level = f.reading.abs();
    let what = match col.full_scale {
        Some(fs) if level >= fs => return None,
        Some(fs) => format!(
            "a clip below the rig's {rig} full_scale {fs} {unit}: the sensor's range is \
             smaller than the rig says; readings at +-{level} {unit} are clipped (flagged \
             saturated, taken as at the full scale); if it is the range of the sensor, give \
             it as the rig's {rig} full_scale"
        ),
        None => format!(
            "a clip at an unknown full scale; readings at +-{level} {unit} are clipped \
             (flagged saturated, taken as at the full scale); if it is the range of the \
             sensor, give it as the rig's {rig} full_scale"
        ),
    };
    Some(LogWarning {
        file: file.to_string(),
        line,
        column: None,
        header: None,
        kind: WarningKind::Clipped,
        message: format!(
            "column {} (`{}`): {} {unit} on {} rows in a row up to here, which a sensor with \
             noise never writes: {what}",
            col.position, col.header, f.reading, f.rows,
        ),
    })
}

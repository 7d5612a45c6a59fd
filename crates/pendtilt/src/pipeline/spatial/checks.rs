//! Checks over a whole 3-D log: its time unit on the first rows, and the share of rows
//! flagged as wheel slip.
use anyhow::bail;

use crate::io::plausibility::{implausible_given_unit, implausible_step};
use crate::io::Log3dRecord;

/// Most of a log flagged as wheel slip is a speed in the wrong unit, not slip: a wheel
/// slips for seconds, and a speed in km/h (3.6x) or mph (2.24x) disagrees with the
/// accelerometer on every change of speed. Measured on ride3d (seed 1, 120 s): 77 % of the
/// rows flagged with the speed in km/h (ekf3d 31.8 deg RMS); in m/s none, 3 % on
/// ride3d_slip, 1.6 % with the speed on one row in 20.
const SLIP_SHARE_WARNING: f64 = 0.1;

/// The warning for a log whose rows with a speed reading are flagged as slip beyond
/// [`SLIP_SHARE_WARNING`].
pub(super) fn slip_warning(file: &str, slip_rows: u64, speed_rows: u64) -> Option<String> {
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

/// The median step of the first rows must be a sensor rate (as the planar reader checks).
pub(super) fn check_time_unit(
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

//! The gap rule, for planar and 3-D logs alike: which sensor comes back after being missing
//! for longer than the restart gap ([`super::RESTART_GAP`]), so that the banks restart the
//! estimators reading it instead of letting them resume from a state the gap has made
//! stale (a gyro rate integrated for seconds).
use super::{Inputs, Sensor, SENSORS};

/// Watches the time since each sensor's last good reading.
#[derive(Debug, Clone, Default)]
pub struct GapWatch {
    /// Time since the first accepted step \[s\].
    now: f64,
    /// When each sensor of the table last gave a complete, finite reading \[s\].
    last_good: [Option<f64>; SENSORS.len()],
    /// The sensors missing on the last sample for longer than the restart gap.
    stale: Inputs,
}

/// Sensors back after a long gap, and the longest of their gaps \[s\].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GapEnd {
    /// The sensors that came back.
    pub sensors: Inputs,
    /// The longest gap among them \[s\].
    pub gap: f64,
}

impl GapWatch {
    /// Nothing seen yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// The sensors missing on the last sample observed for longer than the restart gap:
    /// the estimators reading them have nothing to go on until they restart.
    pub fn stale(&self) -> Inputs {
        self.stale
    }

    /// Takes a sample `dt` \[s\] after the previous one (as the bank receives it: a
    /// refused time step is NaN and moves nothing) on which the sensors `good` gave a
    /// reading (a clip counts as one: the sensor is there, its value beyond the clip); the
    /// sensors that come back on it after a gap longer than `restart_gap` \[s\], if any.
    /// A sensor never good (one the log lacks, or no estimator reads) is never stale.
    pub fn observe(&mut self, dt: f64, good: Inputs, restart_gap: f64) -> Option<GapEnd> {
        if !dt.is_finite() {
            return None;
        }
        self.now += dt;
        let now = self.now;
        let last_good = self.last_good;
        let too_long = |s: Sensor| last_good[s.index()].is_some_and(|l| now - l > restart_gap);
        self.stale = Inputs::from_fn(|s| !good.has(s) && too_long(s));
        let back = Inputs::from_fn(|s| good.has(s) && too_long(s));
        let gap = back
            .iter()
            .filter_map(|s| last_good[s.index()])
            .fold(0.0f64, |g, l| g.max(now - l));
        for s in good.iter() {
            self.last_good[s.index()] = Some(now);
        }
        (!back.is_empty()).then_some(GapEnd { sensors: back, gap })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn good(phi: bool, gyro: bool, accel: bool) -> Inputs {
        [
            (phi, Sensor::Encoder),
            (gyro, Sensor::Gyro),
            (accel, Sensor::Accel),
        ]
        .into_iter()
        .filter(|(on, _)| *on)
        .fold(Inputs::NONE, |set, (_, s)| set.with(s))
    }

    #[test]
    fn a_sensor_back_after_more_than_the_gap_is_reported_once() {
        let mut w = GapWatch::new();
        assert_eq!(w.observe(0.0, Inputs::ALL, 0.5), None);
        // The gyro missing for 0.6 s (600 rows), the others present.
        for _ in 0..600 {
            assert_eq!(w.observe(1e-3, good(true, false, true), 0.5), None);
        }
        assert_eq!(w.stale(), Inputs::GYRO);
        let r = w.observe(1e-3, Inputs::ALL, 0.5).unwrap();
        assert_eq!(r.sensors, Inputs::GYRO);
        assert!((r.gap - 0.601).abs() < 1e-9, "{}", r.gap);
        assert!(w.stale().is_empty());
        assert_eq!(w.observe(1e-3, Inputs::ALL, 0.5), None);
        // 0.4 s missing is bridged; a refused step moves no time.
        for _ in 0..400 {
            w.observe(1e-3, good(false, true, true), 0.5);
        }
        w.observe(f64::NAN, Inputs::ALL, 0.5);
        assert_eq!(w.observe(1e-3, Inputs::ALL, 0.5), None);
        // A time jump of 10 s is a gap of every sensor.
        let r = w.observe(10.0, Inputs::ALL, 0.5).unwrap();
        assert_eq!(r.sensors, Inputs::ALL);
        assert!((r.gap - 10.0).abs() < 1e-9, "{}", r.gap);
    }

    /// A sensor the log lacks is never good, so never stale nor back.
    #[test]
    fn a_sensor_never_seen_is_never_stale() {
        let mut w = GapWatch::new();
        for _ in 0..2000 {
            assert_eq!(w.observe(1e-3, Inputs::PHI_GYRO, 0.5), None);
            assert!(w.stale().is_empty());
        }
    }
}

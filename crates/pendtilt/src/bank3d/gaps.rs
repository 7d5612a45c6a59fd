//! Long sensor gaps in a 3-D log: which sensor comes back after being missing for longer
//! than the restart gap (the planar bank's rule, [`crate::sensors::RESTART_GAP`]), so that the
//! bank restarts the estimators reading it instead of letting them resume from a state the
//! gap has made stale (a gyro rate integrated for seconds).
use pendtilt_core::spatial::SpatialSample;

use crate::bank::Inputs;

/// Watches the time since each sensor's last good reading.
#[derive(Debug, Clone, Default)]
pub struct GapWatch {
    /// Time since the first accepted step \[s\].
    now: f64,
    /// When phi, gyro and the accelerometer last gave a complete, finite reading \[s\].
    last_good: [Option<f64>; 3],
    /// The sensors missing on the last sample for longer than the restart gap.
    stale: Inputs,
}

/// A restart: the sensors back after a long gap, and the longest of their gaps \[s\].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Restart3d {
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

    /// Takes sample `s` (its `dt` as the bank receives it: a refused time step is NaN and
    /// moves nothing), whose `clipped` sensors were read, at a clip, and are missing only
    /// because a clip is (a clip is no gap: the sensor is there, its rate beyond the
    /// clip); the sensors that come back on it after a gap longer than `restart_gap` \[s\],
    /// if any.
    pub fn observe(
        &mut self,
        s: &SpatialSample<f64>,
        clipped: Inputs,
        restart_gap: f64,
    ) -> Option<Restart3d> {
        if !s.dt.is_finite() {
            return None;
        }
        self.now += s.dt;
        let good = [
            s.phi.iter().all(|v| v.is_finite()),
            clipped.gyro || s.gyro.iter().all(|v| v.is_finite()),
            clipped.accel || s.accel.iter().all(|v| v.is_finite()),
        ];
        let stale =
            |i: usize| !good[i] && self.last_good[i].is_some_and(|l| self.now - l > restart_gap);
        self.stale = Inputs {
            phi: stale(0),
            gyro: stale(1),
            accel: stale(2),
        };
        let mut back = [false; 3];
        let mut gap = 0.0f64;
        for i in 0..3 {
            if !good[i] {
                continue;
            }
            if let Some(last) = self.last_good[i] {
                if self.now - last > restart_gap {
                    back[i] = true;
                    gap = gap.max(self.now - last);
                }
            }
            self.last_good[i] = Some(self.now);
        }
        let sensors = Inputs {
            phi: back[0],
            gyro: back[1],
            accel: back[2],
        };
        (!sensors.is_empty()).then_some(Restart3d { sensors, gap })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample(dt: f64, phi: bool, gyro: bool, accel: bool) -> SpatialSample<f64> {
        let v = |ok: bool| if ok { 0.1 } else { f64::NAN };
        SpatialSample {
            dt,
            phi: [v(phi); 2],
            gyro: [v(gyro); 3],
            accel: [v(accel); 3],
            speed: f64::NAN,
        }
    }

    impl GapWatch {
        fn observe_all(&mut self, s: &SpatialSample<f64>, gap: f64) -> Option<Restart3d> {
            self.observe(s, Inputs::default(), gap)
        }
    }

    /// A clipped reading (read as missing) is no gap: 0.6 s of it restarts nothing.
    #[test]
    fn a_clip_is_not_a_gap() {
        let mut w = GapWatch::new();
        w.observe_all(&sample(0.0, true, true, true), 0.5);
        let clipped = Inputs {
            gyro: true,
            accel: true,
            ..Inputs::default()
        };
        for _ in 0..600 {
            assert_eq!(
                w.observe(&sample(1e-3, true, false, false), clipped, 0.5),
                None
            );
        }
        assert_eq!(w.observe_all(&sample(1e-3, true, true, true), 0.5), None);
    }

    #[test]
    fn a_sensor_back_after_more_than_the_gap_is_reported_once() {
        let mut w = GapWatch::new();
        assert_eq!(w.observe_all(&sample(0.0, true, true, true), 0.5), None);
        // The gyro missing for 0.6 s (600 rows), the others present.
        for _ in 0..600 {
            assert_eq!(w.observe_all(&sample(1e-3, true, false, true), 0.5), None);
        }
        let r = w.observe_all(&sample(1e-3, true, true, true), 0.5).unwrap();
        assert!(r.sensors.gyro && !r.sensors.phi && !r.sensors.accel);
        assert!((r.gap - 0.601).abs() < 1e-9, "{}", r.gap);
        assert_eq!(w.observe_all(&sample(1e-3, true, true, true), 0.5), None);
        // 0.4 s missing is bridged; a refused step moves no time.
        for _ in 0..400 {
            w.observe_all(&sample(1e-3, false, true, true), 0.5);
        }
        w.observe_all(&sample(f64::NAN, true, true, true), 0.5);
        assert_eq!(w.observe_all(&sample(1e-3, true, true, true), 0.5), None);
        // A time jump of 10 s is a gap of every sensor.
        let r = w.observe_all(&sample(10.0, true, true, true), 0.5).unwrap();
        assert_eq!(r.sensors, Inputs::ALL);
    }
}

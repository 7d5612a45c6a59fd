//! A gyro that clips often: its readings within range are then a biased sample.
//!
//! A reading at the full scale says only that the rate is beyond it. Where the body's
//! vibration carries the rate across the full scale many times a second, the readings that
//! stay within range are the vibration's troughs: their mean is off by much of the
//! vibration's amplitude, and a filter that integrates them drifts. [`ClipGate`] says when
//! to take the gyro as missing instead: once the share of readings at the full scale over
//! the last seconds ([`CLIPPED_SHARE_TAU`]) reaches [`HEAVY_CLIPPING`], until
//! [`CLIP_HOLD`] after the last clipped reading. A rare clip (a manoeuvre's peak) leaves
//! the readings as they are.
//!
//! Measured with the planar EKF on simulated scooter rides (seeds 1, 3, 4, 5, 20 s, and 6,
//! 12 s; every gyro reading clamped at the full scale, `[gyro] full_scale` in the rig),
//! RMS error from the truth over the whole log (`pendtilt estimate --only ekf`'s summary),
//! without the gate -> with it (the UKF measured the same at 0.3 rad/s on all five
//! rides):
//!
//! | full scale | readings at it | EKF |
//! |---|---|---|
//! | 0.3 rad/s | 30-44 % | 1.60-2.49 -> 0.48-0.58 deg |
//! | 0.5 rad/s | 6-19 % | 0.60-1.15 -> 0.45-0.53 deg |
//! | 0.6 rad/s | 2-10 % | 0.32-0.73 -> 0.29-0.49 deg |
//! | 0.7 rad/s | 1-5 % | 0.16-0.45 -> 0.16-0.45 deg |
//! | 0.8, 1.0 rad/s | 0-2 % | unchanged (0.12-0.28 deg) |
//!
//! Better on 14 of the 25 rides and levels, unchanged on 10, worse on 1: seed 6 at 0.7
//! rad/s (0.368 -> 0.386 deg), where a manoeuvre's own clips opened the gate and the
//! filter ran on the pendulum alone through a turn. Without the gyro the filter runs on
//! the pendulum alone (0.58 deg on the seed-6 ride), which is what the gate gives where
//! the gyro clips most. Counting clip onsets per second instead of the share (2, 5,
//! 10 /s) measured no better at 0.7 rad/s.
use crate::Real;

/// Time constant \[s\] of the share of gyro readings at the full scale. 1 s followed a
/// manoeuvre's own peaks (the gate then cost accuracy at 0.7-0.8 rad/s); 5 s was slower to
/// engage at 0.5-0.6 rad/s. 3 s measured best over the rides above.
pub const CLIPPED_SHARE_TAU: f64 = 3.0;

/// The share of readings at the full scale from which the readings within range are not
/// used (0.08). 0.15 measured worse at 0.5-0.6 rad/s (up to 0.82 deg, against 0.62), 0.04
/// at 0.7-0.8 rad/s (0.27 deg against 0.22 at 0.8 on seed 6).
pub const HEAVY_CLIPPING: f64 = 0.08;

/// How long after the last clipped reading the gyro stays unused \[s\] (1 s). The filter
/// needs that long to forget what the biased readings did: holding 50 ms or 200 ms after
/// each clip measured 0.60-0.94 deg at 0.3 rad/s (seed 6), 1 s 0.54.
pub const CLIP_HOLD: f64 = 1.0;

/// Decides, row by row, whether a gyro's readings are used (see the module).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClipGate<T> {
    /// Share of recent readings at the full scale.
    share: T,
    /// Time since the last clipped reading while clipping heavily \[s\]; `None` if not
    /// within [`CLIP_HOLD`] of one.
    since_heavy: Option<T>,
}

impl<T: Real> Default for ClipGate<T> {
    fn default() -> Self {
        Self::new()
    }
}

impl<T: Real> ClipGate<T> {
    /// No reading seen: the gyro is used.
    pub fn new() -> Self {
        Self {
            share: T::zero(),
            since_heavy: None,
        }
    }

    /// One row, `dt` after the last (not finite or not positive: no time passes), whose
    /// gyro reads at the full scale when `clipped`. Returns `true` when this row's gyro
    /// reading should be taken as missing.
    pub fn offer(&mut self, dt: T, clipped: bool) -> bool {
        let dt = if dt.is_finite() && dt > T::zero() {
            dt
        } else {
            T::zero()
        };
        let a = (dt / T::lit(CLIPPED_SHARE_TAU)).min(T::one());
        let hit = if clipped { T::one() } else { T::zero() };
        self.share += a * (hit - self.share);
        if clipped && self.share >= T::lit(HEAVY_CLIPPING) {
            self.since_heavy = Some(T::zero());
        } else if let Some(t) = self.since_heavy.as_mut() {
            *t += dt;
            if *t > T::lit(CLIP_HOLD) {
                self.since_heavy = None;
            }
        }
        self.since_heavy.is_some()
    }

    /// The share of recent readings at the full scale.
    pub fn share(&self) -> T {
        self.share
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rare_clips_pass_heavy_clipping_gates_until_a_second_after() {
        let dt = 1e-3;
        let mut g = ClipGate::<f64>::new();
        // One reading in 50 at the full scale (2 %) for 20 s: never gated.
        assert!((0..20_000).all(|k| !g.offer(dt, k % 50 == 0)));
        assert!((g.share() - 0.02).abs() < 0.005, "{}", g.share());
        // One in 5 (20 %): gated once the share reaches 8 %, which a one-pole of 3 s
        // from 2 % takes 3 ln((0.20 - 0.02) / (0.20 - 0.08)) = 1.2 s to do.
        let first = (0..5_000).position(|k| g.offer(dt, k % 5 == 0)).unwrap();
        assert!((1100..1300).contains(&first), "{first}");
        // No more clips (the last was that row): gated for 1 s more, then used.
        let used = (1..3_000).find(|_| !g.offer(dt, false)).unwrap();
        assert!((999..=1001).contains(&used), "{used}");
        // A bad time step passes no time.
        let mut h = ClipGate::<f64>::new();
        assert!(!h.offer(f64::NAN, true) && !h.offer(-1.0, true));
        assert_eq!(h.share(), 0.0);
    }
}

//! The phases of a ride, found from the log alone, never from the truth:
//! turning, braking and accelerating, from the `speed` column and the gyro's z component.
//!
//! - turning: the centripetal acceleration `|v w_z|` is above [`PHASE_ACCEL`], `v` the
//!   smoothed speed and `w_z` the smoothed gyro z (body up; on a level road the yaw rate,
//!   on an 8 deg grade or bank 0.99 of it);
//! - braking: the derivative of the smoothed speed is below `-PHASE_ACCEL`;
//! - accelerating: above `+PHASE_ACCEL`.
//!
//! Smoothing is offline and zero-lag: a centred moving average [`SMOOTH_S`] wide, run
//! twice (a triangular window twice as wide; -3 dB near 0.6 Hz), which removes the
//! suspension's yaw wobble, the engine and the speed sensor's noise; the derivative is a
//! centred difference over [`DIFF_S`]. Stretches shorter than [`MIN_PHASE_S`] are dropped
//! and gaps shorter than it bridged, so that a threshold crossed in noise does not flicker.
//! A turn while braking is in both phases. Windows count rows at the log's median rate.
use serde::Serialize;

/// The threshold of every phase \[m/s^2\]: 0.05 g, the acceleration that tilts the
/// specific force (and every filter that takes it as gravity) by about 3 deg. MODEL.md
/// 7.8's `ride3d` pulls away at 1.0-1.04 m/s^2 at its peak: a 1 m/s^2 threshold would
/// flicker there.
pub const PHASE_ACCEL: f64 = 0.5;

/// Width of the moving average, run twice \[s\].
pub const SMOOTH_S: f64 = 0.5;

/// Span of the centred difference of the smoothed speed \[s\].
pub const DIFF_S: f64 = 0.2;

/// Shortest phase, and longest gap bridged inside one \[s\].
pub const MIN_PHASE_S: f64 = 0.5;

/// What a vehicle is doing.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum PhaseKind {
    /// `|v w_z| > PHASE_ACCEL`.
    Turning,
    /// `dv/dt < -PHASE_ACCEL`.
    Braking,
    /// `dv/dt > PHASE_ACCEL`.
    Accelerating,
}

impl PhaseKind {
    /// Every kind, in table order.
    pub const ALL: [PhaseKind; 3] = [
        PhaseKind::Turning,
        PhaseKind::Braking,
        PhaseKind::Accelerating,
    ];

    /// Its name on the page ("turning", ...).
    pub fn word(self) -> &'static str {
        match self {
            PhaseKind::Turning => "turning",
            PhaseKind::Braking => "braking",
            PhaseKind::Accelerating => "accelerating",
        }
    }
}

/// One stretch of one kind.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Phase {
    /// Its kind.
    pub kind: PhaseKind,
    /// First row's time \[s\].
    pub from_s: f64,
    /// Last row's time \[s\].
    pub to_s: f64,
    /// The largest acceleration in it, with its sign (centripetal: positive turning left)
    /// \[m/s^2\].
    pub peak_mps2: f64,
}

/// The smoothed accelerations the phases are found from, one value per row \[m/s^2\]
/// (NaN where the speed or the gyro was missing around the row).
#[derive(Debug, Clone, PartialEq)]
pub struct RideSignals {
    /// Centripetal: smoothed speed times smoothed gyro z (positive turning left).
    pub lateral: Vec<f64>,
    /// Longitudinal: the smoothed speed's derivative.
    pub longitudinal: Vec<f64>,
}

/// The centred moving average of `v` over `2 h + 1` rows, ignoring non-finite values (NaN
/// where the window has none).
fn moving_average(v: &[f64], h: usize) -> Vec<f64> {
    let mut sum = vec![0.0; v.len() + 1];
    let mut count = vec![0usize; v.len() + 1];
    for (k, x) in v.iter().enumerate() {
        let ok = x.is_finite();
        sum[k + 1] = sum[k] + if ok { *x } else { 0.0 };
        count[k + 1] = count[k] + usize::from(ok);
    }
    (0..v.len())
        .map(|k| {
            let (a, b) = (k.saturating_sub(h), (k + h + 1).min(v.len()));
            match count[b] - count[a] {
                0 => f64::NAN,
                n => (sum[b] - sum[a]) / n as f64,
            }
        })
        .collect()
}

/// The median time step \[s\] (NaN without a positive finite one).
fn median_step(t: &[f64]) -> f64 {
    let mut d: Vec<f64> = t
        .windows(2)
        .map(|w| w[1] - w[0])
        .filter(|d| d.is_finite() && *d > 0.0)
        .collect();
    if d.is_empty() {
        return f64::NAN;
    }
    d.sort_by(f64::total_cmp);
    d[d.len() / 2]
}

/// Rows in `s` seconds at step `dt` (at least one).
fn rows(s: f64, dt: f64) -> usize {
    if dt.is_finite() && dt > 0.0 {
        ((s / dt).round() as usize).max(1)
    } else {
        1
    }
}

/// The accelerations of a ride from its time \[s\], speed \[m/s\] and gyro z \[rad/s\],
/// all of one length.
pub fn signals(t: &[f64], speed: &[f64], gyro_z: &[f64]) -> RideSignals {
    let dt = median_step(t);
    let h = rows(SMOOTH_S, dt) / 2;
    let smooth = |v: &[f64]| moving_average(&moving_average(v, h), h);
    let v = smooth(speed);
    let w = smooth(gyro_z);
    let lateral = v.iter().zip(&w).map(|(v, w)| v * w).collect();
    let d = rows(DIFF_S, dt) / 2;
    let d = d.max(1);
    let n = v.len();
    let longitudinal = (0..n)
        .map(|k| {
            let (a, b) = (k.saturating_sub(d), (k + d).min(n.saturating_sub(1)));
            let span = t[b] - t[a];
            if b > a && span > 0.0 {
                (v[b] - v[a]) / span
            } else {
                f64::NAN
            }
        })
        .collect();
    RideSignals {
        lateral,
        longitudinal,
    }
}

/// The stretches of rows where `on` holds, as index ranges, gaps shorter than
/// [`MIN_PHASE_S`] bridged and stretches shorter than it dropped.
fn stretches(t: &[f64], on: impl Fn(usize) -> bool) -> Vec<(usize, usize)> {
    let mut runs: Vec<(usize, usize)> = Vec::new();
    let mut start = None;
    for k in 0..=t.len() {
        let here = k < t.len() && on(k);
        match (here, start) {
            (true, None) => start = Some(k),
            (false, Some(a)) => {
                match runs.last_mut() {
                    Some(last) if t[a] - t[last.1] < MIN_PHASE_S => last.1 = k - 1,
                    _ => runs.push((a, k - 1)),
                }
                start = None;
            }
            _ => {}
        }
    }
    runs.retain(|&(a, b)| t[b] - t[a] >= MIN_PHASE_S);
    runs
}

/// The phases of a ride from its accelerations ([`signals`]), by kind then time.
pub fn phases(t: &[f64], s: &RideSignals) -> Vec<Phase> {
    let mut out = Vec::new();
    for kind in PhaseKind::ALL {
        let value = |k: usize| match kind {
            PhaseKind::Turning => s.lateral[k],
            _ => s.longitudinal[k],
        };
        let on = |k: usize| {
            let x = value(k);
            match kind {
                PhaseKind::Turning => x.abs() > PHASE_ACCEL,
                PhaseKind::Braking => x < -PHASE_ACCEL,
                PhaseKind::Accelerating => x > PHASE_ACCEL,
            }
        };
        for (a, b) in stretches(t, on) {
            let peak = (a..=b)
                .map(value)
                .filter(|x| x.is_finite())
                .fold(0.0, |p: f64, x| if x.abs() > p.abs() { x } else { p });
            out.push(Phase {
                kind,
                from_s: t[a],
                to_s: t[b],
                peak_mps2: peak,
            });
        }
    }
    out
}

/// The phases of a ride from its time \[s\], speed \[m/s\] and gyro z \[rad/s\].
pub fn detect(t: &[f64], speed: &[f64], gyro_z: &[f64]) -> Vec<Phase> {
    phases(t, &signals(t, speed, gyro_z))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_average_skips_missing_values_and_keeps_the_length() {
        let v = [1.0, f64::NAN, 3.0, 5.0];
        let m = moving_average(&v, 1);
        assert_eq!(m.len(), 4);
        assert_eq!(m[0], 1.0);
        assert_eq!(m[1], 2.0);
        assert_eq!(m[2], 4.0);
        assert_eq!(m[3], 4.0);
        assert!(moving_average(&[f64::NAN; 3], 1)[1].is_nan());
    }

    #[test]
    fn short_gaps_are_bridged_and_short_stretches_dropped() {
        let t: Vec<f64> = (0..100).map(|k| k as f64 * 0.1).collect();
        // on 1.0-2.0 s, off 0.3 s, on 2.4-3.0 s; a lone 0.2 s stretch at 6 s
        let on =
            |k: usize| (10..=20).contains(&k) || (24..=30).contains(&k) || (60..62).contains(&k);
        assert_eq!(stretches(&t, on), vec![(10, 30)]);
    }

    #[test]
    fn a_steady_turn_and_a_braking_are_found_with_their_size() {
        // 10 m/s, braking at 2 m/s^2 from 10 s to 12 s, turning at 0.2 rad/s 20-25 s
        let dt = 0.01;
        let t: Vec<f64> = (0..4000).map(|k| k as f64 * dt).collect();
        let speed: Vec<f64> = t
            .iter()
            .map(|&t| 10.0 - 2.0 * (t - 10.0).clamp(0.0, 2.0))
            .collect();
        let gyro: Vec<f64> = t
            .iter()
            .map(|&t| if (20.0..25.0).contains(&t) { 0.2 } else { 0.0 })
            .collect();
        let p = detect(&t, &speed, &gyro);
        assert_eq!(p.len(), 2, "{p:?}");
        let turn = p.iter().find(|p| p.kind == PhaseKind::Turning).unwrap();
        // 6 m/s x 0.2 rad/s = 1.2 m/s^2; the smoothing blurs each edge by < 0.5 s
        assert!((turn.peak_mps2 - 1.2).abs() < 1e-6, "{turn:?}");
        assert!((turn.from_s - 20.0).abs() < 0.5 && (turn.to_s - 25.0).abs() < 0.5);
        let brake = p.iter().find(|p| p.kind == PhaseKind::Braking).unwrap();
        assert!((brake.peak_mps2 + 2.0).abs() < 1e-6, "{brake:?}");
        assert!((brake.from_s - 10.0).abs() < 0.5 && (brake.to_s - 12.0).abs() < 0.5);
    }
}

//! The gyro as the process's drive: its readings and their low-passes, the hold that
//! bridges missing readings, the bias kept through a hold, the re-acquisition after one,
//! and the attitude's variance while an axis is clipped.
use super::covariance::loosen_roll_pitch;
use super::ModelBased;
use crate::engine::GaussianFilter;
use crate::spatial::ekf::state::{Error, State, BIAS, N};
use crate::spatial::SpatialSample;
use crate::{Estimator, Flags, Real};
use nalgebra::Vector3;

/// Cutoff \[Hz\] of the one-pole low-pass of the gyro that bridges missing readings: the
/// last raw reading carries the angular vibration's instantaneous rate (15 deg/s for
/// 0.06 deg at 40 Hz), which a hold integrates; at 5 Hz the vibration is averaged out and
/// the lag (32 ms) costs a slowly tilting body little.
pub(super) const HOLD_HZ: f64 = 5.0;

/// Time constant \[s\] of the mean square of the gyro's departure from its low-pass
/// (HOLD_HZ): the angular vibration a hold misses, measured on the log itself.
pub(super) const VIBRATION_TAU: f64 = 1.0;

/// While the gyro is held (a missing reading, or a clipped axis read as missing) and for
/// this long \[s\] after, the gyro bias stays where it was: the encoders' innovations then
/// carry the rate the hold missed, which the filter would otherwise learn as bias through
/// the attitude-bias correlation. Measured on scooter3d (seed 3, the gyro clipped at 0.1
/// rad/s for 2 s, tests/faults3d): learnt, the z bias moved by 0.005 rad/s and ekf3d
/// took 8.3 s to come back within 0.05 deg of the fault-free run. 2 s rather than 0.5 s:
/// after 100 missing readings of one gyro axis the attitude is still 0.1-0.2 deg off
/// 0.5 s later, which went into the bias and took up to 10 s to wear off
/// (tests/gyro_bursts3d.rs).
pub(super) const BIAS_HOLD: f64 = 2.0;

/// A hold at least this long \[s\] ends with [`ModelBased::reacquire`]: 50 ms, so that
/// one missing reading (a hold of 1 ms, its error within the attitude's variance) does
/// not loosen the attitude (with every hold: 1.04 s instead of 0 back after one missing
/// gyro_x reading, tests/faults3d).
const REACQUIRE_AFTER: f64 = 0.05;

/// The standard deviation \[rad\] roll and pitch are loosened to after a hold of missing
/// gyro readings ([`ModelBased::reacquire`]): 0.5 deg, about the error 100 missing readings
/// of one axis left on scooter3d (0.4-0.5 deg).
const REACQUIRE_SD: f64 = 0.5 * core::f64::consts::PI / 180.0;

impl<T: Real, F: GaussianFilter<T, State<T>, N>> ModelBased<T, F> {
    /// [`Estimator::update`] with the gyro `axes` reading at a clip found in the log (the
    /// std crate's reader finds them): they are read as missing, and a hold that read a
    /// clip ends with roll and pitch loosened to their variance at a start, where one of
    /// missing readings loosens them to 0.5 deg: a clip hides the rate beyond it, without
    /// bound.
    pub fn update_clipped(
        &mut self,
        s: &SpatialSample<T>,
        axes: [bool; 3],
    ) -> crate::spatial::Attitude<T> {
        let mut s = *s;
        for (g, c) in s.gyro.iter_mut().zip(axes) {
            if c {
                *g = T::nan();
                self.state.gyro.clip_hold = true;
            }
        }
        self.update(&s)
    }

    /// Takes the sample's gyro reading into its low-passes, its derivative and the path's
    /// rate; whether all three axes were read.
    pub(super) fn read_gyro(&mut self, s: &SpatialSample<T>, dt: T) -> bool {
        let gyro_ok = s.gyro.iter().all(|v| v.is_finite());
        if gyro_ok {
            let st = &mut self.state.gyro;
            let g = Vector3::new(s.gyro[0], s.gyro[1], s.gyro[2]);
            st.reading = Some(g);
            let m = st.smooth.update(&g, dt);
            if dt > T::zero() {
                st.vibration.update(&(g - m).component_mul(&(g - m)), dt);
            }
            st.path.update(&g, dt);
            if dt > T::zero() && st.diff.is_started() {
                st.diff.update_all(s.gyro, dt);
            } else {
                st.diff.start_all(s.gyro);
            }
        }
        gyro_ok
    }

    /// The rate that drives the step. A missing axis takes its low-passed rate, the axes
    /// read stay as read (bridging all three for one missing axis moved the attitude
    /// 0.39 deg over 100 missing gyro_x readings on scooter3d, and the filter 8.6 s to
    /// come back).
    pub(super) fn bridged_gyro(&self, s: &SpatialSample<T>, gyro_ok: bool) -> Vector3<T> {
        if gyro_ok {
            self.state.gyro.reading.unwrap_or_else(Vector3::zeros)
        } else {
            let m = self
                .state
                .gyro
                .smooth
                .value()
                .unwrap_or_else(Vector3::zeros);
            Vector3::from_fn(|i, _| {
                if s.gyro[i].is_finite() {
                    s.gyro[i]
                } else {
                    m[i]
                }
            })
        }
    }

    /// The gyro bias held from the start of a hold until [`BIAS_HOLD`] after its end.
    pub(super) fn track_held_bias(&mut self, gyro_ok: bool, dt: T) {
        let st = &mut self.state.gyro;
        if gyro_ok {
            st.since_hold += dt;
            if st.since_hold > T::lit(BIAS_HOLD) {
                st.held_bias = None;
            }
        } else if st.held_bias.is_none() {
            st.held_bias = self.state.filter.as_ref().map(|f| f.state().bias);
            st.since_hold = T::zero();
        } else {
            st.since_hold = T::zero();
        }
    }

    /// The variance the attitude gains about each body axis over `dt` from a held or a
    /// clipped gyro, with the flags. A held gyro reading misses the rate's change, the
    /// angular vibration's above all: the attitude's variance grows as (v t)^2 over a hold
    /// of t. A hold that ends re-acquires roll and pitch.
    pub(super) fn rate_uncertainty(
        &mut self,
        s: &SpatialSample<T>,
        dt: T,
        gyro_ok: bool,
    ) -> (Flags, Vector3<T>) {
        if !gyro_ok {
            let st = &mut self.state.gyro;
            let t0 = st.held_for;
            st.held_for += dt;
            // On every axis, the ones read too: a rate missed about one axis turns the
            // others through the motion (the 2 s gyro clip of tests/faults3d: 6.06 s
            // back with the missing axes' alone, 1.74 s with all three).
            let held_for = st.held_for;
            let extra = self.hold_variance() * (held_for * held_for - t0 * t0);
            return (Flags::SAMPLE_MISSING, extra);
        }
        if self.state.gyro.held_for >= T::lit(REACQUIRE_AFTER) {
            self.reacquire();
        } else if !self.settings.use_encoders {
            // imu3d: a hold too short to re-acquire after is too short to move the
            // bias; holding it for BIAS_HOLD then pulled the attitude against the
            // correlations (one missing gyro reading: 0.07 deg worse for 20 s).
            self.state.gyro.held_bias = None;
        }
        self.state.gyro.held_for = T::zero();
        self.state.gyro.clip_hold = false;
        let extra = Vector3::zeros();
        let (flags, clip) = self.clipped(s, dt);
        (flags, extra + clip)
    }

    /// Puts the gyro bias back where it was before the gyro was held (see [`BIAS_HOLD`]).
    pub(super) fn hold_bias(&mut self) {
        if let (Some(b), Some(f)) = (self.state.gyro.held_bias, self.state.filter.as_mut()) {
            let mut dx = Error::<T>::zeros();
            dx.fixed_rows_mut::<3>(BIAS)
                .copy_from(&(b - f.state().bias));
            f.retract(&dx);
        }
    }

    /// On the first gyro reading after a hold of [`REACQUIRE_AFTER`] or more: roll and
    /// pitch are loosened to [`REACQUIRE_SD`] (a hold of missing readings) or to their
    /// variance at a start ([`crate::spatial::ekf::Settings::initial_angle`], a hold of a
    /// clip) and made uncorrelated with the rest, so the encoders carry them back as after
    /// a start. Through the correlations the hold left, the pendulum's states had taken up
    /// part of the attitude's error (0.4-0.5 deg after 100 missing readings of one axis on
    /// scooter3d), which the filter then forgot at about 1.5 s: back within 0.05 deg after
    /// up to 10 s (with the bias it moved), 0.9-1.96 s with this (tests/gyro_bursts3d.rs).
    /// A missing reading hides the rate's departure from its low-pass, the vibration's
    /// scale; a clip hides the rate beyond the clip, without bound. Loosened to the start's
    /// 2 deg, the bursts took up to 2.08 s; to 0.5 deg after the clip of tests/faults3d
    /// (2 s at 0.1 rad/s), 6.06 s instead of 1.71. Loosening the pendulum's rates too
    /// moved the clip to 1.94 s; making them uncorrelated without loosening left some
    /// bursts beyond 3 s.
    fn reacquire(&mut self) {
        let Some(f) = self.state.filter.as_ref() else {
            return;
        };
        let x = *f.state();
        let mut p = *f.covariance();
        let sd = if self.state.gyro.clip_hold {
            self.settings.initial_angle
        } else {
            T::lit(REACQUIRE_SD)
        };
        loosen_roll_pitch(&mut p, sd);
        self.state.filter = Some(F::start(x, p));
    }

    /// The body's angular acceleration now: the gyro's smoothed derivative, zero while the
    /// gyro is missing (a held reading does not change).
    pub(super) fn angular_accel(&self, gyro_ok: bool) -> Vector3<T> {
        let diff = &self.state.gyro.diff;
        if !gyro_ok || !diff.is_started() {
            return Vector3::zeros();
        }
        // The filter's delay ahead by its second derivative (Settings::angular_accel_lead).
        Vector3::from_fn(|i, _| {
            let d = diff.signal(i);
            d.d1 + self.coeffs.accel_lead * d.d2
        })
    }

    /// The gyro axes at or beyond their full scale on sample `s` (a finite reading): the
    /// flag, and the attitude's variance about each over `dt`. The clipped reading is
    /// still the rate used (its sign is right, its size the closest bound to the truth),
    /// but the rate beyond the full scale is unknown: it grows from zero at the clip's
    /// entry at about the rate's slope then, `|w'| t`, so the attitude's error bound is
    /// `|w'| t^2 / 2` after a clip of `t`, and the encoders (the joint angles the body
    /// turns against) carry the attitude for as much. Measured on scooter3d (seed 3,
    /// every gyro cell clipped at 0.15 / 0.2 rad/s, RMS from the unclipped run): 1.49 /
    /// 0.97 deg trusting the clipped reading, 0.70 / 0.46 with this; a variance of
    /// `(fs t)^2` (the full scale as the unknown rate) gave 1.10 / 1.13 and took 8.5 s
    /// instead of 1.4 s to come back after a 0.3 s clip at 0.35 rad/s: the encoders' own
    /// innovations (the pendulum's unmodelled swing) then turn the attitude.
    fn clipped(&mut self, s: &SpatialSample<T>, dt: T) -> (Flags, Vector3<T>) {
        let Some(fs) = self.settings.gyro.checked_full_scale() else {
            return (Flags::empty(), Vector3::zeros());
        };
        let st = &mut self.state.gyro;
        let mut flags = Flags::empty();
        let mut extra = Vector3::zeros();
        for k in 0..3 {
            if s.gyro[k].abs() < fs {
                st.clipped_for[k] = T::zero();
                continue;
            }
            flags = Flags::SATURATED;
            let t0 = st.clipped_for[k];
            if t0 == T::zero() {
                st.clip_slope[k] = if st.diff.is_started() {
                    st.diff.signal(k).d1.abs()
                } else {
                    T::zero()
                };
            }
            let t1 = t0 + dt;
            st.clipped_for[k] = t1;
            let a = st.clip_slope[k] * T::lit(0.5);
            extra[k] = a * a * (t1 * t1 * t1 * t1 - t0 * t0 * t0 * t0);
        }
        (flags, extra)
    }

    /// The mean square of the rate a hold misses, per axis \[rad^2/s^2\]: the gyro's
    /// measured departure from its low-pass, or, before any, the setting
    /// ([`crate::ekf::Environment::angular_vibration_rms`]). Measured, because the
    /// encoders read a held rate's variance as the body turning: set too high (the
    /// default 0.178 rad/s against 0.04 on the scooter3d ride) one missing reading let one
    /// encoder innovation turn the attitude by 0.07 deg, which the filter then took 7 s to
    /// forget.
    fn hold_variance(&self) -> Vector3<T> {
        self.state.gyro.vibration.value().unwrap_or_else(|| {
            let v = self.settings.environment.angular_vibration_rms;
            Vector3::repeat(v * v)
        })
    }
}

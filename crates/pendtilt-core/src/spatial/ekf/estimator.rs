//! The streaming spatial estimator around a Gaussian filter of the engine: time steps,
//! start-up, missing readings, gaps, and the sensors with their innovation gates.
use super::measurement::{Accelerometer, Encoders, RestBias, Speed, UpDirection};
use super::process::{CardanProcess, Drive};
use super::settings::Settings;
use super::slip::{longitudinal_accel, SlipDetector};
use super::state::{Error, State, A, ACC, B, BIAS, N, P, R, ROT, V};
use crate::adaptation::{ForcingAdaptation, SETTLE_SECONDS};
use crate::engine::{substeps, Cov, Gate, GaussianFilter, Measurement, ProcessModel, Rejected};
use crate::filters::diff::{Response, SmoothingDifferentiator};
use crate::filters::one_pole::{OnePole, OnePoleGain};
use crate::spatial::attitude::roll_pitch_from_up;
use crate::spatial::imu::InclinationReference;
use crate::spatial::mounting::lever_arm;
use crate::spatial::travel::PathRate;
use crate::spatial::{Attitude, SpatialSample};
use crate::{Estimator, Flags, Real, StepClock};
use nalgebra::{SVector, UnitQuaternion, Vector2, Vector3, Vector4};

/// Bound on the variance of the heading error \[rad^2\]: rotations about the world's
/// vertical are observed by no sensor, so without a bound their variance grows for ever
/// (gyro noise and the z bias's walk: about 1e3 rad^2 after two hours), and next to the
/// encoders' 1e-8 rad^2 that leaves f32 with no precision (0.36 deg from f64 after two
/// hours). When it passes twice the bound it is scaled back to it (the correlations kept).
/// Small, because a large heading error makes both filters' linearisation (the rotation
/// errors compose, they do not add) cost roll and pitch: ukf3d's sigma points spread it by
/// sqrt(10). Measured (`spatial_scenarios`): at 0.1 rad^2 ukf3d was 1.12 deg RMS on the
/// noise-free still3d and ekf3d 0.31 deg on scooter3d at its defaults; at 1e-3, 0.018 and
/// 0.23; at 1e-5, 0.0027 (ekf3d's 0.0025) and 0.18; below that little changes.
const HEADING_VARIANCE: f64 = 1e-5;

/// Cutoff \[Hz\] of the one-pole low-pass of the gyro that bridges missing readings: the
/// last raw reading carries the angular vibration's instantaneous rate (15 deg/s for
/// 0.06 deg at 40 Hz), which a hold integrates; at 5 Hz the vibration is averaged out and
/// the lag (32 ms) costs a slowly tilting body little.
const HOLD_HZ: f64 = 5.0;

/// Time constant \[s\] of the mean square of the gyro's departure from its low-pass
/// (HOLD_HZ): the angular vibration a hold misses, measured on the log itself.
const VIBRATION_TAU: f64 = 1.0;

/// Standard deviation of O's speed \[m/s\] and its rate \[m/s^2\] while no `speed` column
/// reads them: both held at zero (O not accelerating), with a variance small enough to
/// move nothing and large enough to keep the covariance positive definite (the UKF's
/// Cholesky factor).
const HELD_TRAVEL_SD: f64 = 1e-6;

/// While the gyro is held (a missing reading, or a clipped axis read as missing) and for
/// this long \[s\] after, the gyro bias stays where it was: the encoders' innovations then
/// carry the rate the hold missed, which the filter would otherwise learn as bias through
/// the attitude-bias correlation. Measured on scooter3d (seed 3, the gyro clipped at 0.1
/// rad/s for 2 s, tests/faults3d.rs): learnt, the z bias moved by 0.005 rad/s and ekf3d
/// took 8.3 s to come back within 0.05 deg of the fault-free run. 2 s rather than 0.5 s:
/// after 100 missing readings of one gyro axis the attitude is still 0.1-0.2 deg off
/// 0.5 s later, which went into the bias and took up to 10 s to wear off
/// (tests/gyro_bursts3d.rs).
const BIAS_HOLD: f64 = 2.0;

/// A hold at least this long \[s\] ends with [`ModelBased::reacquire`]: 50 ms, so that
/// one missing reading (a hold of 1 ms, its error within the attitude's variance) does
/// not loosen the attitude (with every hold: 1.04 s instead of 0 back after one missing
/// gyro_x reading, tests/faults3d.rs).
const REACQUIRE_AFTER: f64 = 0.05;

/// The standard deviation \[rad\] roll and pitch are loosened to after a hold of missing
/// gyro readings ([`ModelBased::reacquire`]): 0.5 deg, about the error 100 missing readings
/// of one axis left on scooter3d (0.4-0.5 deg).
const REACQUIRE_SD: f64 = 0.5 * core::f64::consts::PI / 180.0;

/// Standard deviation \[rad/s\] of the pendulum's joint rates when the joint states start
/// again after the pendulum left its range: a pendulum that tumbled may still swing at a
/// few radians a second.
const JOINT_RATE_SD: f64 = 3.0;

/// Standard deviation \[rad\] of the guard's reference as a measurement of the up
/// direction while the pendulum is not used: 1 deg, about VQF's RMS on BROAD's hand-held
/// trials (docs/real-motion.md).
const REFERENCE_SD: f64 = core::f64::consts::PI / 180.0;

/// The forcing factor ([`super::settings::Adaptation`]) at which the guard's reference
/// carries roll and pitch beside the pendulum with [`REFERENCE_SD`]; below it, with that
/// times sqrt(this / factor), and not at all beyond ten times.
const REFERENCE_FORCING: f64 = 100.0;

/// Standard deviation \[rad/s\] of the gyro's bias read at rest: 0.01 deg/s.
const REST_BIAS_SD: f64 = 0.01 * core::f64::consts::PI / 180.0;

/// `x` wrapped to (-pi, pi].
fn wrap_pi<T: Real>(x: T) -> T {
    let tau = T::lit(core::f64::consts::TAU);
    let pi = T::lit(core::f64::consts::PI);
    let v = x - tau * ((x + pi) / tau).floor();
    if v <= -pi {
        v + tau
    } else {
        v
    }
}

/// The model-based spatial estimator (`ekf3d` over the EKF, `ukf3d` over the UKF).
///
/// Per sample: predict over `dt` with the gyro (split into steps of at most
/// [`Settings::max_step`]; a missing gyro reading is replaced by the low-passed gyro and
/// the attitude's process noise grows by the angular vibration it may miss), then update
/// with the encoders, the `speed` column (unless the wheel slips) and, if enabled, the
/// accelerometer, each through its innovation gate. Between `speed` readings (a slower
/// speed signal, or a short loss) O's speed and rate are carried by the filter; after
/// [`super::SpeedSettings::timeout`] without one, or before the first, both are held at
/// zero; the first reading after that starts them at the reading, with the rate unknown
/// ([`super::SpeedSettings::initial_rate`]).
/// The first sample with both encoder readings starts the filter with the pendulum
/// hanging still: roll = phi_x, pitch = phi_y, yaw 0. After a gap longer than
/// [`Settings::max_gap`], or if the filter becomes non-finite, it starts again the same
/// way, but a restart after a gap (or [`Estimator::resume`]) keeps the gyro bias, its
/// variance grown by the bias walk over the gap: a gap cannot change it more. A run of
/// [`Settings::reacquire_after`] rejected encoder readings re-acquires them: the
/// covariance grows along a tilt step of the innovation's size that leaves the pendulum
/// hanging where it is (roll with -a, pitch with -b), and the reading is applied ungated.
#[derive(Debug, Clone)]
pub struct ModelBased<T: Real, F> {
    settings: Settings<T>,
    model: CardanProcess<T>,
    encoders: Encoders<T>,
    q_step: T,
    // `q` is for a travelling vehicle (with the jerk's noise).
    q_travelling: bool,
    q: Cov<T, N>,
    // The part of `q` that the pendulum's forcing adds (scaled by `forcing`), per joint:
    // the angle's, the angle-rate and the rate's variance.
    q_forcing: [[T; 3]; 2],
    // The factor on the forcing's variance (Settings::adaptation), >= 1.
    forcing: ForcingAdaptation<T>,
    // Time since the last encoder reading that was used \[s\] (for the adaptation's step).
    since_used: T,
    // The pendulum is out of its range: the joint states start again at the next reading
    // in range.
    out_of_range: bool,
    // The gyro and accelerometer's inclination (Settings::guard_angle), and how long it
    // has run \[s\].
    reference: InclinationReference<T>,
    reference_age: T,
    // Time since the filter (re)started \[s\].
    since_start: T,
    // The gyro was held: the reference takes the filter's inclination on its return.
    reference_held: bool,
    speed_meas: Speed<T>,
    // The `speed` column has been read since the start: O's speed and rate are states.
    travelling: bool,
    // Consecutive speed readings the gate rejected.
    speed_rejected: u32,
    // Time since the last `speed` reading \[s\], once there was one, and that reading.
    since_speed: Option<T>,
    last_speed: T,
    filter: Option<F>,
    clock: StepClock<T>,
    since_phi: Option<T>,
    gyro: Option<Vector3<T>>,
    // The gyro low-passed (HOLD_HZ): what a hold bridges with.
    smooth: OnePole<T, 3>,
    // The mean square of the gyro's departure from `smooth`, per axis (VIBRATION_TAU).
    vibration: OnePole<T, 3>,
    // How long the gyro reading has been held \[s\].
    held_for: T,
    // How long each gyro axis has been at its full scale \[s\].
    clipped_for: Vector3<T>,
    // The gyro's smoothed rate of change on entering each axis' clip \[rad/s^2\].
    clip_slope: Vector3<T>,
    // The gyro's smoothed derivative: the body's angular acceleration.
    gyro_diff: SmoothingDifferentiator<T, 3>,
    // Its delay, by which its second derivative leads the first (Settings::angular_accel_lead;
    // 0 without the lead), once for the settings.
    accel_lead: T,
    // The path's turn and pitch rate from the gyro.
    path: PathRate<T>,
    // The accelerometer from O, `accel_at - speed_at` \[m\].
    accel_from_centre: Vector3<T>,
    // Wheel slip on the speed.
    slip: SlipDetector<T>,
    rejected: u32,
    last: Attitude<T>,
    // The gyro bias and its variances kept over a gap for the next start.
    kept_bias: Option<(Vector3<T>, Vector3<T>)>,
    // The gyro bias before a run of held (missing or clipped) gyro readings, kept until
    // BIAS_HOLD after the last, and how long since the last \[s\].
    held_bias: Option<Vector3<T>>,
    // Whether the current hold read a clip found in the log ([`ModelBased::update_clipped`]).
    clip_hold: bool,
    since_hold: T,
}

impl<T: Real, F: GaussianFilter<T, State<T>, N>> ModelBased<T, F> {
    /// A new estimator.
    pub fn new(settings: Settings<T>) -> Self {
        let gyro_diff = SmoothingDifferentiator::new(Response::Bessel, settings.angular_accel_hz);
        let accel_lead = if settings.angular_accel_lead {
            Response::Bessel.dc_delay(gyro_diff.cutoff_rad_s())
        } else {
            T::zero()
        };
        Self {
            model: settings.process_model(),
            encoders: Encoders {
                r: settings.encoder_variance().max(T::lit(1e-14)),
            },
            q_step: T::zero(),
            q_travelling: false,
            q: Cov::<T, N>::zeros(),
            q_forcing: [[T::zero(); 3]; 2],
            forcing: ForcingAdaptation::new(),
            since_used: T::zero(),
            out_of_range: false,
            reference: InclinationReference::new(settings.guard_tau),
            reference_age: T::zero(),
            since_start: T::zero(),
            reference_held: false,
            speed_meas: Speed {
                r: (settings.speed.noise * settings.speed.noise).max(T::lit(1e-12)),
            },
            travelling: false,
            speed_rejected: 0,
            since_speed: None,
            last_speed: T::zero(),
            settings,
            filter: None,
            clock: StepClock::new(),
            since_phi: None,
            gyro: None,
            smooth: OnePole::new(OnePoleGain::from_hz(T::lit(HOLD_HZ))),
            vibration: OnePole::new(OnePoleGain::from_time_constant(T::lit(VIBRATION_TAU))),
            held_for: T::zero(),
            clipped_for: Vector3::zeros(),
            clip_slope: Vector3::zeros(),
            gyro_diff,
            accel_lead,
            path: PathRate::new(&settings.path),
            accel_from_centre: settings.mounting.from_centre(settings.mounting.accel_at),
            slip: SlipDetector::new(settings.slip),
            rejected: 0,
            last: Attitude::unknown(),
            kept_bias: None,
            held_bias: None,
            clip_hold: false,
            since_hold: T::zero(),
        }
    }

    /// Puts the gyro bias back where it was before the gyro was held (see [`BIAS_HOLD`]).
    fn hold_bias(&mut self) {
        if let (Some(b), Some(f)) = (self.held_bias, self.filter.as_mut()) {
            let mut dx = Error::<T>::zeros();
            dx.fixed_rows_mut::<3>(BIAS)
                .copy_from(&(b - f.state().bias));
            f.retract(&dx);
        }
    }

    /// On the first gyro reading after a hold of [`REACQUIRE_AFTER`] or more: roll and
    /// pitch are loosened to [`REACQUIRE_SD`] (a hold of missing readings) or to their
    /// variance at a start ([`Settings::initial_angle`], a hold of a clip) and made
    /// uncorrelated with the rest, so the encoders carry them back as after a start.
    /// Through the correlations the hold left, the pendulum's states had taken up part of
    /// the attitude's error (0.4-0.5 deg after 100 missing readings of one axis on
    /// scooter3d), which the filter then forgot at about 1.5 s: back within 0.05 deg after
    /// up to 10 s (with the bias it moved), 0.9-1.96 s with this (tests/gyro_bursts3d.rs).
    /// A missing reading hides the rate's departure from its low-pass, the vibration's
    /// scale; a clip hides the rate beyond the clip, without bound. Loosened to the start's
    /// 2 deg, the bursts took up to 2.08 s; to 0.5 deg after the clip of tests/faults3d.rs
    /// (2 s at 0.1 rad/s), 6.06 s instead of 1.71. Loosening the pendulum's rates too
    /// moved the clip to 1.94 s; making them uncorrelated without loosening left some
    /// bursts beyond 3 s.
    fn reacquire(&mut self) {
        let Some(f) = self.filter.as_ref() else {
            return;
        };
        let x = *f.state();
        let mut p = *f.covariance();
        let sd = if self.clip_hold {
            self.settings.initial_angle
        } else {
            T::lit(REACQUIRE_SD)
        };
        loosen_roll_pitch(&mut p, sd);
        self.filter = Some(F::start(x, p));
    }

    /// [`Estimator::update`] with the gyro `axes` reading at a clip found in the log (the
    /// std crate's reader finds them): they are read as missing, and a hold that read a
    /// clip ends with roll and pitch loosened to their variance at a start, where one of
    /// missing readings loosens them to 0.5 deg: a clip hides the rate beyond it, without
    /// bound.
    pub fn update_clipped(&mut self, s: &SpatialSample<T>, axes: [bool; 3]) -> Attitude<T> {
        let mut s = *s;
        for (g, c) in s.gyro.iter_mut().zip(axes) {
            if c {
                *g = T::nan();
                self.clip_hold = true;
            }
        }
        self.update(&s)
    }

    /// Keeps the running filter's gyro bias for the next start, its variances grown by the
    /// bias walk over the time since the last encoder reading.
    fn keep_bias(&mut self) {
        let walk = self.settings.sensors.gyro_bias_walk;
        let grow = walk * walk * self.since_phi.unwrap_or(T::zero());
        if let Some(f) = self.filter.as_ref() {
            let p = f.covariance();
            let var = Vector3::from_fn(|k, _| p[(BIAS + k, BIAS + k)] + grow);
            self.kept_bias = Some((f.state().bias, var));
        }
    }

    /// Holds O's speed and rate at zero (no `speed` reading for longer than
    /// [`super::SpeedSettings::timeout`]): the state at zero, its
    /// variance at [`HELD_TRAVEL_SD`] and uncorrelated.
    fn hold_travel(&mut self) {
        let Some(f) = self.filter.as_mut() else {
            return;
        };
        let x = f.state().travel;
        let mut dx = Error::<T>::zeros();
        dx[V] = -x[0];
        dx[ACC] = -x[1];
        f.retract(&dx);
        let mut t = Cov::<T, N>::identity();
        t[(V, V)] = T::zero();
        t[(ACC, ACC)] = T::zero();
        f.transform(&t);
        for k in [V, ACC] {
            let mut v = Error::<T>::zeros();
            v[k] = T::lit(HELD_TRAVEL_SD);
            f.inflate(&v);
        }
        self.travelling = false;
    }

    /// The `speed` column's reading after the prediction: checked for wheel slip against
    /// the accelerometer ([`Flags::SLIP`]: not used while it slips), then a measurement of
    /// O's speed; the first after none starts O's speed there, its rate unknown. `gyro`
    /// and `wd` are the drive's rate and angular acceleration.
    fn sense_speed(
        &mut self,
        s: &SpatialSample<T>,
        dt: T,
        gyro: &Vector3<T>,
        wd: &Vector3<T>,
    ) -> Flags {
        let reading = s.speed.is_finite();
        if reading {
            self.since_speed = Some(T::zero());
            self.last_speed = s.speed;
        } else if !self
            .since_speed
            .is_some_and(|e| e <= self.settings.speed.timeout)
        {
            return Flags::empty();
        }
        let Some(f) = self.filter.as_mut() else {
            return Flags::empty();
        };
        let a = if s.accel.iter().all(|v| v.is_finite()) {
            longitudinal_accel(
                &Vector3::new(s.accel[0], s.accel[1], s.accel[2]),
                &f.state().up(),
                self.settings.params.gravity,
                &(gyro - f.state().bias),
                wd,
                &self.accel_from_centre,
            )
        } else {
            T::nan()
        };
        // The detector runs on every row, the last reading held between readings (a slower
        // speed signal): the accelerometer's vibration sampled on the speed's rows alone
        // would alias into its band (ride3d with the speed on one row in 20: 2,543 rows
        // falsely flagged).
        if self.slip.update(self.last_speed, a, dt).slip {
            return Flags::SLIP;
        }
        if !reading {
            return Flags::empty();
        }
        if !self.travelling {
            let sp = &self.settings.speed;
            let mut dx = Error::<T>::zeros();
            dx[V] = s.speed - f.state().travel[0];
            f.retract(&dx);
            let mut v = Error::<T>::zeros();
            v[V] = sp.noise;
            f.inflate(&v);
            let mut v = Error::<T>::zeros();
            v[ACC] = sp.initial_rate;
            f.inflate(&v);
            self.travelling = true;
            return Flags::empty();
        }
        let z = SVector::<T, 1>::new(s.speed);
        let gate = if self.speed_rejected >= self.settings.reacquire_after.max(1) {
            // Re-acquired as the encoders are: the speed's variance grows by the
            // innovation's square and the reading is applied ungated.
            let mut v = Error::<T>::zeros();
            v[V] = s.speed - f.state().travel[0];
            f.inflate(&v);
            Gate::off()
        } else {
            Gate {
                threshold: self.settings.innovation_gate,
                floor: T::zero(),
            }
        };
        match f.update(&self.speed_meas, &z, gate) {
            Ok(()) => {
                self.speed_rejected = 0;
                Flags::empty()
            }
            Err(e) => {
                if e == Rejected::Outlier {
                    self.speed_rejected = self.speed_rejected.saturating_add(1);
                }
                Flags::MEASUREMENT_SKIPPED
            }
        }
    }

    /// The body's angular acceleration now: the gyro's smoothed derivative, zero while the
    /// gyro is missing (a held reading does not change).
    fn angular_accel(&self, gyro_ok: bool) -> Vector3<T> {
        if !gyro_ok || !self.gyro_diff.is_started() {
            return Vector3::zeros();
        }
        // The filter's delay ahead by its second derivative (Settings::angular_accel_lead).
        Vector3::from_fn(|i, _| {
            let d = self.gyro_diff.signal(i);
            d.d1 + self.accel_lead * d.d2
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
        let mut flags = Flags::empty();
        let mut extra = Vector3::zeros();
        for k in 0..3 {
            if s.gyro[k].abs() < fs {
                self.clipped_for[k] = T::zero();
                continue;
            }
            flags = Flags::SATURATED;
            let t0 = self.clipped_for[k];
            if t0 == T::zero() {
                self.clip_slope[k] = if self.gyro_diff.is_started() {
                    self.gyro_diff.signal(k).d1.abs()
                } else {
                    T::zero()
                };
            }
            let t1 = t0 + dt;
            self.clipped_for[k] = t1;
            let a = self.clip_slope[k] * T::lit(0.5);
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
        self.vibration.value().unwrap_or_else(|| {
            let v = self.settings.environment.angular_vibration_rms;
            Vector3::repeat(v * v)
        })
    }

    /// The settings in use.
    pub fn settings(&self) -> &Settings<T> {
        &self.settings
    }

    /// The filter's state (attitude, gyro bias, joints), once started.
    pub fn state(&self) -> Option<&State<T>> {
        self.filter.as_ref().map(|f| f.state())
    }

    /// The wheel-slip detector (whether it slips, the speed it carries).
    pub fn slip_detector(&self) -> &SlipDetector<T> {
        &self.slip
    }

    /// The error covariance, once started.
    pub fn covariance(&self) -> Option<&Cov<T, N>> {
        self.filter.as_ref().map(|f| f.covariance())
    }

    /// The attitude quaternion (world <- body; yaw is unobserved and only integrated),
    /// once started.
    pub fn quaternion(&self) -> Option<UnitQuaternion<T>> {
        self.state().map(|x| x.q)
    }

    /// The factor on the pendulum's forcing variance the adaptation has reached (1: the
    /// floor, [`crate::ekf::Environment::vibration_density`]).
    pub fn forcing_factor(&self) -> T {
        self.forcing.factor()
    }

    fn hold(&self, flags: Flags) -> Attitude<T> {
        Attitude { flags, ..self.last }
    }

    /// Starts with the pendulum hanging still at the sample's encoder angles (imu3d: at
    /// the accelerometer's roll and pitch).
    fn start(&mut self, s: &SpatialSample<T>) -> Attitude<T> {
        let st = &self.settings;
        let phi = if st.use_encoders {
            s.phi
        } else {
            let f = s.accel;
            let (roll, pitch) = roll_pitch_from_up(f);
            [roll, pitch]
        };
        // The guard's reference once it has settled (a restart in motion: the pendulum
        // need not hang still), else the pendulum hanging still.
        let (roll, pitch) = if self.reference_settled() {
            let u = self.reference.up();
            roll_pitch_from_up([u[0], u[1], u[2]])
        } else {
            (phi[0], phi[1])
        };
        let w = self.gyro.unwrap_or_else(Vector3::zeros);
        let (a, b) = (-phi[0], -phi[1]);
        let (sa, ca) = a.sin_cos();
        let (sb, cb) = b.sin_cos();
        // Hanging still: the pendulum's rates about its own x and y axes are zero.
        let u3 = -sa * w[1] + ca * w[2];
        let kept = self.kept_bias.take();
        let x = State {
            q: UnitQuaternion::from_euler_angles(roll, pitch, T::zero()),
            bias: kept.map_or_else(Vector3::zeros, |k| k.0),
            joints: Vector4::new(a, b, sb * u3 / cb, T::zero()),
            travel: Vector2::zeros(),
        };
        let mut p = Cov::<T, N>::zeros();
        let ang = st.initial_angle * st.initial_angle;
        p[(ROT, ROT)] = ang;
        p[(ROT + 1, ROT + 1)] = ang;
        // The heading is unknown, but only its bounded variance is useful (see
        // HEADING_VARIANCE).
        p[(ROT + 2, ROT + 2)] = T::lit(HEADING_VARIANCE);
        let b0 = st.sensors.gyro_bias;
        for k in 0..3 {
            p[(BIAS + k, BIAS + k)] = kept.map_or(b0 * b0 + T::lit(1e-12), |kept| kept.1[k]);
        }
        p[(A, A)] = self.encoders.r;
        p[(B, B)] = self.encoders.r;
        p[(P, P)] = ang;
        p[(R, R)] = ang;
        let held = T::lit(HELD_TRAVEL_SD * HELD_TRAVEL_SD);
        p[(V, V)] = held;
        p[(ACC, ACC)] = held;
        self.travelling = false;
        self.speed_rejected = 0;
        self.since_speed = None;
        self.filter = Some(F::start(x, p));
        self.rejected = 0;
        self.since_start = T::zero();
        self.clock.accept();
        self.last = Attitude {
            roll,
            pitch,
            flags: Flags::INITIALISING,
        };
        self.last
    }

    /// Predicts over `dt` with gyro reading `gyro`, adding `extra[k]` to the variance of
    /// the rotation about body axis `k` over the interval (a held or a clipped gyro);
    /// `false` if the filter could not propagate.
    fn predict(&mut self, dt: T, drive: &Drive<T>, extra: &Vector3<T>) -> bool {
        let (n, h) = substeps(dt, self.settings.max_step);
        if h != self.q_step || self.q_travelling != self.travelling {
            self.q = self.model.q(h);
            let h2 = h * h;
            self.q_forcing = self.model.noise.joints.map(|d| {
                let v = d * d;
                [v * h2 * h / T::lit(3.0), v * h2 / T::lit(2.0), v * h]
            });
            if !self.travelling {
                // O's speed and rate held at zero: no jerk.
                for k in [V, ACC] {
                    for i in 0..N {
                        self.q[(k, i)] = T::zero();
                        self.q[(i, k)] = T::zero();
                    }
                }
            }
            self.q_step = h;
            self.q_travelling = self.travelling;
        }
        let with_extra;
        // Nothing to add (the usual case: a gyro reading within its range and the forcing
        // at its floor) leaves the cached noise as it is, uncopied.
        let forcing = self.forcing.factor();
        let q = if extra.iter().all(|e| *e == T::zero()) && forcing == T::one() {
            &self.q
        } else {
            let mut q = self.q;
            let more = forcing - T::one();
            for ((angle, rate), f) in [(A, P), (B, R)].into_iter().zip(self.q_forcing) {
                q[(angle, angle)] += f[0] * more;
                q[(angle, rate)] += f[1] * more;
                q[(rate, angle)] += f[1] * more;
                q[(rate, rate)] += f[2] * more;
            }
            with_extra = add_rate_noise(q, &(extra / T::lit(n as f64)));
            &with_extra
        };
        let Some(filter) = self.filter.as_mut() else {
            return false;
        };
        let mut ok = true;
        for _ in 0..n {
            ok &= filter.predict(&self.model, drive, h, q);
        }
        ok
    }

    /// The encoders through their gate. A reading is taken to the turn nearest the joint
    /// angle the filter predicts (a pendulum that spun past +-180 deg). Beyond
    /// [`Settings::pendulum_range`], or after [`Settings::reacquire_after`] rejections in a
    /// row, the pendulum is out of its model: the reading is not used, and the next one in
    /// range starts the joint states again at the reading, their rates unknown, the
    /// attitude left as it was ([`Flags::PENDULUM_UNUSED`]). The innovations that pass
    /// drive the forcing's adaptation ([`super::settings::Adaptation`]).
    fn sense_encoders(&mut self, z: &SVector<T, 2>, dt: T) -> Flags {
        let st = self.settings;
        let Some(filter) = self.filter.as_mut() else {
            return Flags::empty();
        };
        self.since_used += dt;
        let pred = self.encoders.predict(filter.state());
        let z = SVector::<T, 2>::from_fn(|i, _| pred[i] + wrap_pi(z[i] - pred[i]));
        if z[1].abs() > st.pendulum_range {
            self.out_of_range = true;
            return Flags::PENDULUM_UNUSED | Flags::MEASUREMENT_SKIPPED;
        }
        if self.out_of_range || self.rejected >= st.reacquire_after.max(1) {
            self.restart_joints(&z);
            self.out_of_range = false;
            self.rejected = 0;
            self.since_used = T::zero();
            return Flags::PENDULUM_UNUSED;
        }
        let p = filter.covariance();
        let nis = (0..2).fold(T::zero(), |acc, i| {
            let (k, y) = ([A, B][i], z[i] - pred[i]);
            acc + y * y / (p[(k, k)] + self.encoders.r)
        }) * T::lit(0.5);
        let gate = Gate {
            threshold: st.innovation_gate,
            floor: T::zero(),
        };
        let flags = match filter.update(&self.encoders, &z, gate) {
            Ok(()) => {
                self.rejected = 0;
                Flags::empty()
            }
            Err(Rejected::Outlier) => {
                self.rejected = self.rejected.saturating_add(1);
                Flags::MEASUREMENT_SKIPPED
            }
            Err(_) => Flags::MEASUREMENT_SKIPPED,
        };
        // A reading the gate rejects counts as the gate's size at most: one wrong reading
        // (a glitch) moves the mean by little, a run of them (a model that no longer
        // fits) as much as it should.
        self.adapt(nis.min(st.innovation_gate));
        flags
    }

    /// One step of the forcing's adaptation ([`ForcingAdaptation::step`]) on the
    /// encoders' normalised innovation squared `nis` (per axis, before the update).
    fn adapt(&mut self, nis: T) {
        let dt = core::mem::replace(&mut self.since_used, T::zero());
        // Not while the gyro is held or its bias kept after a hold, nor while the filter
        // settles after a start: those innovations are the filter's, not the motion's.
        let settling = self.since_start < T::lit(SETTLE_SECONDS) || self.held_bias.is_some();
        if !settling {
            self.forcing.step(&self.settings.adaptation, nis, dt);
        }
    }

    /// Starts the joint states again at the reading `z` (a, b), their rates unknown and
    /// uncorrelated with the rest; the attitude, the bias and O's travel keep their
    /// estimates and covariance.
    fn restart_joints(&mut self, z: &SVector<T, 2>) {
        let Some(f) = self.filter.as_ref() else {
            return;
        };
        let mut x = *f.state();
        let mut p = *f.covariance();
        x.joints = Vector4::new(z[0], z[1], T::zero(), T::zero());
        uncorrelate(&mut p, |i| (A..=R).contains(&i));
        let rate = T::lit(JOINT_RATE_SD);
        p[(A, A)] = self.encoders.r;
        p[(B, B)] = self.encoders.r;
        p[(P, P)] = rate * rate;
        p[(R, R)] = rate * rate;
        self.filter = Some(F::start(x, p));
    }

    /// The guard: the inclination reference takes the sample (the accelerometer less the
    /// acceleration the filter knows of: O's travel and the lever arm from O), and when the
    /// filter's up direction has left the reference's by more than
    /// [`Settings::guard_angle`], the attitude is turned onto it (the smallest turn: the
    /// heading kept), its roll and pitch loosened to the guard's angle and uncorrelated,
    /// and the joint states start again at the encoders' reading.
    fn guard(
        &mut self,
        s: &SpatialSample<T>,
        dt: T,
        drive: &Drive<T>,
        have_phi: bool,
        accel_ok: bool,
    ) -> Flags {
        let st = self.settings;
        let Some(f) = self.filter.as_ref() else {
            return Flags::empty();
        };
        let x = *f.state();
        let w = drive.gyro - x.bias;
        let acc = Accelerometer {
            gravity: st.params.gravity,
            per_speed: drive.centre_accel_per_speed(&w),
            lever: lever_arm(&w, &drive.angular_accel, &self.accel_from_centre),
            r: T::one(),
        };
        // O's travel only while a `speed` column reads it: a filter that lost its way would
        // otherwise lead the reference astray with it.
        let known = if self.travelling {
            acc.predict(&x) - x.up() * st.params.gravity
        } else {
            acc.lever
        };
        let z = Vector3::new(s.accel[0], s.accel[1], s.accel[2]) - known;
        // A missing reading: the gyro carries the reference over it.
        let z = accel_ok.then_some(z);
        // While the gyro is held the reference cannot follow the body: it waits, then takes
        // the filter's inclination (the encoders carried it) and guards again from there.
        // Without the encoders nothing carried the filter better than the reference: it
        // runs on the held rate as the filter does (taking the filter's inclination after
        // one missing gyro reading left imu3d 0.07 deg worse for 20 s, tests/faults3d.rs).
        if self.held_for > T::zero() && st.use_encoders {
            self.reference_held = true;
            return Flags::empty();
        }
        if core::mem::replace(&mut self.reference_held, false) {
            self.reference.align_up(&x.up());
        }
        // The gyro as read: the filter's bias estimate is what the guard guards against.
        self.reference.update(&drive.gyro, z.as_ref(), dt);
        if self.held_bias.is_some() {
            return Flags::empty();
        }
        self.reference_age += dt;
        // The reference needs a few time constants to settle on its start.
        if !(self.reference_settled() && have_phi) {
            return Flags::empty();
        }
        let (u, r) = (x.up(), self.reference.up());
        if u.angle(&r) <= st.guard_angle {
            return Flags::empty();
        }
        let Some(turn) = UnitQuaternion::rotation_between(&r, &u) else {
            return Flags::empty();
        };
        let mut dx = Error::<T>::zeros();
        dx.fixed_rows_mut::<3>(ROT).copy_from(&turn.scaled_axis());
        let Some(f) = self.filter.as_mut() else {
            return Flags::empty();
        };
        f.retract(&dx);
        let x = *f.state();
        let mut p = *f.covariance();
        loosen_roll_pitch(&mut p, st.guard_angle);
        self.filter = Some(F::start(x, p));
        if st.use_encoders {
            let z = SVector::<T, 2>::new(-s.phi[0], -s.phi[1]);
            let pred = self.encoders.predict(&x);
            let z = SVector::<T, 2>::from_fn(|i, _| pred[i] + wrap_pi(z[i] - pred[i]));
            self.restart_joints(&z);
        }
        self.rejected = 0;
        Flags::RESET
    }

    /// Whether the guard's reference has run long enough to be trusted (two of its time
    /// constants).
    fn reference_settled(&self) -> bool {
        self.settings.guard_angle.is_finite()
            && self.reference.is_started()
            && self.reference_age > self.settings.guard_tau * T::lit(2.0)
    }

    /// While the pendulum is not used, the guard's reference carries roll and pitch: its up
    /// direction as a measurement of the attitude, standard deviation
    /// [`REFERENCE_SD`] (what it keeps to on BROAD's hand-held motion), as VQF would.
    fn sense_reference(&mut self, unused: bool, dt: T) {
        if !(self.reference_settled() && dt > T::zero()) {
            return;
        }
        let Some(filter) = self.filter.as_mut() else {
            return;
        };
        let sd = if unused {
            T::lit(REFERENCE_SD)
        } else {
            T::lit(REFERENCE_SD)
                * (T::lit(REFERENCE_FORCING) / self.forcing.factor())
                    .sqrt()
                    .max(T::one())
        };
        if sd > T::lit(10.0 * REFERENCE_SD) {
            return;
        }
        // Beside the pendulum, the reference's error is correlated over its time constant:
        // each sample carries dt / tau of an independent reading's information. Without the
        // pendulum, it carries roll and pitch alone, as in an IMU filter.
        let r = if unused {
            sd * sd
        } else {
            sd * sd * self.settings.guard_tau / dt
        };
        let up = UpDirection { r };
        let _ = filter.update(&up, &self.reference.up(), Gate::off());
    }

    /// While the guard's rest detection says the body rests, the gyro's low-pass is its
    /// bias on every axis, the vertical one too (which the pendulum cannot see at rest, and
    /// which hand-held motion would otherwise drive to several deg/s as the model's
    /// mismatch): a measurement of the bias, standard deviation [`REST_BIAS_SD`], its
    /// error correlated over the rest filter's time constant.
    fn sense_rest(&mut self, dt: T) {
        let on = self.settings.guard_angle.is_finite();
        if !(on && self.reference.is_resting() && dt > T::zero()) {
            return;
        }
        let Some(filter) = self.filter.as_mut() else {
            return;
        };
        let sd = T::lit(REST_BIAS_SD);
        let m = RestBias {
            r: sd * sd * T::lit(crate::spatial::imu::REST_TAU) / dt,
        };
        let _ = filter.update(&m, &self.reference.bias(), Gate::off());
    }

    /// The accelerometer as a measurement of the up direction (and of O's acceleration
    /// while travelling), through its gate. Its variance is the sensor's white noise over
    /// the sample and the vibration's; for imu3d, where it replaces the encoders, also the
    /// body's unmodelled acceleration: the forcing's density over the sample, times the
    /// adapted factor, whose adaptation its innovations drive as the encoders' do in
    /// ekf3d. A missing reading (not `accel_ok`) is skipped.
    fn sense_accel(
        &mut self,
        s: &SpatialSample<T>,
        dt: T,
        drive: &Drive<T>,
        accel_ok: bool,
    ) -> Flags {
        let st = self.settings;
        let Some(filter) = self.filter.as_mut() else {
            return Flags::empty();
        };
        if !accel_ok {
            return Flags::MEASUREMENT_SKIPPED;
        }
        let d = st.sensors.accel_density;
        let vib = st.environment.vibration_rms;
        let h = dt.max(T::lit(1e-6));
        let motion = if st.use_encoders {
            T::zero()
        } else {
            let q = st.environment.vibration_density;
            q * q * self.forcing.factor() / h
        };
        // The lever arm from O at the filter's bias-corrected rate.
        let w = drive.gyro - filter.state().bias;
        let acc = Accelerometer {
            gravity: st.params.gravity,
            per_speed: drive.centre_accel_per_speed(&w),
            lever: lever_arm(&w, &drive.angular_accel, &self.accel_from_centre),
            r: d * d / h + vib * vib + motion,
        };
        let z = Vector3::new(s.accel[0], s.accel[1], s.accel[2]);
        let nis = if st.use_encoders {
            T::zero()
        } else {
            // Per axis, before the update, as the encoders' in ekf3d.
            let x = filter.state();
            let (y, hm) = (z - acc.predict(x), acc.jacobian(x));
            let sv = hm * filter.covariance() * hm.transpose();
            (0..3).fold(T::zero(), |m, i| m + y[i] * y[i] / (sv[(i, i)] + acc.r)) / T::lit(3.0)
        };
        let gate = Gate {
            threshold: st.innovation_gate,
            floor: T::zero(),
        };
        let flags = match filter.update(&acc, &z, gate) {
            Ok(()) => Flags::empty(),
            Err(_) => Flags::MEASUREMENT_SKIPPED,
        };
        if !st.use_encoders {
            self.since_used += dt;
            self.adapt(nis.min(st.innovation_gate));
        }
        flags
    }
}

/// Zeroes the covariances between the states `apart` picks and all others.
fn uncorrelate<T: Real>(p: &mut Cov<T, N>, apart: impl Fn(usize) -> bool) {
    for i in 0..N {
        for j in 0..N {
            if i != j && (apart(i) || apart(j)) {
                p[(i, j)] = T::zero();
            }
        }
    }
}

/// Roll and pitch made uncorrelated with the rest and their standard deviation raised to
/// at least `sd` \[rad\] (a re-acquisition, a reset onto the guard's reference).
fn loosen_roll_pitch<T: Real>(p: &mut Cov<T, N>, sd: T) {
    uncorrelate(p, |i| i == ROT || i == ROT + 1);
    for i in [ROT, ROT + 1] {
        p[(i, i)] = p[(i, i)].max(sd * sd);
    }
}

/// `q` with `share[k]` more variance of the rotation about body axis `k` over the step (a
/// held or clipped gyro's rate error): it turns the attitude one way and the joint angles
/// the other (as the gyro's own noise does, see `CardanProcess::q`).
fn add_rate_noise<T: Real>(mut q: Cov<T, N>, share: &Vector3<T>) -> Cov<T, N> {
    for k in 0..3 {
        q[(ROT + k, ROT + k)] += share[k];
    }
    for (k, joint) in [(0, A), (1, B)] {
        q[(joint, joint)] += share[k];
        q[(ROT + k, joint)] -= share[k];
        q[(joint, ROT + k)] -= share[k];
    }
    q
}

/// Scales the covariance along the unobserved heading back to [`HEADING_VARIANCE`] once it
/// passes twice that. The rotation error is in body axes, so a turn about the world's
/// vertical is one about `u`, the up direction in body axes.
fn bound_heading<T: Real, F: GaussianFilter<T, State<T>, N>>(f: &mut F) {
    let u = f.state().up();
    let p = f.covariance().fixed_view::<3, 3>(ROT, ROT).into_owned();
    let var = u.dot(&(p * u));
    let cap = T::lit(HEADING_VARIANCE);
    if var > cap + cap && var.is_finite() {
        let k = T::one() - (cap / var).sqrt();
        let mut t = Cov::<T, N>::identity();
        let shrink = nalgebra::Matrix3::<T>::identity() - u * u.transpose() * k;
        t.fixed_view_mut::<3, 3>(ROT, ROT).copy_from(&shrink);
        f.transform(&t);
    }
}

impl<T: Real, F: GaussianFilter<T, State<T>, N>> Estimator for ModelBased<T, F> {
    type Input = SpatialSample<T>;
    type Output = Attitude<T>;

    fn update(&mut self, s: &SpatialSample<T>) -> Attitude<T> {
        let Ok(step) = self.clock.offer(s.dt) else {
            return self.hold(Flags::BAD_TIME_STEP);
        };
        let dt = step.unwrap_or(T::zero());
        // The gravity reference the filter starts on and whose gaps restart it: the
        // encoders, or for imu3d the accelerometer.
        let have_phi = if self.settings.use_encoders {
            s.phi.iter().all(|v| v.is_finite())
        } else {
            s.accel.iter().all(|v| v.is_finite())
        };
        let gyro_ok = s.gyro.iter().all(|v| v.is_finite());
        if gyro_ok {
            let g = Vector3::new(s.gyro[0], s.gyro[1], s.gyro[2]);
            self.gyro = Some(g);
            let m = self.smooth.update(&g, dt);
            if dt > T::zero() {
                self.vibration.update(&(g - m).component_mul(&(g - m)), dt);
            }
            self.path.update(&g, dt);
            if dt > T::zero() && self.gyro_diff.is_started() {
                self.gyro_diff.update_all(s.gyro, dt);
            } else {
                self.gyro_diff.start_all(s.gyro);
            }
        }
        // A gap in the rows or in the encoder readings longer than max_gap is not bridged.
        if let Some(e) = self.since_phi.as_mut() {
            *e += s.dt;
        }
        let max_gap = self.settings.max_gap;
        // imu3d: the gyro carries the attitude over missing accelerometer readings, as in
        // any IMU filter; only a gap of both sensors is not bridged (restarting after 0.1 s
        // without the accelerometer took a moving scooter's acceleration for tilt: 43 deg).
        let coasted = have_phi
            && self.since_phi.is_some_and(|e| e > max_gap)
            && (self.settings.use_encoders || self.held_for > max_gap);
        if self.filter.is_some() && (dt > max_gap || coasted) {
            self.keep_bias();
            self.filter = None;
            // Its attitude is as stale as the filter's: both start again.
            self.reference.reset();
            self.reference_age = T::zero();
        }
        if have_phi {
            self.since_phi = Some(T::zero());
        }
        if self.filter.is_none() {
            return if have_phi {
                self.start(s)
            } else {
                self.hold(Flags::INITIALISING | Flags::SAMPLE_MISSING)
            };
        }
        let mut flags = Flags::empty();
        // A missing axis takes its low-passed rate, the axes read stay as read (bridging
        // all three for one missing axis moved the attitude 0.39 deg over 100 missing
        // gyro_x readings on scooter3d, and the filter 8.6 s to come back).
        let gyro = if gyro_ok {
            self.gyro.unwrap_or_else(Vector3::zeros)
        } else {
            let m = self.smooth.value().unwrap_or_else(Vector3::zeros);
            Vector3::from_fn(|i, _| {
                if s.gyro[i].is_finite() {
                    s.gyro[i]
                } else {
                    m[i]
                }
            })
        };
        // A held gyro reading misses the rate's change, the angular vibration's above all:
        // the attitude's variance grows as (v t)^2 over a hold of t.
        if gyro_ok {
            self.since_hold += dt;
            if self.since_hold > T::lit(BIAS_HOLD) {
                self.held_bias = None;
            }
        } else if self.held_bias.is_none() {
            self.held_bias = self.filter.as_ref().map(|f| f.state().bias);
            self.since_hold = T::zero();
        } else {
            self.since_hold = T::zero();
        }
        let mut extra = if gyro_ok {
            if self.held_for >= T::lit(REACQUIRE_AFTER) {
                self.reacquire();
            } else if !self.settings.use_encoders {
                // imu3d: a hold too short to re-acquire after is too short to move the
                // bias; holding it for BIAS_HOLD then pulled the attitude against the
                // correlations (one missing gyro reading: 0.07 deg worse for 20 s).
                self.held_bias = None;
            }
            self.held_for = T::zero();
            self.clip_hold = false;
            Vector3::zeros()
        } else {
            flags |= Flags::SAMPLE_MISSING;
            let t0 = self.held_for;
            self.held_for += dt;
            // On every axis, the ones read too: a rate missed about one axis turns the
            // others through the motion (the 2 s gyro clip of tests/faults3d.rs: 6.06 s
            // back with the missing axes' alone, 1.74 s with all three).
            self.hold_variance() * (self.held_for * self.held_for - t0 * t0)
        };
        if gyro_ok {
            let (f, clip) = self.clipped(s, dt);
            flags |= f;
            extra += clip;
        }
        let angular_accel = self.angular_accel(gyro_ok);
        if let Some(e) = self.since_speed.as_mut() {
            *e += dt;
            if *e > self.settings.speed.timeout && self.travelling {
                self.hold_travel();
                self.slip.reset();
            }
        }
        let drive = Drive {
            gyro,
            angular_accel,
            path_gyro: self.path.rate().unwrap_or(gyro),
            slow_gyro: self.smooth.value().unwrap_or(gyro),
            z_bias: self
                .filter
                .as_ref()
                .map_or(T::zero(), |f| f.state().bias[2]),
        };
        self.since_start += dt;
        let accel_ok = s.accel.iter().all(|v| v.is_finite());
        let ok = self.predict(dt, &drive, &extra);
        if let Some(f) = self.filter.as_mut() {
            bound_heading(f);
        }
        self.clock.accept();
        if !have_phi {
            flags |= Flags::SAMPLE_MISSING;
        } else if self.settings.use_encoders {
            // The joint angles the encoders read (MODEL.md 7.2).
            let z = SVector::<T, 2>::new(-s.phi[0], -s.phi[1]);
            let used = self.sense_encoders(&z, dt);
            flags |= used;
            self.sense_reference(used.contains(Flags::PENDULUM_UNUSED), dt);
            self.hold_bias();
        } else {
            flags |= self.sense_accel(s, dt, &drive, accel_ok);
            self.sense_reference(false, dt);
            self.hold_bias();
        }
        flags |= self.sense_speed(s, dt, &gyro, &angular_accel);
        if self.settings.use_accel && self.settings.use_encoders {
            flags |= self.sense_accel(s, dt, &drive, accel_ok);
        }
        flags |= self.guard(s, dt, &drive, have_phi, accel_ok);
        self.sense_rest(dt);
        let finite = self.filter.as_ref().is_some_and(|f| {
            let p = f.covariance();
            crate::engine::ErrorState::is_finite(f.state())
                && (0..N).fold(T::zero(), |acc, i| acc + p[(i, i)]).is_finite()
        });
        if !ok || !finite {
            self.filter = None;
            return self.hold(flags | Flags::INITIALISING);
        }
        let x = self.filter.as_ref().map(|f| *f.state());
        if let Some(x) = x {
            let u = x.up();
            let (roll, pitch) = roll_pitch_from_up([u[0], u[1], u[2]]);
            self.last = Attitude { roll, pitch, flags };
        }
        self.last
    }

    fn reset(&mut self) {
        self.filter = None;
        self.clock.restart();
        self.since_phi = None;
        self.gyro = None;
        self.smooth.reset();
        self.vibration.reset();
        self.held_for = T::zero();
        self.clipped_for = Vector3::zeros();
        self.clip_slope = Vector3::zeros();
        self.gyro_diff.reset();
        self.path.reset();
        self.travelling = false;
        self.speed_rejected = 0;
        self.since_speed = None;
        self.slip.reset();
        self.rejected = 0;
        self.last = Attitude::unknown();
        self.kept_bias = None;
        self.held_bias = None;
        self.since_hold = T::zero();
        self.clip_hold = false;
        self.forcing.reset();
        self.since_used = T::zero();
        self.out_of_range = false;
        self.reference.reset();
        self.reference_age = T::zero();
    }

    /// Forgets everything but the gyro bias (see the type's documentation).
    fn resume(&mut self) {
        self.keep_bias();
        let kept = self.kept_bias;
        self.reset();
        self.kept_bias = kept;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spatial::ekf::Ekf;

    fn still(k: usize, gyro: [f64; 3]) -> SpatialSample<f64> {
        SpatialSample {
            dt: if k == 0 { 0.0 } else { 1e-3 },
            phi: [0.0, 0.0],
            gyro,
            accel: [f64::NAN; 3],
            speed: f64::NAN,
        }
    }

    /// imu3d ([`Settings::imu_only`]) needs no encoders: on a body resting tilted, with no
    /// encoder reading at all, it starts on the accelerometer and holds its tilt; ekf3d on
    /// the same samples never starts. A body accelerating along x at 2 m/s^2 for a second
    /// (12 deg of an accelerometer's tilt) moves it by far less: the adaptation and the
    /// guard's reference keep to the gyro.
    #[test]
    fn imu3d_runs_on_the_accelerometer_alone() {
        let (roll, pitch) = (0.2f64, -0.1f64);
        let up = crate::spatial::attitude::up_from_roll_pitch(roll, pitch);
        let sample = |k: usize, push: f64| {
            let f = [9.81 * up[0] + push, 9.81 * up[1], 9.81 * up[2]];
            SpatialSample {
                dt: if k == 0 { 0.0 } else { 1e-3 },
                phi: [f64::NAN; 2],
                gyro: [0.0; 3],
                accel: f,
                speed: f64::NAN,
            }
        };
        let mut imu = Ekf::<f64>::new(Settings::default().imu_only());
        let mut ekf = Ekf::<f64>::new(Settings::default());
        let mut worst = 0.0f64;
        for k in 0..20_000 {
            let push = if (10_000..11_000).contains(&k) {
                2.0
            } else {
                0.0
            };
            let a = imu.update(&sample(k, push));
            let e = ekf.update(&sample(k, push));
            assert!(e.flags.contains(Flags::INITIALISING), "{k}");
            if k > 3000 {
                let err = crate::spatial::attitude::inclination_between(
                    crate::spatial::attitude::up_from_roll_pitch(a.roll, a.pitch),
                    up,
                );
                worst = worst.max(err.to_degrees());
            }
            if k == 9_999 {
                assert!((a.roll - roll).abs() < 1e-3 && (a.pitch - pitch).abs() < 1e-3);
            }
        }
        assert!(worst < 3.0, "{worst} deg");
    }

    /// A gyro axis at its full scale is flagged saturated and loosens the attitude about
    /// that axis against its joint angle (by the slope the rate had on entering the clip),
    /// so the encoders carry it; below the full scale, or without one, nothing changes.
    #[test]
    fn a_reading_at_full_scale_is_flagged_and_loosens_the_attitude_about_its_axis() {
        let mut st = Settings::default();
        st.gyro.full_scale = Some(0.5);
        let mut e = Ekf::<f64>::new(st);
        let mut plain = Ekf::<f64>::new(Settings::default());
        // The x rate ramps up at 10 rad/s^2 and sticks at the full scale for 20 ms.
        let rate = |k: usize| (k.saturating_sub(100) as f64 * 1e-2).min(0.5);
        let mut flagged = 0;
        for k in 0..170 {
            let s = still(k, [rate(k), 0.0, 0.0]);
            let a = e.update(&s);
            plain.update(&s);
            assert_eq!(a.flags.contains(Flags::SATURATED), rate(k) >= 0.5, "{k}");
            flagged += usize::from(a.flags.contains(Flags::SATURATED));
        }
        assert_eq!(flagged, 20);
        let (p, q) = (e.covariance().unwrap(), plain.covariance().unwrap());
        // The prediction's variance about x before the last update is at least
        // (10 rad/s^2 (20 ms)^2 / 2)^2 = 4e-6 rad^2 more (the smoothed slope is a little
        // under the ramp's); the encoders then leave the extra mostly on the
        // joint-and-attitude direction they do not see.
        let dx = p[(ROT, ROT)] - q[(ROT, ROT)];
        let dy = p[(ROT + 1, ROT + 1)] - q[(ROT + 1, ROT + 1)];
        assert!(dx > 1e-7 && dx > 100.0 * dy.abs(), "{dx} {dy}");
        let mut none = Ekf::<f64>::new(Settings::default());
        let a = none.update(&still(0, [9.0; 3]));
        assert!(!a.flags.contains(Flags::SATURATED));
    }

    /// While the gyro is held (missing) and for BIAS_HOLD after, the encoders move the
    /// attitude but not the gyro bias: a body rolling at 0.2 rad/s for 0.3 s with its gyro
    /// missing leaves the bias where it was (to rounding); BIAS_HOLD later it is learnt
    /// again.
    #[test]
    fn a_held_gyro_leaves_the_bias_where_it_was() {
        let mut e = Ekf::<f64>::new(Settings::default());
        let bias_walk = |e: &Ekf<f64>| e.state().unwrap().bias;
        // Still and level, a reading of 0.01 rad/s on x: the bias starts being learnt.
        for k in 0..2000 {
            e.update(&still(k, [0.01, 0.0, 0.0]));
        }
        let before = bias_walk(&e);
        assert!(before[0] > 1e-4, "{before}");
        // The body rolls at 0.2 rad/s (the pendulum hanging: phi_x follows the roll) with
        // the gyro missing, then still again with the gyro back.
        let mut roll = 0.0;
        for k in 2000..2300 {
            roll += 0.2e-3;
            let mut s = still(k, [f64::NAN; 3]);
            s.phi = [roll, 0.0];
            let a = e.update(&s);
            assert!(a.flags.contains(Flags::SAMPLE_MISSING));
            assert!((bias_walk(&e) - before).norm() < 1e-15, "{k}");
        }
        let mut s = still(2300, [0.01, 0.0, 0.0]);
        s.phi = [roll, 0.0];
        let a = e.update(&s);
        assert!((bias_walk(&e) - before).norm() < 1e-15);
        // The encoders turned the attitude meanwhile.
        assert!(a.roll > 0.1 * roll, "{} {roll}", a.roll);
        // BIAS_HOLD after the hold the bias is learnt again.
        for k in 2301..2400 + (BIAS_HOLD * 1e3) as usize {
            let mut s = still(k, [0.01, 0.0, 0.0]);
            s.phi = [roll, 0.0];
            e.update(&s);
        }
        assert!((bias_walk(&e) - before).norm() > 1e-9);
    }

    /// On a level body the heading and the z bias are unobserved: the heading variance
    /// would grow as the z bias's variance times t^2; it is held at or below twice its
    /// bound, and roll and pitch stay exact.
    #[test]
    fn the_unobserved_heading_variance_is_bounded() {
        let mut e = Ekf::<f64>::new(Settings::default());
        let mut worst = 0.0f64;
        for k in 0..300_000 {
            let s = SpatialSample {
                dt: if k == 0 { 0.0 } else { 1e-3 },
                phi: [0.0, 0.0],
                gyro: [0.0; 3],
                accel: [f64::NAN; 3],
                speed: f64::NAN,
            };
            let a = e.update(&s);
            worst = worst.max(a.roll.abs()).max(a.pitch.abs());
        }
        let x = e.state().unwrap();
        let p = e
            .covariance()
            .unwrap()
            .fixed_view::<3, 3>(ROT, ROT)
            .into_owned();
        let u = x.up();
        let var = u.dot(&(p * u));
        assert!(var <= 2.0 * HEADING_VARIANCE + 1e-9, "{var}");
        // Without the bound it would be about 3e-4 (rad/s)^2 (300 s)^2 = 27 rad^2.
        assert!(var > 0.5 * HEADING_VARIANCE, "{var}");
        assert!(worst < 1e-9, "{worst}");
    }

    /// O accelerates along body x on a level body (a smooth 2 m/s^2 pulse from 2 to 6 s),
    /// the joints following the filter's own equations of motion under that force. The
    /// pendulum alone reads 11 deg of apparent pitch at the peak; with the speed column
    /// (0.05 m/s of noise) ekf3d and ukf3d put it into O's acceleration, which the speed
    /// alone gives only through its derivative, and stay level; so does ekf3d with the
    /// speed on one row in 20 (a 50 Hz wheel-speed signal in a 1 kHz log).
    #[test]
    fn the_speed_column_tells_acceleration_from_tilt() {
        let st = Settings::<f64>::default();
        let model = st.process_model();
        let accel = |t: f64| {
            if (2.0..6.0).contains(&t) {
                2.0 * (core::f64::consts::PI * (t - 2.0) / 4.0).sin().powi(2)
            } else {
                0.0
            }
        };
        // The speed (1 m/s at the start), the integral of `accel`, and a deterministic
        // noise of sd 0.05 m/s.
        let speed = |t: f64| {
            let tau = (t - 2.0).clamp(0.0, 4.0);
            1.0 + tau - 2.0 / core::f64::consts::PI * (core::f64::consts::PI * tau / 2.0).sin()
        };
        let noise = |k: usize| (((k * 7919 + 13) % 1000) as f64 / 1000.0 - 0.5) * 0.173;
        let drive = Drive {
            gyro: Vector3::zeros(),
            angular_accel: Vector3::zeros(),
            path_gyro: Vector3::zeros(),
            slow_gyro: Vector3::zeros(),
            z_bias: 0.0,
        };
        let up = Vector3::z();
        let mut joints = Vector4::<f64>::zeros();
        let mut with = Ekf::<f64>::new(st);
        let mut with_ukf = crate::spatial::ekf::Ukf::<f64>::new(st);
        let mut without = Ekf::<f64>::new(st);
        let mut sparse = Ekf::<f64>::new(st);
        let (mut worst, mut worst_ukf, mut apparent, mut rate_err) =
            (0.0f64, 0.0f64, 0.0f64, 0.0f64);
        let mut worst_sparse = 0.0f64;
        for k in 0..8000 {
            let t = k as f64 * 1e-3;
            if k > 0 {
                let travel = Vector2::new(speed(t), accel(t));
                joints = model.joint_step(&joints, &Vector3::zeros(), &drive, (&up, &travel), 1e-3);
            }
            let mut s = SpatialSample {
                dt: if k == 0 { 0.0 } else { 1e-3 },
                phi: [-joints[0], -joints[1]],
                gyro: [0.0; 3],
                accel: [f64::NAN; 3],
                speed: speed(t) + noise(k),
            };
            let a = with.update(&s);
            let u = with_ukf.update(&s);
            let reading = s.speed;
            s.speed = f64::NAN;
            let b = without.update(&s);
            s.speed = if k % 20 == 0 { reading } else { f64::NAN };
            let c = sparse.update(&s);
            let incl = |a: &Attitude<f64>| a.roll.hypot(a.pitch).to_degrees();
            if t > 1.0 {
                worst = worst.max(incl(&a));
                worst_ukf = worst_ukf.max(incl(&u));
                apparent = apparent.max(incl(&b));
                worst_sparse = worst_sparse.max(incl(&c));
                rate_err = rate_err.max((with.state().unwrap().travel[1] - accel(t)).abs());
            }
        }
        // Measured: 11.3 deg without the speed; 0.083 deg (ekf3d and ukf3d) with it, the
        // rate within 0.12 m/s^2 (at the pulse's onset, where the jerk is largest).
        assert!(apparent > 10.0, "{apparent}");
        assert!(worst < 0.15, "{worst}");
        assert!(worst_ukf < 0.15, "{worst_ukf}");
        // One row in 20: 0.19 deg (20 times fewer readings); with the speed held at zero
        // on every row without one, as before SpeedSettings::timeout, 11.3 (none at all).
        assert!(worst_sparse < 0.3, "{worst_sparse}");
        assert!(rate_err < 0.2, "{rate_err}");
    }
}

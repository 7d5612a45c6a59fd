//! What the estimator carries from one sample to the next: the filter, the clock, and
//! the state of the gyro's hold, the speed, and the guard.
use super::gyro_hold::{HOLD_HZ, VIBRATION_TAU};
use crate::adaptation::ForcingAdaptation;
use crate::filters::diff::{Response, SmoothingDifferentiator};
use crate::filters::one_pole::{OnePole, OnePoleGain};
use crate::spatial::ekf::settings::Settings;
use crate::spatial::ekf::slip::SlipDetector;
use crate::spatial::imu::InclinationReference;
use crate::spatial::travel::PathRate;
use crate::spatial::Attitude;
use crate::{Real, StepClock};
use nalgebra::Vector3;

/// The state of [`super::ModelBased`] (VQF's split: settings, coefficients, state).
#[derive(Debug, Clone)]
pub(super) struct RunState<T: Real, F> {
    /// The Gaussian filter, once started.
    pub filter: Option<F>,
    pub clock: StepClock<T>,
    /// The last estimate, held while none is made.
    pub last: Attitude<T>,
    /// Time since the last sample with the gravity reference (the encoders, or imu3d's
    /// accelerometer) \[s\], once there was one.
    pub since_phi: Option<T>,
    /// Time since the filter (re)started \[s\].
    pub since_start: T,
    /// The gyro bias and its variances kept over a gap for the next start.
    pub kept_bias: Option<(Vector3<T>, Vector3<T>)>,
    /// The factor on the forcing's variance (`Settings::adaptation`), >= 1.
    pub forcing: ForcingAdaptation<T>,
    /// Time since the last encoder reading that was used \[s\] (for the adaptation's
    /// step).
    pub since_used: T,
    /// Consecutive encoder readings the gate rejected.
    pub rejected: u32,
    /// The pendulum is out of its range: the joint states start again at the next
    /// reading in range.
    pub out_of_range: bool,
    pub gyro: GyroState<T>,
    pub speed: SpeedState<T>,
    pub guard: GuardState<T>,
}

/// The gyro's readings, their low-passes and derivative, and its holds and clips.
#[derive(Debug, Clone)]
pub(super) struct GyroState<T: Real> {
    /// The last reading with all three axes.
    pub reading: Option<Vector3<T>>,
    /// The gyro low-passed (`HOLD_HZ`): what a hold bridges with.
    pub smooth: OnePole<T, 3>,
    /// The mean square of the gyro's departure from `smooth`, per axis (`VIBRATION_TAU`).
    pub vibration: OnePole<T, 3>,
    /// How long the gyro reading has been held \[s\].
    pub held_for: T,
    /// How long each gyro axis has been at its full scale \[s\].
    pub clipped_for: Vector3<T>,
    /// The gyro's smoothed rate of change on entering each axis' clip \[rad/s^2\].
    pub clip_slope: Vector3<T>,
    /// The gyro's smoothed derivative: the body's angular acceleration.
    pub diff: SmoothingDifferentiator<T, 3>,
    /// The path's turn and pitch rate from the gyro.
    pub path: PathRate<T>,
    /// The gyro bias before a run of held (missing or clipped) gyro readings, kept until
    /// `BIAS_HOLD` after the last.
    pub held_bias: Option<Vector3<T>>,
    /// Whether the current hold read a clip found in the log.
    pub clip_hold: bool,
    /// How long since the last hold \[s\].
    pub since_hold: T,
}

/// The `speed` column's readings and O's travel.
#[derive(Debug, Clone)]
pub(super) struct SpeedState<T: Real> {
    /// The `speed` column has been read since the start: O's speed and rate are states.
    pub travelling: bool,
    /// Consecutive speed readings the gate rejected.
    pub rejected: u32,
    /// Time since the last `speed` reading \[s\], once there was one.
    pub since: Option<T>,
    /// That reading.
    pub last: T,
    /// Wheel slip on the speed.
    pub slip: SlipDetector<T>,
}

/// The guard's inclination reference.
#[derive(Debug, Clone)]
pub(super) struct GuardState<T: Real> {
    /// The gyro and accelerometer's inclination (`Settings::guard_angle`).
    pub reference: InclinationReference<T>,
    /// How long it has run \[s\].
    pub age: T,
    /// The gyro was held: the reference takes the filter's inclination on its return.
    pub held: bool,
}

impl<T: Real, F> RunState<T, F> {
    /// The state before the first sample.
    pub fn new(settings: &Settings<T>) -> Self {
        Self {
            filter: None,
            clock: StepClock::new(),
            last: Attitude::unknown(),
            since_phi: None,
            since_start: T::zero(),
            kept_bias: None,
            forcing: ForcingAdaptation::new(),
            since_used: T::zero(),
            rejected: 0,
            out_of_range: false,
            gyro: GyroState::new(settings),
            speed: SpeedState {
                travelling: false,
                rejected: 0,
                since: None,
                last: T::zero(),
                slip: SlipDetector::new(settings.slip),
            },
            guard: GuardState {
                reference: InclinationReference::new(settings.guard_tau),
                age: T::zero(),
                held: false,
            },
        }
    }

    /// Forgets everything ([`crate::Estimator::reset`]).
    pub fn reset(&mut self) {
        self.filter = None;
        self.clock.restart();
        self.since_phi = None;
        self.gyro.reset();
        self.speed.reset();
        self.rejected = 0;
        self.last = Attitude::unknown();
        self.kept_bias = None;
        self.forcing.reset();
        self.since_used = T::zero();
        self.out_of_range = false;
        self.guard.reset();
    }
}

impl<T: Real> GyroState<T> {
    fn new(settings: &Settings<T>) -> Self {
        Self {
            reading: None,
            smooth: OnePole::new(OnePoleGain::from_hz(T::lit(HOLD_HZ))),
            vibration: OnePole::new(OnePoleGain::from_time_constant(T::lit(VIBRATION_TAU))),
            held_for: T::zero(),
            clipped_for: Vector3::zeros(),
            clip_slope: Vector3::zeros(),
            diff: SmoothingDifferentiator::new(Response::Bessel, settings.angular_accel_hz),
            path: PathRate::new(&settings.path),
            held_bias: None,
            clip_hold: false,
            since_hold: T::zero(),
        }
    }

    fn reset(&mut self) {
        self.reading = None;
        self.smooth.reset();
        self.vibration.reset();
        self.held_for = T::zero();
        self.clipped_for = Vector3::zeros();
        self.clip_slope = Vector3::zeros();
        self.diff.reset();
        self.path.reset();
        self.held_bias = None;
        self.since_hold = T::zero();
        self.clip_hold = false;
    }
}

impl<T: Real> SpeedState<T> {
    fn reset(&mut self) {
        self.travelling = false;
        self.rejected = 0;
        self.since = None;
        self.slip.reset();
    }
}

impl<T: Real> GuardState<T> {
    /// Starts the reference again (a reset, or a gap: its attitude is as stale as the
    /// filter's).
    pub fn reset(&mut self) {
        self.reference.reset();
        self.age = T::zero();
    }
}

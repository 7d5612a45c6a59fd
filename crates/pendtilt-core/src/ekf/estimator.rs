//! The streaming estimator around a [`GaussianFilter`] of the engine: time steps,
//! start-up, missing samples, restarts, and the loop over the sensors
//! (`super::sensor`) with their innovation gates. [`super::Ekf`] and [`super::Ukf`] are
//! this over the EKF and the UKF.
//!
//! Kept apart as VQF keeps them: the [`ModelSettings`], the coefficients computed from
//! them and from the step length (`coefficients`), and the state carried from one sample
//! to the next (`run_state`); the gates and the adaptation (`sensing`), starts and gaps
//! (`restart`), and the encoder's measured noise (`encoder_noise`) in modules of their
//! own.
mod coefficients;
mod encoder_noise;
mod restart;
mod run_state;
mod sensing;
#[cfg(test)]
mod tests;

use self::coefficients::Coefficients;
use self::run_state::RunState;
use super::model::{Cov, State, BIAS, N, OMEGA, PHI, THETA};
use super::sensor::wrap;
use super::settings::ModelSettings;
use crate::engine::{substeps, GaussianFilter};
use crate::{Estimate, Estimator, Flags, Real, Sample};

/// Time constant \[s\] of the low-passed theta' the filter coasts on while the gyro is
/// missing ([`ModelBased`]): long enough to average the body's angular vibration out (the
/// scooter's 40 Hz), short next to its manoeuvres.
pub const SLOW_RATE_TAU: f64 = 0.025;

/// How uncertain theta' is when the gyro goes missing, in units of
/// [`ModelSettings::gyro_vibration`] (standard deviation): theta' is then the 25 ms mean
/// ([`SLOW_RATE_TAU`]), which leaves a sixth of the vibration and lags the manoeuvres. 3 (the
/// earlier value) let the encoder's readings, which the unknown translation of the pivot
/// swings, turn theta: a 450 ms gyro gap in a turn of the scooter ride (seed 6, from
/// 8.2 s) put the EKF 5.7 deg off, 0.45 deg RMS over the ride; with 1, 0.21 deg RMS and
/// no excursion beyond the start's. Over 27 bursts of 100 missing readings (seeds 1, 3,
/// 6) the EKF is back within 0.05 deg of its fault-free run within 2 s in 24, as with 3
/// (0.5: 23, at most 5.6 s).
pub const MISSING_RATE_SIGMAS: f64 = 1.0;

/// Time constant \[s\] of the mean square of the encoder's second difference, the
/// encoder's own noise measured on the log ([`ModelBased`]): long next to one sample, short
/// next to a ride, so that a noisier encoder than the settings say is known within seconds.
pub const ENCODER_NOISE_TAU: f64 = 1.0;

/// The gate on one second difference of the encoder, in units of the variance measured so
/// far (at least the settings'): the innovation gate's 50.
pub const NOISE_GATE: f64 = 50.0;

/// A model-based tilt estimator (see the module documentation of [`super`]).
///
/// With [`ModelSettings::adaptation`] on (the default), the pendulum's forcing variance
/// ([`super::ProcessNoise::pendulum`]) is scaled by a factor that follows the encoder's
/// normalised innovation squared before its update ([`crate::adaptation`]), and the
/// encoder's variance is at least its noise measured on the log (the second difference of
/// consecutive accepted readings, [`ENCODER_NOISE_TAU`]): otherwise an encoder noisier than
/// the settings say would raise the innovations and the forcing with them. Only readings
/// the gate accepted count, and none within
/// [`SETTLE_SECONDS`](crate::adaptation::SETTLE_SECONDS) of a start (a restart after a
/// gap starts the factor again at 1), while the gate is held open after a gap or a
/// re-acquisition, or on a sample without the gyro: those innovations are the filter's,
/// not the motion's. A run of rejections is the re-acquisition's to handle.
///
/// Per sample: predict over `dt` (split into steps of at most
/// [`ModelSettings::max_step`]), then update with each sensor in turn (the gyro, the
/// encoder and, if enabled, the accelerometer), each only if its reading is finite. The first sample with a finite phi starts the
/// filter at `theta = phi` (the pendulum at rest), `theta' = gyro`. After a gap longer
/// than [`ModelSettings::max_gap`] (between rows, or of the encoder while the gyro was
/// missing too: with the gyro, theta is followed through an encoder gap) it starts again
/// the same way but keeps its gyro bias, whose variance grows by the bias random walk
/// over the gap; so does [`Estimator::resume`]. If the filter ever becomes non-finite it
/// starts afresh, as [`Estimator::reset`] does.
///
/// A gyro gap: the filter tracks the body's angular vibration in theta' and theta''
/// (the gyro's noise is far below it), so on the first sample without the gyro they
/// are replaced by the slow rate and zero and loosened (`loosen`), and on the first
/// reading after it the rate is set from the reading without moving theta or the bias
/// (`unhook`); the encoder then corrects theta. After 100 missing gyro readings on the
/// scooter ride (seed 6) this put the filter back within 0.05 deg of the fault-free run
/// after 0.81 s, where plain prediction left it 1 deg off for over 10 s (the error went
/// into the bias).
///
/// Each measurement goes through the innovation gate ([`ModelSettings::innovation_gate`]):
/// an outlier is skipped and the sample flagged [`Flags::MEASUREMENT_SKIPPED`]. After
/// [`ModelSettings::reacquire_after`] consecutive rejections of one measurement the
/// filter re-acquires it: for an innovation `y` it adds `v v^T` to the covariance with
/// the sensor's directions (`Sensor::inflation`):
/// - encoder: `v = y` on theta and on phi together, a tilt step that leaves the pendulum
///   where it hangs (an encoder re-zero reads exactly so; inflating phi and phi' apart,
///   a pendulum swing, sent the nonlinear model spinning after a 2.5 rad step),
/// - gyro: `v = y` on theta', and separately `v = y` on the bias (a rate or an offset),
/// - accelerometer: `v = |y| / g` on theta,
///
/// then applies the measurement without the gate.
#[derive(Debug, Clone)]
pub struct ModelBased<T: Real, F> {
    settings: ModelSettings<T>,
    coeffs: Coefficients<T>,
    state: RunState<T, F>,
}

impl<T: Real, F: GaussianFilter<T, State<T>, N>> ModelBased<T, F> {
    /// A new estimator.
    pub fn new(settings: ModelSettings<T>) -> Self {
        let coeffs = Coefficients::new(&settings);
        Self {
            state: RunState::new(coeffs.encoder_r),
            coeffs,
            settings,
        }
    }

    /// The settings in use.
    pub fn settings(&self) -> &ModelSettings<T> {
        &self.settings
    }

    /// The underlying filter (state and covariance), once started.
    pub fn filter(&self) -> Option<&F> {
        self.state.filter.as_ref()
    }

    /// The state estimate `[theta, theta', theta'', phi, phi', bias]`, once started.
    pub fn state(&self) -> Option<&State<T>> {
        self.state.filter.as_ref().map(|f| f.state())
    }

    /// The state covariance, once started.
    pub fn covariance(&self) -> Option<&Cov<T>> {
        self.state.filter.as_ref().map(|f| f.covariance())
    }

    /// The gyro-bias estimate [rad/s] (0 before the start).
    pub fn bias(&self) -> T {
        self.state().map_or(T::zero(), |x| x[BIAS])
    }

    /// The factor on the pendulum's forcing variance the adaptation has reached (1: the
    /// settings' [`super::ProcessNoise::pendulum`]).
    pub fn forcing_factor(&self) -> T {
        self.state.forcing.factor()
    }

    /// The low-passed normalised innovation squared of the encoder that drives the
    /// adaptation, once one counted.
    pub fn innovation_mean(&self) -> Option<T> {
        self.state.forcing.mean()
    }

    /// The encoder's variance as the filter takes it \[rad^2\]: the settings', floored
    /// by the noise measured on the log while the adaptation is on.
    pub fn encoder_variance(&self) -> T {
        self.state.encoder.r
    }

    fn gyro_variance(&self, dt: T) -> T {
        let d = self.settings.sensors.gyro_density;
        (d * d / dt).max(T::lit(1e-14))
    }

    /// Predicts over `dt`, split into steps no longer than [`ModelSettings::max_step`];
    /// `false` if a step could not be propagated.
    #[inline(always)]
    fn predict(&mut self, dt: T) -> bool {
        let (n, h) = substeps(dt, self.settings.max_step);
        self.coeffs.noise.refresh(&self.coeffs.model, h);
        // At the factor 1 (always, without the adaptation) the noise is the settings' to
        // the bit.
        let f = self.state.forcing.factor();
        let scaled;
        let q = if f == T::one() {
            self.coeffs.noise.plain()
        } else {
            scaled = self.coeffs.noise.scaled(f);
            &scaled
        };
        let Some(filter) = self.state.filter.as_mut() else {
            return false;
        };
        let mut ok = true;
        for _ in 0..n {
            ok &= filter.predict(&self.coeffs.model, &(), h, q);
        }
        ok
    }

    /// Keeps theta within a turn (phi moves with it: only phi - theta is physical).
    #[inline(always)]
    fn keep_theta_in_turn(filter: &mut F) {
        let th = filter.state()[THETA];
        if th.abs() > T::pi() {
            let d = wrap(th) - th;
            let mut dx = State::<T>::zeros();
            dx[THETA] = d;
            dx[PHI] = d;
            filter.retract(&dx);
        }
    }

    /// Whether the state and the covariance's diagonal are finite: a NaN or infinity
    /// anywhere makes the sum non-finite (off-diagonal terms reach the diagonal at the
    /// next step).
    #[inline(always)]
    fn is_finite(filter: &F) -> bool {
        let x = filter.state();
        let p = filter.covariance();
        (0..x.len())
            .fold(T::zero(), |acc, i| acc + x[i] + p[(i, i)])
            .is_finite()
    }
}

impl<T: Real, F: GaussianFilter<T, State<T>, N>> Estimator for ModelBased<T, F> {
    type Input = Sample<T>;
    type Output = Estimate<T>;

    #[inline]
    fn update(&mut self, s: &Sample<T>) -> Estimate<T> {
        let Ok(step) = self.state.clock.offer(s.dt) else {
            return self.hold(Flags::BAD_TIME_STEP);
        };
        let dt = step.unwrap_or(T::zero());
        if let Some(start) = self.gaps(s, dt) {
            return start;
        }
        let r_gyro = self.gyro_variance(dt);
        let ok = self.predict(dt);
        if self.state.filter.is_none() {
            return self.hold(Flags::INITIALISING);
        }
        self.state.clock.accept();
        let (flags, enc) = self.sense_all(s, r_gyro);
        let Some(filter) = self.state.filter.as_mut() else {
            return self.hold(Flags::INITIALISING);
        };
        Self::keep_theta_in_turn(filter);
        if !ok || !Self::is_finite(filter) {
            // Start again at the next sample with a phi.
            self.state.filter = None;
            return self.hold(flags | Flags::INITIALISING);
        }
        self.learn(s, dt, enc);
        let x = *self.state().unwrap_or(&State::<T>::zeros());
        let theta = x[THETA];
        if s.gyro.is_finite() {
            let a = (dt / T::lit(SLOW_RATE_TAU)).min(T::one());
            let run = &mut self.state;
            run.slow_rate = run.slow_rate + a * (x[OMEGA] - run.slow_rate);
        }
        self.state.last_theta = theta;
        Estimate { theta, flags }
    }

    fn reset(&mut self) {
        self.state.reset(self.coeffs.encoder_r);
    }

    /// Forgets everything but the gyro bias, which restarts with its variance grown by
    /// its random walk over the gap ([`ModelSettings::sensors`]' `gyro_bias_walk`).
    fn resume(&mut self) {
        self.drop_keeping_bias();
        let kept = self.state.kept_bias;
        self.reset();
        self.state.kept_bias = kept;
    }
}

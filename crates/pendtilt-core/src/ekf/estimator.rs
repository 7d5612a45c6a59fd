//! The streaming estimator around a [`GaussianFilter`] of the engine: time steps,
//! start-up, missing samples, restarts, and the loop over the sensors
//! (`super::sensor`) with their innovation gates. [`super::Ekf`] and [`super::Ukf`] are
//! this over the EKF and the UKF.
use super::measurement::{Accelerometer, Encoder, Gyro};
use super::model::{
    Cov, PendulumProcess, ProcessNoise, State, ALPHA, BIAS, DPHI, N, OMEGA, PHI, THETA,
};
use super::sensor::{wrap, Sensor};
use super::settings::ModelSettings;
use crate::adaptation::{ForcingAdaptation, SETTLE_SECONDS};
use crate::engine::{substeps, Gate, GaussianFilter, ProcessModel, Rejected};
use crate::{Estimate, Estimator, Flags, Real, Sample, StepClock};

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

/// The encoder's noise measured on its readings: the mean square of the second difference
/// of consecutive accepted readings over 6 (white noise of variance `s^2` has a second
/// difference of variance `6 s^2`; the pendulum's own motion adds `phi'' dt^2`, 1e-5 rad at
/// 10 rad/s^2 and 1 kHz, far below a 12-bit encoder's rounding).
#[derive(Debug, Clone, Copy, PartialEq)]
struct EncoderNoise<T> {
    last: [T; 2],
    // Consecutive accepted readings in `last` (0-2).
    run: u8,
    mean: Option<T>,
    // The smallest change between consecutive readings: a quantised encoder's step.
    step: Option<T>,
    // How long the mean has run \[s\].
    age: T,
}

impl<T: Real> EncoderNoise<T> {
    fn new() -> Self {
        Self {
            last: [T::zero(); 2],
            run: 0,
            mean: None,
            step: None,
            age: T::zero(),
        }
    }

    /// A reading `phi`, `dt` after the last row. A second difference beyond
    /// [`NOISE_GATE`] times the variance so far (at least `floor`) is a jump (a glitch, a
    /// re-zero), not noise: it is left out and the run starts again.
    fn push(&mut self, phi: T, dt: T, floor: T) {
        if self.run >= 2 {
            // Wrapped, for an encoder that turns past +-pi.
            let d1 = wrap(phi - self.last[1]);
            let d2 = d1 - wrap(self.last[1] - self.last[0]);
            let v = d2 * d2 / T::lit(6.0);
            let so_far = self.mean.unwrap_or(T::zero()).max(floor);
            if v > T::lit(NOISE_GATE) * so_far {
                self.last = [self.last[1], phi];
                self.run = 1;
                return;
            }
            if d1.abs() > T::lit(1e-12) {
                self.step = Some(self.step.map_or(d1.abs(), |q| q.min(d1.abs())));
            }
            let k = (dt / T::lit(ENCODER_NOISE_TAU)).min(T::one());
            self.mean = Some(self.mean.map_or(v, |m| m + k * (v - m)));
            self.age += dt;
        }
        self.last = [self.last[1], phi];
        self.run = (self.run + 1).min(2);
    }

    /// A reading missing or not accepted: the next second difference waits for three in
    /// a row again.
    fn interrupt(&mut self) {
        self.run = 0;
    }

    /// The measured variance \[rad^2\]: the second difference's, or the rounding's
    /// (`q^2 / 12`), whichever is larger (a clean encoder's rounding is not white on a
    /// slow signal, and its second difference reads less); `None` until it has run for
    /// [`ENCODER_NOISE_TAU`].
    fn variance(&self) -> Option<T> {
        let q = self.step.unwrap_or(T::zero());
        self.mean
            .filter(|_| self.age >= T::lit(ENCODER_NOISE_TAU))
            .map(|m| m.max(q * q / T::lit(12.0)))
    }
}

/// A model-based tilt estimator (see the module documentation of [`super`]).
///
/// With [`ModelSettings::adaptation`] on (the default), the pendulum's forcing variance
/// ([`super::ProcessNoise::pendulum`]) is scaled by a factor that follows the encoder's
/// normalised innovation squared before its update ([`crate::adaptation`]), and the
/// encoder's variance is at least its noise measured on the log (the second difference of
/// consecutive accepted readings, [`ENCODER_NOISE_TAU`]): otherwise an encoder noisier than
/// the settings say would raise the innovations and the forcing with them. Only readings
/// the gate accepted count, and none within [`SETTLE_SECONDS`] of a start (a restart after
/// a gap starts the factor again at 1), while the gate is held open after a gap or a
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
    model: PendulumProcess<T>,
    accel: Accelerometer<T>,
    encoder: Encoder<T>,
    q_step: T,
    q: Cov<T>,
    // The part of `q` the pendulum's forcing adds, scaled by the adapted factor.
    q_forcing: Cov<T>,
    forcing: ForcingAdaptation<T>,
    // The settings' encoder variance, which the measured noise floors.
    encoder_r: T,
    encoder_noise: EncoderNoise<T>,
    // Time since the filter (re)started, and since the last encoder reading \[s\].
    since_start: T,
    since_reading: T,
    filter: Option<F>,
    clock: StepClock<T>,
    // Time since the last row with an encoder reading.
    since_phi: Option<T>,
    // Time since the last row with a gyro reading.
    since_gyro: Option<T>,
    // The gyro bias and its variance kept through a restart after a gap.
    kept_bias: Option<(T, T)>,
    // theta' low-passed (the body's slow rate without its vibration), what the filter
    // coasts on while the gyro is missing.
    slow_rate: T,
    last_theta: T,
    runs: Runs,
}

/// Where one measurement stands with the innovation gate.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Lock {
    /// Gated; the count of consecutive rejections so far.
    Tracking(u32),
    /// Applied without the gate for this many more samples: after a gap (the prediction
    /// coasted with theta'' held at its last value, vibration and all, and its
    /// covariance is too small) or a re-acquisition (the prediction was wrong).
    Open(u32),
}

impl Default for Lock {
    fn default() -> Self {
        Lock::Tracking(0)
    }
}

/// The gate state of each measurement.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
struct Runs {
    phi: Lock,
    gyro: Lock,
    accel: Lock,
}

impl<T: Real, F: GaussianFilter<T, State<T>, N>> ModelBased<T, F> {
    /// A new estimator.
    pub fn new(settings: ModelSettings<T>) -> Self {
        let dt = T::lit(1e-3);
        let sens = &settings.sensors;
        let accel = Accelerometer {
            gravity: settings.gravity,
            distance: settings.accel_distance,
            r: sens.accel_density * sens.accel_density / dt
                + settings.accel_vibration * settings.accel_vibration,
        };
        let encoder_r = settings.encoder_variance().max(T::lit(1e-14));
        Self {
            model: settings.process_model(),
            accel,
            encoder: Encoder { r: encoder_r },
            q_step: T::zero(),
            q: Cov::<T>::zeros(),
            q_forcing: Cov::<T>::zeros(),
            forcing: ForcingAdaptation::new(),
            encoder_r,
            encoder_noise: EncoderNoise::new(),
            since_start: T::zero(),
            since_reading: T::zero(),
            settings,
            filter: None,
            clock: StepClock::new(),
            since_phi: None,
            since_gyro: None,
            kept_bias: None,
            slow_rate: T::zero(),
            last_theta: T::nan(),
            runs: Runs::default(),
        }
    }

    /// The settings in use.
    pub fn settings(&self) -> &ModelSettings<T> {
        &self.settings
    }

    /// The underlying filter (state and covariance), once started.
    pub fn filter(&self) -> Option<&F> {
        self.filter.as_ref()
    }

    /// The state estimate `[theta, theta', theta'', phi, phi', bias]`, once started.
    pub fn state(&self) -> Option<&State<T>> {
        self.filter.as_ref().map(|f| f.state())
    }

    /// The state covariance, once started.
    pub fn covariance(&self) -> Option<&Cov<T>> {
        self.filter.as_ref().map(|f| f.covariance())
    }

    /// The gyro-bias estimate [rad/s] (0 before the start).
    pub fn bias(&self) -> T {
        self.state().map_or(T::zero(), |x| x[BIAS])
    }

    /// The factor on the pendulum's forcing variance the adaptation has reached (1: the
    /// settings' [`super::ProcessNoise::pendulum`]).
    pub fn forcing_factor(&self) -> T {
        self.forcing.factor()
    }

    /// The low-passed normalised innovation squared of the encoder that drives the
    /// adaptation, once one counted.
    pub fn innovation_mean(&self) -> Option<T> {
        self.forcing.mean()
    }

    /// The encoder's variance as the filter takes it \[rad^2\]: the settings', floored
    /// by the noise measured on the log while the adaptation is on.
    pub fn encoder_variance(&self) -> T {
        self.encoder.r
    }

    fn gyro_variance(&self, dt: T) -> T {
        let d = self.settings.sensors.gyro_density;
        (d * d / dt).max(T::lit(1e-14))
    }

    fn start(&mut self, s: &Sample<T>) -> Estimate<T> {
        let st = &self.settings;
        let b0 = st.sensors.gyro_bias;
        let kept = self.kept_bias.is_some();
        let (bias, bias_var) = self
            .kept_bias
            .take()
            .unwrap_or((T::zero(), b0 * b0 + T::lit(1e-12)));
        let (w0, w_var) = if s.gyro.is_finite() {
            let var = if kept { bias_var } else { b0 * b0 };
            (s.gyro, var + self.gyro_variance(T::lit(1e-3)))
        } else {
            (T::zero(), T::one())
        };
        let mut x = State::<T>::zeros();
        x[THETA] = s.phi;
        x[OMEGA] = w0 - bias;
        x[PHI] = s.phi;
        x[BIAS] = bias;
        let mut p = Cov::<T>::zeros();
        p[(THETA, THETA)] = st.initial_angle * st.initial_angle + self.encoder.r;
        p[(OMEGA, OMEGA)] = w_var;
        p[(ALPHA, ALPHA)] = T::lit(100.0);
        p[(PHI, PHI)] = self.encoder.r;
        p[(DPHI, DPHI)] = T::lit(0.01);
        p[(BIAS, BIAS)] = bias_var;
        if kept && s.gyro.is_finite() {
            // theta' = gyro - bias: their errors are opposite.
            p[(OMEGA, BIAS)] = -bias_var;
            p[(BIAS, OMEGA)] = -bias_var;
        }
        self.filter = Some(F::start(x, p));
        self.slow_rate = x[OMEGA];
        self.runs = Runs::default();
        self.forcing.reset();
        self.since_start = T::zero();
        self.since_reading = T::zero();
        self.clock.accept();
        self.last_theta = s.phi;
        Estimate {
            theta: s.phi,
            flags: Flags::INITIALISING,
        }
    }

    /// Applies `sensor`'s reading of `s`, if it has one, through its gate ([`Lock`]).
    /// After [`ModelSettings::reacquire_after`] consecutive rejections, `v v^T` is added
    /// to the covariance for each `v` of [`Sensor::inflation`] and the gate is held open
    /// for as many samples (as after a gap). Returns the reading's flags, and
    /// [`Flags::MEASUREMENT_SKIPPED`] if it was not applied.
    #[inline(always)]
    fn sense<Z: Sensor<T, M>, const M: usize>(
        filter: &mut F,
        settings: &ModelSettings<T>,
        sensor: &Z,
        s: &Sample<T>,
        lock: &mut Lock,
    ) -> Flags {
        let n = settings.reacquire_after.max(1);
        let Some((z, flags)) = sensor.reading(s, filter.state()) else {
            *lock = Lock::Open(n);
            return Z::MISSING;
        };
        let gate = match *lock {
            Lock::Tracking(run) if run >= n => {
                for v in &sensor.inflation(s, filter.state()) {
                    filter.inflate(v);
                }
                *lock = Lock::Open(n);
                Gate::off()
            }
            Lock::Tracking(_) => sensor.gate(settings.innovation_gate),
            Lock::Open(_) => Gate::off(),
        };
        flags
            | match filter.update(sensor, &z, gate) {
                Ok(()) => {
                    *lock = match *lock {
                        Lock::Open(k) if k > 1 => Lock::Open(k - 1),
                        _ => Lock::Tracking(0),
                    };
                    Flags::empty()
                }
                Err(Rejected::Outlier) => {
                    if let Lock::Tracking(run) = lock {
                        *run += 1;
                    }
                    Flags::MEASUREMENT_SKIPPED
                }
                Err(_) => Flags::MEASUREMENT_SKIPPED,
            }
    }

    /// Predicts over `dt`, split into steps no longer than [`ModelSettings::max_step`];
    /// `false` if a step could not be propagated.
    #[inline(always)]
    fn predict(&mut self, dt: T) -> bool {
        let (n, h) = substeps(dt, self.settings.max_step);
        if h != self.q_step {
            self.q = self.model.q(h);
            let forcing = PendulumProcess {
                params: self.model.params,
                noise: ProcessNoise {
                    jerk: T::zero(),
                    pendulum: self.model.noise.pendulum,
                    bias: T::zero(),
                },
            };
            self.q_forcing = forcing.q(h);
            self.q_step = h;
        }
        // At the factor 1 (always, without the adaptation) the noise is the settings' to
        // the bit.
        let f = self.forcing.factor();
        let scaled;
        let q = if f == T::one() {
            &self.q
        } else {
            scaled = self.q + self.q_forcing * (f - T::one());
            &scaled
        };
        let Some(filter) = self.filter.as_mut() else {
            return false;
        };
        let mut ok = true;
        for _ in 0..n {
            ok &= filter.predict(&self.model, &(), h, q);
        }
        ok
    }

    /// Drops the filter for a restart, keeping the gyro bias and its variance (a gap
    /// cannot change the bias beyond its random walk, which [`Self::start`] adds).
    fn drop_keeping_bias(&mut self) {
        if let Some(f) = self.filter.take() {
            let (b, v) = (f.state()[BIAS], f.covariance()[(BIAS, BIAS)]);
            if b.is_finite() && v.is_finite() {
                self.kept_bias = Some((b, v));
            }
        }
    }

    /// On the first sample without the gyro. The filter tracks the body's angular
    /// vibration in theta' and theta'' (the gyro's noise is far below it): coasting on them
    /// would carry one sample of the vibration through the gap (3 deg after 0.1 s on the
    /// scooter ride). theta' goes to its low-passed value ([`SLOW_RATE_TAU`]), theta''
    /// to 0, both become uncertain ([`MISSING_RATE_SIGMAS`]; theta'' as at the start) and
    /// uncorrelated with the other states. phi' moves with theta' (the pendulum's own
    /// rate phi' - theta' is kept).
    fn loosen(&mut self) {
        let Some(f) = self.filter.as_ref() else {
            return;
        };
        let mut x = *f.state();
        let mut p = *f.covariance();
        x[DPHI] = x[DPHI] + self.slow_rate - x[OMEGA];
        x[OMEGA] = self.slow_rate;
        x[ALPHA] = T::zero();
        split(&mut p, |i| i == OMEGA || i == ALPHA);
        let v = self.settings.gyro_vibration * T::lit(MISSING_RATE_SIGMAS);
        p[(OMEGA, OMEGA)] += v * v;
        p[(ALPHA, ALPHA)] += T::lit(100.0);
        self.filter = Some(F::start(x, p));
    }

    /// On the first gyro reading after a gap: theta' is set to it (less the bias), phi'
    /// moves with it, and the fast states (theta', theta'', phi, phi') become uncorrelated
    /// with theta and the bias. What the rate was off by at the end of the gap is mostly
    /// vibration, not a rate error that lasted the whole gap: through the covariance the
    /// gap built up, the reading would have moved theta by several degrees and the bias
    /// with it (which then took over 10 s to decay). The encoder then corrects theta.
    fn unhook(&mut self, gyro: T) {
        let Some(f) = self.filter.as_ref() else {
            return;
        };
        let mut x = *f.state();
        let mut p = *f.covariance();
        let w = gyro - x[BIAS];
        x[DPHI] = x[DPHI] + w - x[OMEGA];
        x[OMEGA] = w;
        split(&mut p, |i| {
            i == OMEGA || i == ALPHA || i == PHI || i == DPHI
        });
        self.filter = Some(F::start(x, p));
    }

    /// The gaps before sample `s` (step `dt`): a gap in the rows, or in the encoder's
    /// readings while the gyro was missing too, longer than [`ModelSettings::max_gap`] is
    /// not bridged (the prediction would extrapolate the last estimated tilt acceleration,
    /// vibration included, for the whole gap): the filter restarts, keeping its bias.
    /// A gyro gap starts with `loosen` and ends with `unhook`. Returns the estimate when
    /// the filter (re)starts on this sample or is waiting for a phi to start on.
    fn gaps(&mut self, s: &Sample<T>, dt: T) -> Option<Estimate<T>> {
        let gyro_was_there = self.since_gyro == Some(T::zero());
        for e in [self.since_phi.as_mut(), self.since_gyro.as_mut()]
            .into_iter()
            .flatten()
        {
            *e += s.dt;
        }
        let max_gap = self.settings.max_gap;
        // With the gyro, theta was followed through the encoder's gap.
        let gyro_gap = self.since_gyro.is_none_or(|e| e > max_gap);
        let coasted = s.phi.is_finite() && self.since_phi.is_some_and(|e| e > max_gap) && gyro_gap;
        if self.filter.is_some() && (dt > max_gap || coasted) {
            self.drop_keeping_bias();
        }
        if s.phi.is_finite() {
            self.since_phi = Some(T::zero());
        }
        if s.gyro.is_finite() {
            self.since_gyro = Some(T::zero());
        }
        if self.filter.is_none() {
            if !s.phi.is_finite() {
                return Some(self.hold(Flags::INITIALISING | Flags::SAMPLE_MISSING));
            }
            if let Some((_, v)) = self.kept_bias.as_mut() {
                // The bias walked over the gap (a jump in the rows; empty rows were
                // predicted through).
                let gap = if s.dt.is_finite() {
                    s.dt.max(T::zero())
                } else {
                    T::zero()
                };
                *v += self.settings.process.bias * gap;
            }
            return Some(self.start(s));
        }
        if !s.gyro.is_finite() && gyro_was_there {
            self.loosen();
        } else if s.gyro.is_finite() && !gyro_was_there {
            self.unhook(s.gyro);
        }
        None
    }

    fn hold(&self, flags: Flags) -> Estimate<T> {
        Estimate {
            theta: self.last_theta,
            flags,
        }
    }
}

impl<T: Real, F: GaussianFilter<T, State<T>, N>> Estimator for ModelBased<T, F> {
    type Input = Sample<T>;
    type Output = Estimate<T>;

    #[inline]
    fn update(&mut self, s: &Sample<T>) -> Estimate<T> {
        let Ok(step) = self.clock.offer(s.dt) else {
            return self.hold(Flags::BAD_TIME_STEP);
        };
        let mut flags = Flags::empty();
        let dt = step.unwrap_or(T::zero());
        if let Some(start) = self.gaps(s, dt) {
            return start;
        }
        let r_gyro = self.gyro_variance(dt);
        let ok = self.predict(dt);
        let Some(filter) = self.filter.as_mut() else {
            return self.hold(Flags::INITIALISING);
        };
        self.clock.accept();
        let st = &self.settings;
        let gyro = Gyro {
            r: r_gyro,
            gate_floor: st.gyro_vibration * st.gyro_vibration,
        };
        // The sensors, in this order; a new sensor is one more line.
        let runs = &mut self.runs;
        flags |= Self::sense(filter, st, &gyro, s, &mut runs.gyro);
        // The encoder's normalised innovation before its update, for the adaptation, and
        // whether the gate tests it (not held open, not re-acquiring).
        let gated = matches!(runs.phi, Lock::Tracking(run) if run < st.reacquire_after.max(1));
        let nis = {
            let (x, p) = (filter.state(), filter.covariance());
            let y = wrap(s.phi - x[PHI]);
            y * y / (p[(PHI, PHI)] + self.encoder.r)
        };
        let enc = Self::sense(filter, st, &self.encoder, s, &mut runs.phi);
        flags |= enc;
        if st.use_accel {
            flags |= Self::sense(filter, st, &self.accel, s, &mut runs.accel);
        }
        // Keep theta within a turn (phi moves with it: only phi - theta is physical).
        let th = filter.state()[THETA];
        if th.abs() > T::pi() {
            let d = wrap(th) - th;
            let mut dx = State::<T>::zeros();
            dx[THETA] = d;
            dx[PHI] = d;
            filter.retract(&dx);
        }
        // A NaN or infinity anywhere in the state or on P's diagonal makes the sum
        // non-finite (off-diagonal terms reach the diagonal at the next step).
        let x = filter.state();
        let p = filter.covariance();
        let finite = (0..x.len())
            .fold(T::zero(), |acc, i| acc + x[i] + p[(i, i)])
            .is_finite();
        if !ok || !finite {
            // Start again at the next sample with a phi.
            self.filter = None;
            return self.hold(flags | Flags::INITIALISING);
        }
        self.since_start += dt;
        self.since_reading += dt;
        if s.phi.is_finite() && st.adaptation.enabled {
            let since = core::mem::replace(&mut self.since_reading, T::zero());
            self.encoder_noise.push(s.phi, dt, self.encoder_r);
            if let Some(v) = self.encoder_noise.variance() {
                self.encoder.r = self.encoder_r.max(v);
            }
            let settled = self.since_start >= T::lit(SETTLE_SECONDS);
            let applied = !enc.contains(Flags::MEASUREMENT_SKIPPED);
            if applied && gated && settled && s.gyro.is_finite() {
                self.forcing.step(&st.adaptation, nis, since);
            }
        } else if !s.phi.is_finite() {
            self.encoder_noise.interrupt();
        }
        let theta = filter.state()[THETA];
        if s.gyro.is_finite() {
            let a = (dt / T::lit(SLOW_RATE_TAU)).min(T::one());
            self.slow_rate = self.slow_rate + a * (x[OMEGA] - self.slow_rate);
        }
        self.last_theta = theta;
        Estimate { theta, flags }
    }

    fn reset(&mut self) {
        self.filter = None;
        self.kept_bias = None;
        self.clock.restart();
        self.since_phi = None;
        self.since_gyro = None;
        self.last_theta = T::nan();
        self.runs = Runs::default();
        self.forcing.reset();
        self.encoder_noise = EncoderNoise::new();
        self.encoder.r = self.encoder_r;
    }

    /// Forgets everything but the gyro bias, which restarts with its variance grown by
    /// its random walk over the gap ([`ModelSettings::sensors`]' `gyro_bias_walk`).
    fn resume(&mut self) {
        self.drop_keeping_bias();
        let kept = self.kept_bias;
        self.reset();
        self.kept_bias = kept;
    }
}

/// Zeroes the covariance between the states `fast` picks and the others. The two diagonal
/// blocks are principal submatrices of a covariance, so the result is one too.
fn split<T: Real>(p: &mut Cov<T>, fast: impl Fn(usize) -> bool) {
    for i in 0..N {
        for j in 0..N {
            if fast(i) != fast(j) {
                p[(i, j)] = T::zero();
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ekf::ExtendedKalman;

    /// Sample `k` of a 1 kHz log (`k` is kept for the tests' readability).
    fn s(k: usize, phi: f64) -> Sample<f64> {
        Sample {
            dt: if k == 0 { 0.0 } else { 1e-3 },
            phi,
            gyro: 0.0,
            ax: f64::NAN,
            ay: f64::NAN,
        }
    }

    fn skipped(e: &mut ModelBased<f64, ExtendedKalman<f64>>, k: usize, phi: f64) -> bool {
        e.update(&s(k, phi))
            .flags
            .contains(Flags::MEASUREMENT_SKIPPED)
    }

    #[test]
    fn a_step_is_skipped_reacquire_after_times_then_followed() {
        let st = ModelSettings {
            reacquire_after: 5,
            ..ModelSettings::<f64>::default()
        };
        let mut e = ModelBased::<f64, ExtendedKalman<f64>>::new(st);
        for k in 0..2000 {
            e.update(&s(k, 0.1));
        }
        // A glitch shorter than reacquire_after: skipped, the estimate untouched.
        let before = e.state().unwrap()[THETA];
        assert!((2000..2004).all(|k| skipped(&mut e, k, 0.4)));
        assert!((e.state().unwrap()[THETA] - before).abs() < 1e-6);
        assert!(!skipped(&mut e, 2004, 0.1));
        // A step that stays: five rejections, then re-acquired and never rejected again.
        let flags: [bool; 10] = core::array::from_fn(|i| skipped(&mut e, 2005 + i, 0.4));
        assert_eq!(
            flags,
            [true, true, true, true, true, false, false, false, false, false]
        );
        let mut theta = 0.0;
        for k in 2015..3000 {
            let o = e.update(&s(k, 0.4));
            assert!(!o.flags.contains(Flags::MEASUREMENT_SKIPPED), "sample {k}");
            theta = o.theta;
        }
        assert!((theta - 0.4).abs() < 1e-3, "{theta}");
    }

    #[test]
    fn the_reading_after_a_gap_is_taken_ungated() {
        let mut e = ModelBased::<f64, ExtendedKalman<f64>>::new(ModelSettings::default());
        for k in 0..2000 {
            e.update(&s(k, 0.1));
        }
        assert!(skipped(&mut e, 2000, f64::NAN));
        // Far outside the gate, but the first reading after a gap.
        assert!(!skipped(&mut e, 2001, 0.2));
        // Without the gap it is an outlier.
        let mut f = ModelBased::<f64, ExtendedKalman<f64>>::new(ModelSettings::default());
        for k in 0..2001 {
            f.update(&s(k, 0.1));
        }
        assert!(skipped(&mut f, 2001, 0.2));
    }

    /// A still body on a gyro with a 0.01 rad/s bias: 20 s to learn the bias.
    fn biased(phi: f64, gyro: f64, k: usize) -> Sample<f64> {
        Sample {
            gyro: if gyro.is_nan() { gyro } else { gyro + 0.01 },
            ..s(k, phi)
        }
    }

    #[test]
    fn resume_keeps_the_bias_and_reset_forgets_it() {
        let mut e = ModelBased::<f64, ExtendedKalman<f64>>::new(ModelSettings::default());
        for k in 0..20_000 {
            e.update(&biased(0.1, 0.0, k));
        }
        let learnt = e.bias();
        assert!((learnt - 0.01).abs() < 1e-3, "{learnt}");
        let var = e.covariance().unwrap()[(BIAS, BIAS)];
        let mut f = e.clone();
        e.resume();
        // The next row comes 10 s later: the bias walked.
        let out = e.update(&Sample {
            dt: 10.0,
            ..biased(0.1, 0.0, 1)
        });
        assert!(out.flags.contains(Flags::INITIALISING));
        assert!((e.bias() - learnt).abs() < 1e-12);
        let walk = e.settings().process.bias * 10.0;
        let grown = e.covariance().unwrap()[(BIAS, BIAS)];
        assert!(
            (grown - (var + walk)).abs() <= 1e-9 * grown,
            "{grown} {var} {walk}"
        );
        f.reset();
        f.update(&biased(0.1, 0.0, 0));
        assert_eq!(f.bias(), 0.0);
    }

    #[test]
    fn an_encoder_gap_is_bridged_with_the_gyro_and_restarts_without_it() {
        let mut e = ModelBased::<f64, ExtendedKalman<f64>>::new(ModelSettings::default());
        for k in 0..20_000 {
            e.update(&biased(0.1, 0.0, k));
        }
        let learnt = e.bias();
        // 100 ms without the encoder (twice max_gap), the gyro there: no restart.
        let mut f = e.clone();
        for k in 0..100 {
            f.update(&biased(f64::NAN, 0.0, k + 1));
        }
        let back = f.update(&biased(0.1, 0.0, 101));
        assert!(!back.flags.contains(Flags::INITIALISING), "{back:?}");
        assert!((back.theta - 0.1).abs() < 1e-3, "{back:?}");
        // Without the gyro too: a restart that keeps the bias.
        for k in 0..100 {
            e.update(&biased(f64::NAN, f64::NAN, k + 1));
        }
        let back = e.update(&biased(0.1, 0.0, 101));
        assert!(back.flags.contains(Flags::INITIALISING), "{back:?}");
        assert!((e.bias() - learnt).abs() < 1e-12);
    }

    #[test]
    fn a_gyro_gap_leaves_theta_and_the_bias_where_they_were() {
        let mut e = ModelBased::<f64, ExtendedKalman<f64>>::new(ModelSettings::default());
        for k in 0..20_000 {
            e.update(&biased(0.1, 0.0, k));
        }
        let learnt = e.bias();
        for k in 0..100 {
            e.update(&biased(0.1, f64::NAN, k + 1));
        }
        // Back with a reading off by a vibration-sized 0.2 rad/s for one sample.
        e.update(&biased(0.1, 0.2, 101));
        let mut theta = 0.0;
        for k in 102..1000 {
            theta = e.update(&biased(0.1, 0.0, k)).theta;
        }
        assert!((theta - 0.1).abs() < 1e-3, "{theta}");
        assert!((e.bias() - learnt).abs() < 1e-3, "{} {learnt}", e.bias());
    }
}

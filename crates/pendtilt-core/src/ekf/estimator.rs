//! The streaming estimator around a [`StateFilter`]: time steps, start-up, missing
//! samples, encoder wrap-around and restarts. [`super::Ekf`] and [`super::Ukf`] are this
//! over the EKF and the UKF.
use super::filter::StateFilter;
use super::measurement::{Accelerometer, Encoder, Gyro};
use super::model::{Cov, PendulumProcess, State, ALPHA, BIAS, DPHI, OMEGA, PHI, THETA};
use super::settings::ModelSettings;
use crate::{Estimate, Estimator, Flags, Real, Sample};

/// Upper bound on the integration steps one sample interval is split into.
const MAX_SUBSTEPS: usize = 10_000;

/// A model-based tilt estimator (see the module documentation of [`super`]).
///
/// Per sample: predict over `dt` (split into steps of at most
/// [`ModelSettings::max_step`]), then update with the gyro, the encoder and, if enabled,
/// the accelerometer, each only if finite. The first sample with a finite phi starts the
/// filter at `theta = phi` (the pendulum at rest), `theta' = gyro`; after a gap longer
/// than [`ModelSettings::max_gap`], or if the filter ever becomes non-finite, it starts
/// again the same way.
#[derive(Debug, Clone)]
pub struct ModelBased<T: Real, F> {
    settings: ModelSettings<T>,
    model: PendulumProcess<T>,
    accel: Accelerometer<T>,
    r_phi: T,
    q_step: T,
    q: Cov<T>,
    filter: Option<F>,
    t_prev: Option<T>,
    last_theta: T,
}

impl<T: Real, F: StateFilter<T>> ModelBased<T, F> {
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
        Self {
            model: settings.process_model(),
            accel,
            r_phi: settings.sensors.encoder_variance().max(T::lit(1e-14)),
            q_step: T::zero(),
            q: Cov::<T>::zeros(),
            settings,
            filter: None,
            t_prev: None,
            last_theta: T::nan(),
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

    fn gyro_variance(&self, dt: T) -> T {
        let d = self.settings.sensors.gyro_density;
        (d * d / dt).max(T::lit(1e-14))
    }

    fn start(&mut self, s: &Sample<T>) -> Estimate<T> {
        let st = &self.settings;
        let b0 = st.sensors.gyro_bias;
        let (w0, w_var) = if s.gyro.is_finite() {
            (s.gyro, b0 * b0 + self.gyro_variance(T::lit(1e-3)))
        } else {
            (T::zero(), T::one())
        };
        let mut x = State::<T>::zeros();
        x[THETA] = s.phi;
        x[OMEGA] = w0;
        x[PHI] = s.phi;
        let mut p = Cov::<T>::zeros();
        p[(THETA, THETA)] = st.initial_angle * st.initial_angle + self.r_phi;
        p[(OMEGA, OMEGA)] = w_var;
        p[(ALPHA, ALPHA)] = T::lit(100.0);
        p[(PHI, PHI)] = self.r_phi;
        p[(DPHI, DPHI)] = T::lit(0.01);
        p[(BIAS, BIAS)] = b0 * b0 + T::lit(1e-12);
        self.filter = Some(F::start(x, p));
        self.t_prev = Some(s.t);
        self.last_theta = s.phi;
        Estimate {
            theta: s.phi,
            flags: Flags::INITIALISING,
        }
    }

    fn hold(&self, flags: Flags) -> Estimate<T> {
        Estimate {
            theta: self.last_theta,
            flags,
        }
    }
}

/// `x` wrapped into (-pi, pi].
#[inline]
fn wrap<T: Real>(x: T) -> T {
    if x.abs() > T::pi() {
        x.sin().atan2(x.cos())
    } else {
        x
    }
}

impl<T: Real, F: StateFilter<T>> Estimator<T> for ModelBased<T, F> {
    #[inline]
    fn update(&mut self, s: &Sample<T>) -> Estimate<T> {
        if !s.t.is_finite() || self.t_prev.is_some_and(|tp| s.t <= tp) {
            return self.hold(Flags::BAD_TIME_STEP);
        }
        let mut flags = Flags::empty();
        let dt = s.t - self.t_prev.unwrap_or(s.t);
        if self.filter.is_some() && dt > self.settings.max_gap {
            self.filter = None;
        }
        if self.filter.is_none() {
            if s.phi.is_finite() {
                return self.start(s);
            }
            return self.hold(Flags::INITIALISING | Flags::SAMPLE_MISSING);
        }
        let r_gyro = self.gyro_variance(dt);
        // Predict, split into steps no longer than max_step.
        let ratio = (dt / self.settings.max_step).ceil().to_f64();
        let n = if ratio.is_finite() && ratio >= 1.0 {
            (ratio as usize).min(MAX_SUBSTEPS)
        } else {
            1
        };
        let h = dt / T::lit(n as f64);
        if h != self.q_step {
            self.q = self.model.q(h);
            self.q_step = h;
        }
        let Some(filter) = self.filter.as_mut() else {
            return self.hold(Flags::INITIALISING);
        };
        let mut ok = true;
        for _ in 0..n {
            ok &= filter.predict(&self.model, h, &self.q);
        }
        self.t_prev = Some(s.t);
        // Gyro: theta' + bias.
        if s.gyro.is_finite() {
            if filter
                .update_unit(&Gyro::<T>::INDICES, s.gyro, r_gyro)
                .is_err()
            {
                flags |= Flags::MEASUREMENT_SKIPPED;
            }
        } else {
            flags |= Flags::SAMPLE_MISSING | Flags::MEASUREMENT_SKIPPED;
        }
        // Encoder: phi, taken within half a turn of the prediction.
        if s.phi.is_finite() {
            let pred = filter.state()[PHI];
            let z = pred + wrap(s.phi - pred);
            if (z - s.phi).abs() > T::lit(1e-9) {
                flags |= Flags::ENCODER_WRAPPED;
            }
            if filter
                .update_unit(&Encoder::<T>::INDICES, z, self.r_phi)
                .is_err()
            {
                flags |= Flags::MEASUREMENT_SKIPPED;
            }
        } else {
            flags |= Flags::SAMPLE_MISSING | Flags::MEASUREMENT_SKIPPED;
        }
        if self.settings.use_accel {
            if s.ax.is_finite() && s.ay.is_finite() {
                if filter.update_accel(&self.accel, [s.ax, s.ay]).is_err() {
                    flags |= Flags::MEASUREMENT_SKIPPED;
                }
            } else {
                flags |= Flags::MEASUREMENT_SKIPPED;
            }
        }
        // Keep theta within a turn (phi moves with it: only phi - theta is physical).
        let th = filter.state()[THETA];
        if th.abs() > T::pi() {
            let d = wrap(th) - th;
            let mut dx = State::<T>::zeros();
            dx[THETA] = d;
            dx[PHI] = d;
            filter.shift(&dx);
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
        let theta = filter.state()[THETA];
        self.last_theta = theta;
        Estimate { theta, flags }
    }

    fn reset(&mut self) {
        self.filter = None;
        self.t_prev = None;
        self.last_theta = T::nan();
    }
}

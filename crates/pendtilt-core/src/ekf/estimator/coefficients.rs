//! What the estimator computes from its settings once, and from the step length when it
//! changes: the process model, the accelerometer's and the encoder's noise, and the
//! process noise of one step.
use crate::ekf::measurement::Accelerometer;
use crate::ekf::model::{Cov, PendulumProcess, ProcessNoise};
use crate::ekf::settings::ModelSettings;
use crate::engine::ProcessModel;
use crate::Real;

/// The coefficients of [`super::ModelBased`] (VQF's split: settings, coefficients, state).
#[derive(Debug, Clone)]
pub(super) struct Coefficients<T: Real> {
    /// The pendulum's equations of motion.
    pub model: PendulumProcess<T>,
    /// The accelerometer as a measurement (its variance at 1 kHz).
    pub accel: Accelerometer<T>,
    /// The settings' encoder variance, which the measured noise floors.
    pub encoder_r: T,
    /// The process noise of the last step length.
    pub noise: StepNoise<T>,
}

impl<T: Real> Coefficients<T> {
    /// The coefficients of `settings`.
    pub fn new(settings: &ModelSettings<T>) -> Self {
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
            encoder_r: settings.encoder_variance().max(T::lit(1e-14)),
            noise: StepNoise {
                step: T::zero(),
                q: Cov::<T>::zeros(),
                forcing: Cov::<T>::zeros(),
            },
        }
    }
}

/// The process noise over one step, kept for the step length it was computed for.
#[derive(Debug, Clone)]
pub(super) struct StepNoise<T: Real> {
    step: T,
    q: Cov<T>,
    // The part of `q` the pendulum's forcing adds, scaled by the adapted factor.
    forcing: Cov<T>,
}

impl<T: Real> StepNoise<T> {
    /// Recomputes the noise if the step `h` changed.
    #[inline(always)]
    pub fn refresh(&mut self, model: &PendulumProcess<T>, h: T) {
        if h == self.step {
            return;
        }
        self.q = model.q(h);
        let forcing = PendulumProcess {
            params: model.params,
            noise: ProcessNoise {
                jerk: T::zero(),
                pendulum: model.noise.pendulum,
                bias: T::zero(),
            },
        };
        self.forcing = forcing.q(h);
        self.step = h;
    }

    /// The cached noise.
    #[inline(always)]
    pub fn plain(&self) -> &Cov<T> {
        &self.q
    }

    /// The cached noise with the forcing at `factor` times the settings'.
    #[inline(always)]
    pub fn scaled(&self, factor: T) -> Cov<T> {
        self.q + self.forcing * (factor - T::one())
    }
}

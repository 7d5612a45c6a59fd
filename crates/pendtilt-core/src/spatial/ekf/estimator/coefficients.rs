//! What the estimator computes from its settings once, and from the step length when it
//! changes: the process model, the measurement noises, the lever arm from O and the
//! process noise of one step.
use super::covariance::add_rate_noise;
use crate::engine::{Cov, ProcessModel};
use crate::filters::diff::{Response, SmoothingDifferentiator};
use crate::spatial::ekf::measurement::{Encoders, Speed};
use crate::spatial::ekf::process::CardanProcess;
use crate::spatial::ekf::settings::Settings;
use crate::spatial::ekf::state::{A, ACC, B, N, P, R, V};
use crate::Real;
use nalgebra::Vector3;

/// The coefficients of [`super::ModelBased`] (VQF's split: settings, coefficients, state).
#[derive(Debug, Clone)]
pub(super) struct Coefficients<T: Real> {
    /// The gyro and the pendulum's equations of motion.
    pub model: CardanProcess<T>,
    /// The encoders as a measurement (their variance).
    pub encoders: Encoders<T>,
    /// The `speed` column as a measurement (its variance).
    pub speed: Speed<T>,
    /// The delay of the gyro's differentiator, by which its second derivative leads the
    /// first (`Settings::angular_accel_lead`; 0 without the lead).
    pub accel_lead: T,
    /// The accelerometer from O, `accel_at - speed_at` \[m\].
    pub accel_from_centre: Vector3<T>,
    /// The process noise of the last step length.
    pub noise: StepNoise<T>,
}

impl<T: Real> Coefficients<T> {
    /// The coefficients of `settings`, with `gyro_diff` the differentiator of the gyro
    /// the estimator runs (its delay sets the lead).
    pub fn new(settings: &Settings<T>, gyro_diff: &SmoothingDifferentiator<T, 3>) -> Self {
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
            speed: Speed {
                r: (settings.speed.noise * settings.speed.noise).max(T::lit(1e-12)),
            },
            accel_lead,
            accel_from_centre: settings.mounting.from_centre(settings.mounting.accel_at),
            noise: StepNoise::new(),
        }
    }
}

/// The process noise over one step, kept for the step length and the travel it was
/// computed for.
#[derive(Debug, Clone)]
pub(super) struct StepNoise<T: Real> {
    step: T,
    // For a travelling vehicle (with the jerk's noise).
    travelling: bool,
    q: Cov<T, N>,
    // The part of `q` that the pendulum's forcing adds (scaled by the forcing factor), per
    // joint: the angle's, the angle-rate and the rate's variance.
    forcing: [[T; 3]; 2],
}

impl<T: Real> StepNoise<T> {
    fn new() -> Self {
        Self {
            step: T::zero(),
            travelling: false,
            q: Cov::<T, N>::zeros(),
            forcing: [[T::zero(); 3]; 2],
        }
    }

    /// Recomputes the noise if the step `h` or the travel changed.
    pub fn refresh(&mut self, model: &CardanProcess<T>, h: T, travelling: bool) {
        if h == self.step && self.travelling == travelling {
            return;
        }
        self.q = model.q(h);
        let h2 = h * h;
        self.forcing = model.noise.joints.map(|d| {
            let v = d * d;
            [v * h2 * h / T::lit(3.0), v * h2 / T::lit(2.0), v * h]
        });
        if !travelling {
            // O's speed and rate held at zero: no jerk.
            for k in [V, ACC] {
                for i in 0..N {
                    self.q[(k, i)] = T::zero();
                    self.q[(i, k)] = T::zero();
                }
            }
        }
        self.step = h;
        self.travelling = travelling;
    }

    /// The cached noise with the forcing at `forcing` times its floor and `share[k]` more
    /// variance of the rotation about body axis `k` (a held or clipped gyro).
    pub fn with(&self, forcing: T, share: &Vector3<T>) -> Cov<T, N> {
        let mut q = self.q;
        let more = forcing - T::one();
        for ((angle, rate), f) in [(A, P), (B, R)].into_iter().zip(self.forcing) {
            q[(angle, angle)] += f[0] * more;
            q[(angle, rate)] += f[1] * more;
            q[(rate, angle)] += f[1] * more;
            q[(rate, rate)] += f[2] * more;
        }
        add_rate_noise(q, share)
    }

    /// The cached noise.
    pub fn plain(&self) -> &Cov<T, N> {
        &self.q
    }
}

//! What the estimator carries from one sample to the next: the filter, the clock, the
//! gaps, the gates and the adaptation.
use super::encoder_noise::EncoderNoise;
use crate::adaptation::ForcingAdaptation;
use crate::ekf::measurement::Encoder;
use crate::{Real, StepClock};

/// The state of [`super::ModelBased`] (VQF's split: settings, coefficients, state).
#[derive(Debug, Clone)]
pub(super) struct RunState<T: Real, F> {
    /// The Gaussian filter, once started.
    pub filter: Option<F>,
    pub clock: StepClock<T>,
    /// The encoder as a measurement, its variance floored by the measured noise.
    pub encoder: Encoder<T>,
    pub encoder_noise: EncoderNoise<T>,
    /// The factor on the pendulum's forcing variance.
    pub forcing: ForcingAdaptation<T>,
    /// Time since the filter (re)started \[s\].
    pub since_start: T,
    /// Time since the last encoder reading \[s\].
    pub since_reading: T,
    /// Time since the last row with an encoder reading.
    pub since_phi: Option<T>,
    /// Time since the last row with a gyro reading.
    pub since_gyro: Option<T>,
    /// The gyro bias and its variance kept through a restart after a gap.
    pub kept_bias: Option<(T, T)>,
    /// theta' low-passed (the body's slow rate without its vibration), what the filter
    /// coasts on while the gyro is missing.
    pub slow_rate: T,
    /// The last estimate, held while none is made.
    pub last_theta: T,
    pub runs: Runs,
}

/// Where one measurement stands with the innovation gate.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Lock {
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
pub(super) struct Runs {
    pub phi: Lock,
    pub gyro: Lock,
    pub accel: Lock,
}

impl<T: Real, F> RunState<T, F> {
    /// The state before the first sample, the encoder's variance at `encoder_r`.
    pub fn new(encoder_r: T) -> Self {
        Self {
            filter: None,
            clock: StepClock::new(),
            encoder: Encoder { r: encoder_r },
            encoder_noise: EncoderNoise::new(),
            forcing: ForcingAdaptation::new(),
            since_start: T::zero(),
            since_reading: T::zero(),
            since_phi: None,
            since_gyro: None,
            kept_bias: None,
            slow_rate: T::zero(),
            last_theta: T::nan(),
            runs: Runs::default(),
        }
    }

    /// Forgets everything ([`crate::Estimator::reset`]), the encoder's variance back at
    /// `encoder_r`.
    pub fn reset(&mut self, encoder_r: T) {
        self.filter = None;
        self.kept_bias = None;
        self.clock.restart();
        self.since_phi = None;
        self.since_gyro = None;
        self.last_theta = T::nan();
        self.runs = Runs::default();
        self.forcing.reset();
        self.encoder_noise = EncoderNoise::new();
        self.encoder.r = encoder_r;
    }
}

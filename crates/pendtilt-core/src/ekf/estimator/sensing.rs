//! The sensors in turn through their gates ([`Lock`]), and what the encoder's readings
//! teach: its measured noise and the forcing's adaptation.
use super::run_state::Lock;
use super::ModelBased;
use crate::adaptation::SETTLE_SECONDS;
use crate::ekf::measurement::Gyro;
use crate::ekf::model::{State, N, PHI};
use crate::ekf::sensor::{wrap, Sensor};
use crate::ekf::settings::ModelSettings;
use crate::engine::{Gate, GaussianFilter, Rejected};
use crate::{Flags, Real, Sample};

/// The encoder's reading on one sample, as the adaptation takes it.
#[derive(Debug, Clone, Copy)]
pub(super) struct EncoderStep<T> {
    /// The normalised innovation squared before the update.
    nis: T,
    /// Whether the gate tested it (not held open, not re-acquiring).
    gated: bool,
    /// Whether it was applied.
    applied: bool,
}

impl<T: Real, F: GaussianFilter<T, State<T>, N>> ModelBased<T, F> {
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

    /// The sensors in this order: the gyro (its variance `r_gyro` over the step), the
    /// encoder and, if enabled, the accelerometer; a new sensor is one more line.
    #[inline(always)]
    pub(super) fn sense_all(&mut self, s: &Sample<T>, r_gyro: T) -> (Flags, EncoderStep<T>) {
        let st = &self.settings;
        let run = &mut self.state;
        let mut flags = Flags::empty();
        let Some(filter) = run.filter.as_mut() else {
            return (flags, EncoderStep::default());
        };
        let gyro = Gyro {
            r: r_gyro,
            gate_floor: st.gyro_vibration * st.gyro_vibration,
        };
        let runs = &mut run.runs;
        flags |= Self::sense(filter, st, &gyro, s, &mut runs.gyro);
        // The encoder's normalised innovation before its update, for the adaptation, and
        // whether the gate tests it (not held open, not re-acquiring).
        let gated = matches!(runs.phi, Lock::Tracking(run) if run < st.reacquire_after.max(1));
        let nis = {
            let (x, p) = (filter.state(), filter.covariance());
            let y = wrap(s.phi - x[PHI]);
            y * y / (p[(PHI, PHI)] + run.encoder.r)
        };
        let enc = Self::sense(filter, st, &run.encoder, s, &mut runs.phi);
        flags |= enc;
        if st.use_accel {
            flags |= Self::sense(filter, st, &self.coeffs.accel, s, &mut runs.accel);
        }
        let applied = !enc.contains(Flags::MEASUREMENT_SKIPPED);
        (
            flags,
            EncoderStep {
                nis,
                gated,
                applied,
            },
        )
    }

    /// What sample `s` (step `dt`) teaches with the adaptation on: the encoder's noise
    /// measured on its readings floors its variance, and an encoder reading the gate
    /// tested and applied steps the forcing's adaptation, but none within
    /// [`SETTLE_SECONDS`] of a start nor on a sample without the gyro.
    #[inline(always)]
    pub(super) fn learn(&mut self, s: &Sample<T>, dt: T, enc: EncoderStep<T>) {
        let st = &self.settings;
        let run = &mut self.state;
        run.since_start += dt;
        run.since_reading += dt;
        if s.phi.is_finite() && st.adaptation.enabled {
            let since = core::mem::replace(&mut run.since_reading, T::zero());
            let floor = self.coeffs.encoder_r;
            run.encoder_noise.push(s.phi, dt, floor);
            if let Some(v) = run.encoder_noise.variance() {
                run.encoder.r = floor.max(v);
            }
            let settled = run.since_start >= T::lit(SETTLE_SECONDS);
            if enc.applied && enc.gated && settled && s.gyro.is_finite() {
                run.forcing.step(&st.adaptation, enc.nis, since);
            }
        } else if !s.phi.is_finite() {
            run.encoder_noise.interrupt();
        }
    }
}

impl<T: Real> Default for EncoderStep<T> {
    fn default() -> Self {
        Self {
            nis: T::zero(),
            gated: false,
            applied: false,
        }
    }
}

//! The inclination error of MODEL.md 7.9 accumulated over a log: RMS, max and mean over
//! `t >= t0 + score_from`; a row without an estimate (not finite: flagged, e.g. a sensor
//! missing for longer than the restart gap) is counted as missing, not scored.
use pendtilt_core::spatial::attitude::inclination_error;

/// Running inclination-error statistics of one estimator \[rad\].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Inclination {
    sum_sq: f64,
    sum: f64,
    max: f64,
    n: u64,
    missing: u64,
}

impl Inclination {
    /// Adds one sample: the estimate against the truth (both roll, pitch \[rad\]). A row
    /// without truth is not scored; one without an estimate is counted as missing.
    pub fn add(&mut self, est: (f64, f64), truth: (f64, f64)) {
        if !(truth.0.is_finite() && truth.1.is_finite()) {
            return;
        }
        let e = inclination_error(est.0, est.1, truth.0, truth.1);
        if !e.is_finite() {
            self.missing += 1;
            return;
        }
        self.sum_sq += e * e;
        self.sum += e;
        self.max = self.max.max(e);
        self.n += 1;
    }

    /// Number of scored samples.
    pub fn count(&self) -> u64 {
        self.n
    }

    /// Number of rows with the truth but no estimate.
    pub fn missing(&self) -> u64 {
        self.missing
    }

    /// RMS \[rad\] (NaN when nothing was scored).
    pub fn rms(&self) -> f64 {
        (self.sum_sq / self.n as f64).sqrt()
    }

    /// Largest \[rad\] (NaN when nothing was scored).
    pub fn max(&self) -> f64 {
        if self.n == 0 {
            f64::NAN
        } else {
            self.max
        }
    }

    /// Mean \[rad\] (NaN when nothing was scored).
    pub fn mean(&self) -> f64 {
        self.sum / self.n as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pure_pitch_errors_score_as_themselves() {
        let mut s = Inclination::default();
        s.add((0.0, 0.01), (0.0, 0.0));
        s.add((0.0, -0.03), (0.0, 0.0));
        s.add((0.0, 0.5), (f64::NAN, 0.0));
        assert_eq!(s.count(), 2);
        assert!((s.rms() - (0.0005f64).sqrt()).abs() < 1e-12);
        assert!((s.max() - 0.03).abs() < 1e-12 && (s.mean() - 0.02).abs() < 1e-12);
        s.add((f64::NAN, 0.0), (0.0, 0.0));
        assert_eq!((s.count(), s.missing()), (2, 1));
        assert!((s.rms() - (0.0005f64).sqrt()).abs() < 1e-12);
    }
}

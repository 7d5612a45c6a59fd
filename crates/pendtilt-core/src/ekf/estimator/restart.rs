//! Starts and gaps: the start at the pendulum's angle, the gaps that are not bridged (the
//! gyro bias kept over them), and the gyro's gaps, loosened at their start and unhooked
//! at their end.
use super::run_state::Runs;
use super::{ModelBased, MISSING_RATE_SIGMAS};
use crate::ekf::model::{Cov, State, ALPHA, BIAS, DPHI, N, OMEGA, PHI, THETA};
use crate::engine::GaussianFilter;
use crate::{Estimate, Flags, Real, Sample};

impl<T: Real, F: GaussianFilter<T, State<T>, N>> ModelBased<T, F> {
    /// The start at sample `s`: theta = phi (the pendulum at rest), theta' = gyro, the
    /// gyro bias as kept over a gap or unknown.
    fn start(&mut self, s: &Sample<T>) -> Estimate<T> {
        let st = &self.settings;
        let run = &mut self.state;
        let b0 = st.sensors.gyro_bias;
        let kept = run.kept_bias.is_some();
        let (bias, bias_var) = run
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
        let r = self.state.encoder.r;
        let mut p = Cov::<T>::zeros();
        p[(THETA, THETA)] = st.initial_angle * st.initial_angle + r;
        p[(OMEGA, OMEGA)] = w_var;
        p[(ALPHA, ALPHA)] = T::lit(100.0);
        p[(PHI, PHI)] = r;
        p[(DPHI, DPHI)] = T::lit(0.01);
        p[(BIAS, BIAS)] = bias_var;
        if kept && s.gyro.is_finite() {
            // theta' = gyro - bias: their errors are opposite.
            p[(OMEGA, BIAS)] = -bias_var;
            p[(BIAS, OMEGA)] = -bias_var;
        }
        let run = &mut self.state;
        run.filter = Some(F::start(x, p));
        run.slow_rate = x[OMEGA];
        run.runs = Runs::default();
        run.forcing.reset();
        run.since_start = T::zero();
        run.since_reading = T::zero();
        run.clock.accept();
        run.last_theta = s.phi;
        Estimate {
            theta: s.phi,
            flags: Flags::INITIALISING,
        }
    }

    /// Drops the filter for a restart, keeping the gyro bias and its variance (a gap
    /// cannot change the bias beyond its random walk, which [`Self::start`] adds).
    pub(super) fn drop_keeping_bias(&mut self) {
        if let Some(f) = self.state.filter.take() {
            let (b, v) = (f.state()[BIAS], f.covariance()[(BIAS, BIAS)]);
            if b.is_finite() && v.is_finite() {
                self.state.kept_bias = Some((b, v));
            }
        }
    }

    /// On the first sample without the gyro. The filter tracks the body's angular
    /// vibration in theta' and theta'' (the gyro's noise is far below it): coasting on them
    /// would carry one sample of the vibration through the gap (3 deg after 0.1 s on the
    /// scooter ride). theta' goes to its low-passed value ([`super::SLOW_RATE_TAU`]), theta''
    /// to 0, both become uncertain ([`MISSING_RATE_SIGMAS`]; theta'' as at the start) and
    /// uncorrelated with the other states. phi' moves with theta' (the pendulum's own
    /// rate phi' - theta' is kept).
    fn loosen(&mut self) {
        let Some(f) = self.state.filter.as_ref() else {
            return;
        };
        let mut x = *f.state();
        let mut p = *f.covariance();
        let slow_rate = self.state.slow_rate;
        x[DPHI] = x[DPHI] + slow_rate - x[OMEGA];
        x[OMEGA] = slow_rate;
        x[ALPHA] = T::zero();
        split(&mut p, |i| i == OMEGA || i == ALPHA);
        let v = self.settings.gyro_vibration * T::lit(MISSING_RATE_SIGMAS);
        p[(OMEGA, OMEGA)] += v * v;
        p[(ALPHA, ALPHA)] += T::lit(100.0);
        self.state.filter = Some(F::start(x, p));
    }

    /// On the first gyro reading after a gap: theta' is set to it (less the bias), phi'
    /// moves with it, and the fast states (theta', theta'', phi, phi') become uncorrelated
    /// with theta and the bias. What the rate was off by at the end of the gap is mostly
    /// vibration, not a rate error that lasted the whole gap: through the covariance the
    /// gap built up, the reading would have moved theta by several degrees and the bias
    /// with it (which then took over 10 s to decay). The encoder then corrects theta.
    fn unhook(&mut self, gyro: T) {
        let Some(f) = self.state.filter.as_ref() else {
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
        self.state.filter = Some(F::start(x, p));
    }

    /// The gaps before sample `s` (step `dt`): a gap in the rows, or in the encoder's
    /// readings while the gyro was missing too, longer than
    /// [`crate::ekf::ModelSettings::max_gap`] is not bridged (the prediction would
    /// extrapolate the last estimated tilt acceleration, vibration included, for the
    /// whole gap): the filter restarts, keeping its bias. A gyro gap starts with `loosen`
    /// and ends with `unhook`. Returns the estimate when the filter (re)starts on this
    /// sample or is waiting for a phi to start on.
    pub(super) fn gaps(&mut self, s: &Sample<T>, dt: T) -> Option<Estimate<T>> {
        let run = &mut self.state;
        let gyro_was_there = run.since_gyro == Some(T::zero());
        for e in [run.since_phi.as_mut(), run.since_gyro.as_mut()]
            .into_iter()
            .flatten()
        {
            *e += s.dt;
        }
        let max_gap = self.settings.max_gap;
        // With the gyro, theta was followed through the encoder's gap.
        let gyro_gap = run.since_gyro.is_none_or(|e| e > max_gap);
        let coasted = s.phi.is_finite() && run.since_phi.is_some_and(|e| e > max_gap) && gyro_gap;
        if run.filter.is_some() && (dt > max_gap || coasted) {
            self.drop_keeping_bias();
        }
        let run = &mut self.state;
        if s.phi.is_finite() {
            run.since_phi = Some(T::zero());
        }
        if s.gyro.is_finite() {
            run.since_gyro = Some(T::zero());
        }
        if run.filter.is_none() {
            return Some(self.restart(s));
        }
        if !s.gyro.is_finite() && gyro_was_there {
            self.loosen();
        } else if s.gyro.is_finite() && !gyro_was_there {
            self.unhook(s.gyro);
        }
        None
    }

    /// A start on sample `s` once it has a phi, the kept bias's variance grown by its
    /// walk over the gap.
    fn restart(&mut self, s: &Sample<T>) -> Estimate<T> {
        if !s.phi.is_finite() {
            return self.hold(Flags::INITIALISING | Flags::SAMPLE_MISSING);
        }
        if let Some((_, v)) = self.state.kept_bias.as_mut() {
            // The bias walked over the gap (a jump in the rows; empty rows were
            // predicted through).
            let gap = if s.dt.is_finite() {
                s.dt.max(T::zero())
            } else {
                T::zero()
            };
            *v += self.settings.process.bias * gap;
        }
        self.start(s)
    }

    /// The last estimate with `flags`.
    pub(super) fn hold(&self, flags: Flags) -> Estimate<T> {
        Estimate {
            theta: self.state.last_theta,
            flags,
        }
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

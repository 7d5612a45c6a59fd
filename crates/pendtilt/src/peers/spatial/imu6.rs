//! [`Imu6`]: any [`ImuFilter`] as a
//! [`SpatialEstimator`](pendtilt_core::spatial::SpatialEstimator), with what every 3-D peer
//! shares (the start, restarts, gaps, clips; see [`super`]).
use pendtilt_core::estimators::input_hold::GapBridge;
use pendtilt_core::spatial::attitude::roll_pitch_from_up;
use pendtilt_core::spatial::{Attitude, SpatialSample};
use pendtilt_core::{Estimator, Flags, StepClock};

use super::{ImuFilter, CLIP_RESTART_AFTER};
use crate::peers::ahrs_planar::MISSING_RATE_TAU;
use crate::peers::steady::SteadyFit;

/// How a filter is built on the first usable sample: from its roll, pitch, step and
/// parameters.
pub type MakeFilter<F> = fn(roll: f64, pitch: f64, dt: f64, params: &<F as ImuFilter>::Params) -> F;

/// An [`ImuFilter`] as a [`SpatialEstimator`](pendtilt_core::spatial::SpatialEstimator) (see
/// the module documentation).
#[derive(Debug, Clone)]
pub struct Imu6<F: ImuFilter> {
    make: MakeFilter<F>,
    gains: F::Params,
    filter: Option<F>,
    clock: StepClock<f64>,
    mean_rate: Option<[f64; 3]>,
    mean_accel: Option<[f64; 3]>,
    last: Attitude<f64>,
    gyro_full_scale: Option<f64>,
    // The filter that ran before a restart ([`Estimator::resume`]), for `keep_from`.
    kept: Option<F>,
    // After a restart, the accelerometer's mean direction so far (body axes, carried by
    // the gyro) and how long it has been averaged \[s\].
    average: Option<([f64; 3], f64)>,
    // For a filter built with the step: the first usable sample's gyro and accelerometer
    // readings, held until the next gives the step.
    held: Option<([f64; 3], [f64; 3])>,
    // The filter's gain \[1/s\] for `with_restart_offset` (None: off).
    offset_gain: Option<f64>,
    // Its steady `a_hat x up_est` (body axes) as last fitted, kept over a restart.
    offset: Option<[f64; 3]>,
    fit: SteadyFit<3>,
    // How long the gyro has read at a clip so far \[s\].
    clipped_for: f64,
    // Per gyro axis: the bridge over its last gap.
    bridges: [GapBridge<f64>; 3],
    // The gain \[1/s\] for `with_gap_bridge` (None: off).
    bridge_gain: Option<f64>,
}

impl<F: ImuFilter> Imu6<F> {
    /// [`Estimator::update`] with sample `s`, whose gyro reads at a clip found in the log
    /// when `clipped` (a reading at the rig's full scale is one too). The first reading
    /// after a clip of [`CLIP_RESTART_AFTER`] or longer restarts the filter
    /// ([`Estimator::resume`], keeping what it keeps over a gap): the clip hid the rotation
    /// beyond it, without bound, and the filter would forget the tilt error it left only
    /// at its accelerometer gain.
    pub fn update_clipped(&mut self, s: &SpatialSample<f64>, clipped: bool) -> Attitude<f64> {
        let at_scale = self
            .gyro_full_scale
            .is_some_and(|fs| s.gyro.iter().any(|g| g.abs() >= fs));
        if clipped || at_scale {
            if s.dt.is_finite() && s.dt > 0.0 {
                self.clipped_for += s.dt;
            }
        } else if self.clipped_for > 0.0 {
            if self.clipped_for >= CLIP_RESTART_AFTER && self.filter.is_some() {
                Estimator::resume(self);
            }
            self.clipped_for = 0.0;
        }
        self.advance(s, at_scale)
    }

    /// One step of the wrapper and its filter; `at_scale`: a gyro axis reads at the rig's
    /// full scale (flagged saturated).
    pub(super) fn advance(&mut self, s: &SpatialSample<f64>, at_scale: bool) -> Attitude<f64> {
        let step = match self.clock.offer(s.dt) {
            Ok(step) => step,
            Err(flags) => return self.hold(flags),
        };
        let accel = usable(&s.accel).then_some(s.accel);
        let gyro_ok = s.gyro.iter().all(|x| x.is_finite());
        let mut flags = Flags::empty();
        let dt = match step {
            Some(dt) if self.filter.is_some() => dt,
            Some(dt) if self.held.is_some() => {
                self.start_held(dt);
                dt
            }
            _ => return self.start(s, step, accel, gyro_ok),
        };
        if at_scale {
            flags |= Flags::SATURATED;
        }
        // Axis by axis: a missing (or clipped, read as missing) axis takes its recent mean,
        // the others stay as read.
        let k = (dt / MISSING_RATE_TAU).min(1.0);
        let m = self.mean_rate.unwrap_or(s.gyro);
        let m: [f64; 3] = core::array::from_fn(|i| if m[i].is_finite() { m[i] } else { 0.0 });
        let gyro: [f64; 3] = core::array::from_fn(|i| {
            if s.gyro[i].is_finite() {
                s.gyro[i]
            } else {
                m[i]
            }
        });
        self.mean_rate = Some(core::array::from_fn(|i| m[i] + k * (gyro[i] - m[i])));
        // The angle each axis' hold integrated wrong through its last gap, once the readings
        // after it tell: a small rotation vector in body axes (the gap is short), turned in
        // with this step, less what the filter's gain forgot of it since.
        let turn: [f64; 3] = core::array::from_fn(|i| {
            self.bridges[i].offer(s.gyro[i], m[i], Some(dt));
            let c = self.bridges[i].take(self.bridge_gain.unwrap_or(0.0));
            if self.bridge_gain.is_some() && c.is_finite() {
                c
            } else {
                0.0
            }
        });
        let gyro: [f64; 3] = core::array::from_fn(|i| gyro[i] + turn[i] / dt);
        if !gyro_ok {
            flags |= Flags::SAMPLE_MISSING;
        }
        if accel.is_none() {
            flags |= Flags::SAMPLE_MISSING;
        }
        let accel = self.bridge_accel(&s.accel, accel, dt);
        self.clock.accept();
        let Some(f) = self.filter.as_mut() else {
            return self.hold(flags);
        };
        if !f.step(gyro, accel, dt) && accel.is_some() {
            flags |= Flags::MEASUREMENT_SKIPPED;
        }
        if let (Some(gain), Some(a)) = (self.offset_gain, accel) {
            let e = cross(a.map(|x| x / norm(a)), f.up());
            self.fit.add(e, dt, gain);
            if let Some(c) = self.fit.steady(gain) {
                self.offset = Some(c);
            }
        }
        let (roll, pitch) = roll_pitch_from_up(f.up());
        if roll.is_finite() && pitch.is_finite() {
            self.last = Attitude { roll, pitch, flags };
            self.last
        } else {
            // Never seen with finite input; start again rather than output NaN forever.
            self.filter = None;
            self.hold(flags | Flags::INITIALISING)
        }
    }

    /// The sample `s` while the filter has not started (`step`: the clock's step to it,
    /// `None` for the first sample): starts it on a usable accelerometer reading (after a
    /// restart, once the accelerometer has been averaged for the filter's
    /// [`ImuFilter::restart_average`]); a filter built with the step
    /// ([`ImuFilter::BUILT_WITH_STEP`]) has its first sample held instead.
    fn start(
        &mut self,
        s: &SpatialSample<f64>,
        step: Option<f64>,
        accel: Option<[f64; 3]>,
        gyro_ok: bool,
    ) -> Attitude<f64> {
        let Some(a) = accel else {
            return self.hold(Flags::INITIALISING | Flags::SAMPLE_MISSING);
        };
        let window = self.kept.as_ref().map_or(0.0, |f| f.restart_average());
        let (roll, pitch) = if window > 0.0 {
            let done = self.average(a, gyro_ok.then_some(s.gyro), step.unwrap_or(0.0), window);
            let u = self.average.map_or(a, |m| m.0);
            if !done {
                self.clock.accept();
                let (roll, pitch) = roll_pitch_from_up(u);
                self.last = Attitude {
                    roll,
                    pitch,
                    flags: Flags::INITIALISING,
                };
                return self.last;
            }
            roll_pitch_from_up(self.offset.map_or(u, |e| steady(u, e)))
        } else {
            roll_pitch_from_up(a)
        };
        match step {
            None if F::BUILT_WITH_STEP => self.held = Some((s.gyro, a)),
            // The step only seeds the period of a filter that takes each sample's own.
            _ => self.build(roll, pitch, step.unwrap_or(1e-3)),
        }
        self.average = None;
        self.mean_rate = gyro_ok.then_some(s.gyro);
        for (b, g) in self.bridges.iter_mut().zip(s.gyro) {
            b.offer(g, 0.0, None);
        }
        self.clock.accept();
        self.last = Attitude {
            roll,
            pitch,
            flags: Flags::INITIALISING,
        };
        self.last
    }

    /// Builds the filter for a step of `dt` \[s\] at `roll` and `pitch`, with what it keeps
    /// from the filter before a restart.
    fn build(&mut self, roll: f64, pitch: f64, dt: f64) {
        let mut f = (self.make)(roll, pitch, dt, &self.gains);
        if let Some(old) = self.kept.take() {
            f.keep_from(&old);
        }
        self.filter = Some(f);
    }

    /// Builds a filter of [`ImuFilter::BUILT_WITH_STEP`] for `dt`, the step to the sample
    /// after the held one, and feeds it the held sample (at the same step, as the filter
    /// takes a log of constant step; a held gyro reading with a missing axis is left out,
    /// there being no mean to bridge it with yet).
    fn start_held(&mut self, dt: f64) {
        let Some((gyro, accel)) = self.held.take() else {
            return;
        };
        let (roll, pitch) = roll_pitch_from_up(accel);
        self.build(roll, pitch, dt);
        if let Some(f) = self.filter.as_mut() {
            if gyro.iter().all(|g| g.is_finite()) {
                f.step(gyro, Some(accel), dt);
            }
        }
    }

    /// A wrapper that builds its filter with `make(roll, pitch, dt, gains)`.
    pub fn new(make: MakeFilter<F>, gains: F::Params) -> Self {
        Self {
            make,
            gains,
            filter: None,
            clock: StepClock::new(),
            mean_rate: None,
            mean_accel: None,
            last: Attitude::unknown(),
            gyro_full_scale: None,
            kept: None,
            average: None,
            held: None,
            offset_gain: None,
            offset: None,
            fit: SteadyFit::default(),
            clipped_for: 0.0,
            bridges: [GapBridge::new(); 3],
            bridge_gain: None,
        }
    }

    /// The same wrapper correcting the attitude a gap in the gyro held wrong once the gyro
    /// is back (the core's [`GapBridge`], axis by axis: the angle turned through the gap
    /// fitted to the readings on both sides), the correction handed to the
    /// filter as a turn of the one step where [`BRIDGE_WINDOW`] of readings after the gap
    /// have come, less what the filter forgot of the error since at `gain` \[1/s\] (the
    /// rate at which it forgets a tilt error). A `gain` that is negative or not finite
    /// turns it off.
    ///
    /// [`BRIDGE_WINDOW`]: pendtilt_core::estimators::input_hold::BRIDGE_WINDOW
    pub fn with_gap_bridge(mut self, gain: f64) -> Self {
        self.bridge_gain = (gain >= 0.0 && gain.is_finite()).then_some(gain);
        self
    }

    /// The same wrapper restarting its filter (after a long gap, [`Estimator::resume`]) in
    /// its own steady state relative to the accelerometer: a filter with a proportional
    /// gain only (Mahony with ki = 0, `gain` its kp \[1/s\]) carries a steady tilt offset,
    /// the gyro's bias over its gain (1.3 deg on the scooter3d ride), which a gap cannot
    /// change and which it takes several time constants to build again from the
    /// accelerometer's mean direction `u`. The wrapper fits the steady state of the
    /// filter's disagreement with the accelerometer, `e = a_hat x up_est`, under its start
    /// transient (`e(t) = c + A exp(-gain t)`, least squares, [`SteadyFit`])
    /// and restarts at `normalize(u + c x u)`. A first start is unchanged. A `gain` that
    /// is not positive turns it off.
    pub fn with_restart_offset(mut self, gain: f64) -> Self {
        self.offset_gain = (gain > 0.0 && gain.is_finite()).then_some(gain);
        self
    }

    /// The same wrapper flagging [`Flags::SATURATED`] on a gyro reading at or beyond
    /// `full_scale` \[rad/s\] on any axis (`None`, or a bound that is not positive: no
    /// check).
    pub fn with_gyro_full_scale(mut self, full_scale: Option<f64>) -> Self {
        self.gyro_full_scale = full_scale.filter(|f| *f > 0.0);
        self
    }

    /// The gains (or settings) it was built with.
    pub fn gains(&self) -> F::Params {
        self.gains
    }

    fn hold(&self, flags: Flags) -> Attitude<f64> {
        Attitude { flags, ..self.last }
    }

    /// The accelerometer reading the filter gets: `read` when usable; else, for a filter
    /// that asks for it ([`ImuFilter::bridges_accel`]) and a reading with some axes left,
    /// the missing axes from their recent mean ([`MISSING_RATE_TAU`]), the others as read
    /// (a whole reading missing is still skipped: held over a long gap the mean would pin
    /// the filter to a stale body-frame direction).
    fn bridge_accel(
        &mut self,
        raw: &[f64; 3],
        read: Option<[f64; 3]>,
        dt: f64,
    ) -> Option<[f64; 3]> {
        let bridges = self.filter.as_ref().is_some_and(|f| f.bridges_accel());
        if !bridges {
            return read;
        }
        let a = match (read, self.mean_accel) {
            (Some(a), _) => a,
            (None, Some(m)) if raw.iter().any(|x| x.is_finite()) => {
                core::array::from_fn(|i| if raw[i].is_finite() { raw[i] } else { m[i] })
            }
            _ => return None,
        };
        let k = (dt / MISSING_RATE_TAU).min(1.0);
        let m = self.mean_accel.unwrap_or(a);
        self.mean_accel = Some(core::array::from_fn(|i| m[i] + k * (a[i] - m[i])));
        usable(&a).then_some(a)
    }

    /// After a restart: one sample into the mean accelerometer direction (the old mean
    /// turned by the gyro over `dt`, then `a`'s direction averaged in, as the filters use
    /// it: the mean of the raw vector measured worse, Mahony 10.7 s instead of 8.5 s back
    /// after the 10 s gap of tests/faults3d/); `true` once it has been averaged for the
    /// filter's [`ImuFilter::restart_average`].
    fn average(&mut self, a: [f64; 3], gyro: Option<[f64; 3]>, dt: f64, window: f64) -> bool {
        let n = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
        let a = a.map(|x| x / n);
        let (mut u, t) = self.average.unwrap_or((a, 0.0));
        if let Some(w) = gyro {
            // A world vector seen from the body turns by -w: u' = u x w.
            let c = [
                u[1] * w[2] - u[2] * w[1],
                u[2] * w[0] - u[0] * w[2],
                u[0] * w[1] - u[1] * w[0],
            ];
            u = core::array::from_fn(|i| u[i] + c[i] * dt);
        }
        let t = t + dt;
        let k = if t > 0.0 { dt / t } else { 1.0 };
        u = core::array::from_fn(|i| u[i] + k * (a[i] - u[i]));
        self.average = Some((u, t));
        t >= window
    }
}

pub(super) fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

pub(super) fn norm(a: [f64; 3]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

/// The up direction at which a filter whose steady disagreement with the accelerometer is
/// `e = a_hat x up_est` stands when the accelerometer reads `u`: `up = u + e x u` (to first
/// order, `e x (a_hat x up) = up - a_hat (a_hat . up)` for unit vectors), normalised.
fn steady(u: [f64; 3], e: [f64; 3]) -> [f64; 3] {
    let d = cross(e, u);
    let v: [f64; 3] = core::array::from_fn(|i| u[i] + d[i]);
    let n = norm(v);
    if n > 0.0 && n.is_finite() {
        v.map(|x| x / n)
    } else {
        u
    }
}

fn usable(v: &[f64; 3]) -> bool {
    v.iter().all(|x| x.is_finite()) && v.iter().any(|x| *x != 0.0)
}

impl<F: ImuFilter> Estimator for Imu6<F> {
    type Input = SpatialSample<f64>;
    type Output = Attitude<f64>;

    /// [`Self::update_clipped`] with no clip found in the log.
    fn update(&mut self, s: &SpatialSample<f64>) -> Attitude<f64> {
        self.update_clipped(s, false)
    }

    fn reset(&mut self) {
        *self = Self {
            offset_gain: self.offset_gain,
            bridge_gain: self.bridge_gain,
            ..Self::new(self.make, self.gains).with_gyro_full_scale(self.gyro_full_scale)
        };
    }

    /// Starts again on the next usable reading, keeping what a gap cannot change
    /// ([`ImuFilter::keep_from`]), after averaging the accelerometer for
    /// [`ImuFilter::restart_average`].
    fn resume(&mut self) {
        let old = self.filter.take().or(self.kept.take());
        let offset = self.offset;
        self.reset();
        self.kept = old;
        self.offset = offset;
    }
}

//! An inclination reference from the gyro and the accelerometer alone, after VQF's 6D core
//! (Laidig and Seel, *VQF: Highly accurate IMU orientation estimation with bias estimation
//! and magnetic disturbance rejection*, Information Fusion 91, 2023, section 3.2): the gyro
//! is integrated into a strapdown attitude, the specific force is rotated by it into that
//! (almost inertial) frame and low-passed there with a time constant of seconds, and the
//! inclination correction is the rotation that takes the low-passed force to the vertical.
//! A body's translational accelerations average out over the time constant, because its
//! velocity stays bounded; the pendulum cannot do that for itself, since it is forced by
//! them.
//!
//! ekf3d and ukf3d run it beside their model as a guard: an attitude that leaves it by more
//! than [`super::ekf::Settings::guard_angle`] is reset to it (the pendulum's model no longer
//! holds, and the filter followed it).
use crate::Real;
use nalgebra::{Quaternion, UnitQuaternion, Vector3};

/// Default of the low-pass's time constant \[s\]: VQF's `tauAcc`, 3 s, chosen by its
/// authors on BROAD (the same data the replay benchmark uses; docs/real-motion.md).
pub const DEFAULT_REFERENCE_TAU: f64 = 3.0;

/// Rest detection (VQF's, section 3.4, at its defaults): the body rests while the gyro stays
/// within [`REST_GYRO`] of its low-pass and the accelerometer within [`REST_ACCEL`] of its,
/// for [`REST_MIN_T`] or longer; meanwhile the gyro's low-pass is its bias. A MEMS gyro's
/// bias (0.1 deg/s on BROAD's IMU) would otherwise tilt the reference by bias times
/// the time constant.
pub const REST_GYRO: f64 = 2.0 * core::f64::consts::PI / 180.0;
/// See [`REST_GYRO`] \[m/s^2\].
pub const REST_ACCEL: f64 = 0.5;
/// See [`REST_GYRO`] \[s\].
pub const REST_MIN_T: f64 = 1.5;
/// Time constant \[s\] of the rest detection's low-passes (VQF's `restFilterTau`).
pub const REST_TAU: f64 = 0.5;

/// The gyro and accelerometer inclination reference (see the module documentation).
#[derive(Debug, Clone)]
pub struct InclinationReference<T: Real> {
    tau: T,
    /// The gyro's bias, from the rests.
    bias: Vector3<T>,
    /// Low-passes of the gyro and the accelerometer for the rest detection.
    rest_gyro: Option<Vector3<T>>,
    rest_accel: Option<Vector3<T>>,
    /// How long the body has rested \[s\].
    resting: T,
    /// Strapdown attitude from the gyro alone (world' <- body).
    gyro_q: UnitQuaternion<T>,
    /// Inclination correction (world <- world').
    acc_q: UnitQuaternion<T>,
    /// The specific force in the gyro's frame through two one-pole low-passes in cascade
    /// (a critically damped second order: exact in f32 at a cutoff 1e-4 of the rate, where
    /// a biquad's poles round to one).
    lp: [Vector3<T>; 2],
    started: bool,
}

impl<T: Real> InclinationReference<T> {
    /// A reference whose specific force is low-passed with time constant `tau` \[s\].
    pub fn new(tau: T) -> Self {
        Self {
            tau,
            bias: Vector3::zeros(),
            rest_gyro: None,
            rest_accel: None,
            resting: T::zero(),
            gyro_q: UnitQuaternion::identity(),
            acc_q: UnitQuaternion::identity(),
            lp: [Vector3::zeros(); 2],
            started: false,
        }
    }

    /// Forgets everything.
    pub fn reset(&mut self) {
        *self = Self::new(self.tau);
    }

    /// Whether it has had a first reading.
    pub fn is_started(&self) -> bool {
        self.started
    }

    /// The gyro's bias it has found at rest \[rad/s\].
    pub fn bias(&self) -> Vector3<T> {
        self.bias
    }

    /// Whether the body rests now (for [`REST_MIN_T`] or longer): the gyro then reads its
    /// bias.
    pub fn is_resting(&self) -> bool {
        self.resting >= T::lit(REST_MIN_T)
    }

    /// One sample: the gyro `gyro` \[rad/s\] (as read: the bias is found at rest) and the
    /// specific force `f` \[m/s^2\], body axes, `dt` after the previous one. The first
    /// sample starts level on its specific force. A non-finite gyro skips the sample; a
    /// specific force that is `None` or not finite (missing, or clipped at the
    /// accelerometer's full scale: its direction is then wrong) leaves the low-pass where it
    /// was while the gyro turns the attitude on.
    pub fn update(&mut self, gyro: &Vector3<T>, f: Option<&Vector3<T>>, dt: T) {
        let f = f.filter(|f| f.iter().all(|x| x.is_finite()));
        if !gyro.iter().all(|x| x.is_finite()) || (!self.started && f.is_none()) {
            return;
        }
        match f {
            Some(f) => self.detect_rest(gyro, f, dt),
            // No rest without a reading that says so.
            None => self.resting = T::zero(),
        }
        let w = &(gyro - self.bias);
        if !self.started {
            if let Some(f) = f {
                // The first reading's direction is up: start the correction there.
                self.acc_q = tilt_to_vertical(&f.normalize());
                self.started = true;
            }
        } else if dt > T::zero() {
            let angle = w.norm() * dt;
            if angle > T::zero() {
                self.gyro_q *= UnitQuaternion::from_scaled_axis(w * dt);
            }
        }
        let Some(f) = f else {
            return;
        };
        // The specific force in the gyro's frame, low-passed there.
        let fi = self.gyro_q * f;
        if self.lp[0] == Vector3::zeros() && self.lp[1] == Vector3::zeros() {
            self.lp = [fi; 2];
        }
        // Each stage's time constant half the whole's: the cascade's mean delay is `tau`.
        let k = (dt * T::lit(2.0) / self.tau).min(T::one());
        self.lp[0] += (fi - self.lp[0]) * k;
        self.lp[1] += (self.lp[0] - self.lp[1]) * k;
        let lp = self.lp[1];
        let n = lp.norm();
        if n > T::zero() {
            let earth = self.acc_q * (lp / n);
            // The whole correction at once (the low-pass already sets the bandwidth).
            self.acc_q = tilt_to_vertical(&earth) * self.acc_q;
        }
    }

    /// Rest detection and, at rest, the bias (see [`REST_GYRO`]).
    fn detect_rest(&mut self, gyro: &Vector3<T>, f: &Vector3<T>, dt: T) {
        let k = (dt / T::lit(REST_TAU)).min(T::one());
        let lp = |old: Option<Vector3<T>>, x: &Vector3<T>| match old {
            Some(o) => o + (x - o) * k,
            None => *x,
        };
        let (g, a) = (lp(self.rest_gyro, gyro), lp(self.rest_accel, f));
        self.rest_gyro = Some(g);
        self.rest_accel = Some(a);
        let still = (gyro - g).norm() < T::lit(REST_GYRO) && (f - a).norm() < T::lit(REST_ACCEL);
        self.resting = if still { self.resting + dt } else { T::zero() };
        if self.resting >= T::lit(REST_MIN_T) {
            self.bias = g;
        }
    }

    /// Turns the reference so that its up direction is `up` (body axes, unit), its heading
    /// kept: after a stretch it could not follow (a held gyro), it takes a better estimate's
    /// inclination and goes on from there.
    pub fn align_up(&mut self, up: &Vector3<T>) {
        if !self.started {
            return;
        }
        let q = self.attitude();
        // The world's directions of the two ups: turn the world so one lands on the other.
        if let Some(turn) = UnitQuaternion::rotation_between(&(q * up), &Vector3::z()) {
            self.acc_q = turn * self.acc_q;
        }
    }

    /// The attitude (world <- body), its heading arbitrary.
    pub fn attitude(&self) -> UnitQuaternion<T> {
        self.acc_q * self.gyro_q
    }

    /// The world's up direction in body axes.
    pub fn up(&self) -> Vector3<T> {
        self.attitude().inverse() * Vector3::z()
    }
}

/// The smallest rotation that takes the unit vector `v` to the vertical `e_z`.
fn tilt_to_vertical<T: Real>(v: &Vector3<T>) -> UnitQuaternion<T> {
    let c = v[2];
    if c <= T::lit(-0.999_999) {
        // Upside down: half a turn about x.
        return UnitQuaternion::from_scaled_axis(Vector3::x() * T::lit(core::f64::consts::PI));
    }
    let w = ((c + T::one()) * T::lit(0.5)).sqrt();
    let h = T::lit(0.5) / w;
    // v x e_z = (v_y, -v_x, 0); q = (w, (v x e_z) / (2 w)).
    UnitQuaternion::new_normalize(Quaternion::new(w, v[1] * h, -v[0] * h, T::zero()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A body at rest, tilted, is found tilted from its first reading; one that turns at a
    /// constant rate while a translational acceleration of 3 m/s^2 (17 deg of a still
    /// body's tilt) comes and goes each second stays within a degree once settled.
    #[test]
    fn the_reference_finds_the_up_direction_and_ignores_short_accelerations() {
        let up = Vector3::new(-0.3f64, 0.2, 0.93).normalize();
        let mut r = InclinationReference::new(DEFAULT_REFERENCE_TAU);
        r.update(&Vector3::zeros(), Some(&(up * 9.81)), 0.0);
        assert!((r.up() - up).norm() < 1e-12);
        for _ in 0..1000 {
            r.update(&Vector3::zeros(), Some(&(up * 9.81)), 0.01);
        }
        assert!((r.up() - up).norm() < 1e-9, "{:?}", r.up());

        // Turning about the vertical at 1 rad/s, pitched 20 deg, with a horizontal
        // acceleration along the world's x that changes sign every half second.
        let mut r = InclinationReference::new(DEFAULT_REFERENCE_TAU);
        let pitch = UnitQuaternion::from_euler_angles(0.0, 20f64.to_radians(), 0.0);
        let dt = 0.005;
        let mut worst = 0.0f64;
        for k in 0..6000 {
            let t = k as f64 * dt;
            let att = UnitQuaternion::from_euler_angles(0.0, 0.0, t) * pitch;
            let w = pitch.inverse() * Vector3::new(0.0, 0.0, 1.0);
            let a_world = Vector3::new(if (t % 1.0) < 0.5 { 3.0 } else { -3.0 }, 0.0, 0.0);
            let f = att.inverse() * (a_world + Vector3::new(0.0, 0.0, 9.81));
            r.update(&w, Some(&f), if k == 0 { 0.0 } else { dt });
            // After the start's transient (it began 17 deg off, on an accelerating body).
            if t > 15.0 {
                let true_up = att.inverse() * Vector3::z();
                worst = worst.max(r.up().angle(&true_up).to_degrees());
            }
        }
        assert!(worst < 1.0, "{worst} deg");
    }

    /// Without accelerometer readings the gyro still turns the reference: a body turning
    /// about x at 0.5 rad/s for a second while the accelerometer is missing is found
    /// turned by 0.5 rad.
    #[test]
    fn without_the_accelerometer_the_gyro_carries_the_reference() {
        let mut r = InclinationReference::new(DEFAULT_REFERENCE_TAU);
        r.update(&Vector3::zeros(), Some(&Vector3::new(0.0, 0.0, 9.81)), 0.0);
        for _ in 0..100 {
            r.update(&Vector3::new(0.5, 0.0, 0.0), None, 0.01);
        }
        let roll = r.up()[1].atan2(r.up()[2]);
        assert!((roll - 0.5).abs() < 1e-9, "{roll}");
        // Nothing to start on without a reading.
        let mut r = InclinationReference::<f64>::new(DEFAULT_REFERENCE_TAU);
        r.update(&Vector3::new(0.5, 0.0, 0.0), None, 0.01);
        assert!(!r.is_started());
    }

    #[test]
    fn tilt_to_vertical_takes_a_vector_up() {
        for v in [
            Vector3::new(0.3f64, -0.4, 0.8),
            Vector3::new(0.0, 0.0, 1.0),
            Vector3::new(0.6, 0.0, -0.8),
            Vector3::new(0.0, 0.0, -1.0),
        ] {
            let v = v.normalize();
            let up = tilt_to_vertical(&v) * v;
            assert!((up - Vector3::z()).norm() < 1e-9, "{v:?} -> {up:?}");
        }
    }
}

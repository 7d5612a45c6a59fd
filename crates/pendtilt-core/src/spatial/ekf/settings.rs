//! Settings of the spatial filter ([`super::Ekf`], [`super::Ukf`]) and how the process
//! noise follows from the rig, the sensors and the environment.
//!
//! The sensors' noise figures ([`SensorNoise`]) and the environment ([`Environment`]) are
//! the planar filter's types: one definition of each figure. What they become here:
//! - encoders: `r = q^2 / 12 + sigma^2 + j^2` per axis ([`SensorNoise::encoder_variance`]
//!   and the vibration's jitter `j`, [`Settings::encoder_jitter`]);
//! - gyro: its density diffuses the attitude and the joint angles (it drives the
//!   process); its bias walks at [`SensorNoise::gyro_bias_walk`];
//! - the pendulum's rates: an unknown specific force `d` across the pendulum forces its
//!   absolute rate by `d / (g b)` per axis (MODEL.md 7.3, normalised); as in the planar
//!   filter, the density that stands for it is the vibration's density near the natural
//!   frequency, [`Environment::vibration_density`];
//! - accelerometer (optional): `d_a^2 / dt + sigma_vib^2` per axis.
use super::process::{CardanProcess, ProcessNoise};
use crate::ekf::{Environment, SensorNoise};
use crate::params::GyroSettings;
use crate::spatial::cardan::CardanParams;
use crate::spatial::mounting::Mounting;
use crate::Real;

/// Default of [`Settings::angular_accel_hz`] \[Hz\]. The body's swings that move the pivot
/// about O lie below the pendulum's natural frequency (a few Hz), the engine's angular
/// vibration above 20 Hz; the Bessel filter's delay (`2.11 / w_c`, 34 ms at 10 Hz) costs
/// the lever arm a phase error of `2 pi f` times it (0.19 rad at 0.9 Hz), which
/// [`Settings::angular_accel_lead`] takes out; at 20 Hz with the lead the second
/// derivative's noise costs more (ride3d seeds 1/2: 0.179/0.207 against 0.148/0.168 deg
/// RMS at 10 Hz; ship3d 0.265 against 0.235), at 5 or 7 Hz the lead is less exact (ride3d
/// seed 5 max 1.20 and 1.12 deg against 0.93).
pub const DEFAULT_ANGULAR_ACCEL_HZ: f64 = 10.0;

/// The defaults of [`Settings::path`] (with their measurements): the travelling
/// vehicle's, [`crate::spatial::travel`].
pub use crate::spatial::travel::{PathSettings, DEFAULT_PATH_PITCH_HZ, DEFAULT_PATH_TURN_HZ};

/// Default of [`SpeedSettings::noise`] \[m/s\]: MODEL.md 7.7's noisy grade.
pub const DEFAULT_SPEED_NOISE: f64 = 0.05;

/// Default of [`SpeedSettings::jerk_density`] \[m/s^3/sqrt(Hz)\]. Low, because the
/// pendulum against the gyro reads O's acceleration well above the speed's own band (it
/// reads tilt plus acceleration, the gyro the tilt's changes): the jerk's density need
/// only cover what that leaves to the speed. Measured (ekf3d, 120 s, seed 1, deg RMS
/// inclination / max; ride3d seeds 1/2/3 RMS): 0.1: ride3d 0.160/0.179/0.267; 0.25:
/// 0.158/0.177/0.269; 0.5: 0.158/0.178/0.271 (max 0.68/0.77/0.63), scooter3d 0.0458,
/// ship3d 0.228; 2: 0.165/0.181/0.272, scooter3d 0.0456, ship3d 0.229; 10: ride3d 0.185
/// (max 0.77), ship3d 0.230. Before O's speed and rate were states (the speed's
/// derivative through a 5 Hz Bessel filter): ride3d 0.174/0.213/0.294, scooter3d 0.0562,
/// ship3d 0.297 (max 2.24).
pub const DEFAULT_JERK_DENSITY: f64 = 0.5;

/// Default of [`SpeedSettings::initial_rate`] \[m/s^2\]: a vehicle whose speed is first
/// read while it brakes or pulls away (0.2 g).
pub const DEFAULT_INITIAL_SPEED_RATE: f64 = 2.0;

/// Default of [`SpeedSettings::timeout`] \[s\]: as long as the CLI lets any sensor be
/// missing before it restarts the estimators that read it; a wheel-speed signal on a bus
/// comes at 10-100 Hz, so a log at the IMU's rate has it on one row in 10-100.
pub const DEFAULT_SPEED_TIMEOUT: f64 = 0.5;

/// O's forward speed and its rate as states: the `speed` column measures the
/// speed, the rate is a random walk.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpeedSettings<T> {
    /// Standard deviation of one `speed` reading \[m/s\]. Default 0.05: see
    /// [`DEFAULT_SPEED_NOISE`].
    pub noise: T,
    /// Density of O's jerk along body x \[m/s^3/sqrt(Hz)\]: how fast the vehicle's
    /// forward acceleration may change. Default: see [`DEFAULT_JERK_DENSITY`].
    pub jerk_density: T,
    /// Standard deviation of O's forward acceleration when the speed is first read
    /// \[m/s^2\]. Default 2: see [`DEFAULT_INITIAL_SPEED_RATE`].
    pub initial_rate: T,
    /// Longest stretch \[s\] without a `speed` reading over which O's speed and rate are
    /// carried by the filter (rows between the readings of a slower speed signal, or a
    /// short loss); after it both are held at zero (the vehicle taken as not
    /// accelerating) until the next reading. Default 0.5 s: see [`DEFAULT_SPEED_TIMEOUT`].
    pub timeout: T,
}

impl<T: Real> Default for SpeedSettings<T> {
    fn default() -> Self {
        Self {
            noise: T::lit(DEFAULT_SPEED_NOISE),
            jerk_density: T::lit(DEFAULT_JERK_DENSITY),
            initial_rate: T::lit(DEFAULT_INITIAL_SPEED_RATE),
            timeout: T::lit(DEFAULT_SPEED_TIMEOUT),
        }
    }
}

impl<T: Real> SpeedSettings<T> {
    /// The same settings in another scalar type.
    pub fn cast<U: Real>(&self) -> SpeedSettings<U> {
        let c = |x: T| U::lit(x.to_f64());
        SpeedSettings {
            noise: c(self.noise),
            jerk_density: c(self.jerk_density),
            initial_rate: c(self.initial_rate),
            timeout: c(self.timeout),
        }
    }
}

/// Default of [`Settings::encoder_jitter`] \[deg\]. Measured (ekf3d, deg RMS inclination,
/// 120 s, seeds 1/2/3, scenario sensor figures), without -> 0.05 deg:
/// - scooter3d: 0.109/0.086/0.079 -> 0.054/0.059/0.057;
/// - ride3d: 0.51/1.21/0.83 (max 5.0/8.8/7.3) -> 0.340/0.483/0.514 (max 1.06/1.57/1.54;
///   with the speed's derivative at 5 Hz rather than 2, 0.285/0.432/0.451);
/// - ship3d: 0.305/0.243/0.235 -> 0.307/0.245/0.235; still3d (noise-free, 6 s) 0.003
///   either way, ukf3d too. 0.03 and 0.1 gave 0.054 and 0.053 on scooter3d seed 1.
pub const DEFAULT_ENCODER_JITTER_DEG: f64 = 0.05;

/// Defaults of [`SlipSettings`] (wheel slip; module `super::slip`). Measured
/// with ekf3d at its other defaults (`cargo test --release -p pendtilt --test ride3d_slip
/// -- --nocapture`; the sweep on 2026-12-02, before the encoder jitter and the 5 Hz speed
/// derivative: ride3d seeds 1-3, scooter3d and ship3d 120 s, ride3d_slip seeds 1-3; the
/// seed-1 figures re-measured after them).
pub mod slip_defaults {
    /// [`super::SlipSettings::hz`] \[Hz\]: the cutoff of the detector's Bessel filter
    /// (the speed's derivative and the accelerometer's longitudinal acceleration alike).
    /// Its delay (`2.11 / w_c`, 67 ms at 5 Hz) is most of the detection's; higher lets
    /// more of the engine's and the road's vibration through. Measured: at 5 Hz (gate 2)
    /// no false slip on the five plain 120 s logs, the lock on ride3d_slip flagged 26-33
    /// ms after it starts and the spin 56-65 ms after; at 10 Hz 215 falsely flagged
    /// samples on ride3d seed 2 (gate 2) and ekf3d's largest error during the lock (seed
    /// 1) 1.34 deg against 1.21.
    pub const HZ: f64 = 5.0;
    /// [`super::SlipSettings::gate`] \[m/s^2\]: the accelerations through the same filter
    /// disagree by at most 0.96 m/s^2 on plain ride3d (seed 1, 120 s) (engine and road vibration, the
    /// attitude's error, the lever arm from the smoothed gyro), while a wheel locking or
    /// spinning changes the reading at 10-100 m/s^2. Measured at 5 Hz: no false slip at
    /// 1.5, 2 or 3 on the plain logs; detection 3-5 ms later at 3 than at 1.5.
    pub const GATE: f64 = 2.0;
    /// [`super::SlipSettings::impossible`] \[m/s^2\]: 1.5 g. A car brakes at up to 1 g
    /// (1.2 g on racing tyres), pulls away at well under; a wheel that locks or spins
    /// changes its reading at tens of m/s^2.
    pub const IMPOSSIBLE: f64 = 1.5 * 9.80665;
    /// [`super::SlipSettings::speed_tolerance`] \[m/s\]: a few times the reading's noise
    /// after the filter (0.05 m/s white in the noisy grade) plus the carried speed's lead
    /// before the slip (0.13 m/s braking at 4 m/s^2 on ride3d_slip seed 1).
    pub const SPEED_TOLERANCE: f64 = 0.3;
    /// [`super::SlipSettings::drift`] \[m/s^2\]: what the carried speed may drift per
    /// second of slip. Measured: 0.46 m/s over the 1.3 s lock on ride3d_slip seed 1
    /// (ekf3d's attitude error while braking, ~1 deg, is 0.17 m/s^2).
    pub const DRIFT: f64 = 0.5;
    /// [`super::SlipSettings::hold`] \[s\]: a reading that comes back must stay for this
    /// long (the filter's delay and a margin). Measured: the spin (83.5-85.7 s) is flagged
    /// to 85.97 s, the lock (61.8-62.95 s) to 63.25 s, seed 1.
    pub const HOLD: f64 = 0.2;
    /// [`super::SlipSettings::timeout`] \[s\]: the carried speed's drift (at DRIFT) reaches
    /// 2.5 m/s by then; a longer slip is better taken as a wrong but smooth reading. Not
    /// reached on ride3d_slip.
    pub const TIMEOUT: f64 = 5.0;
    /// [`super::SlipSettings::follow_hz`] \[Hz\]: low enough that the detection's delay
    /// (30-65 ms) lets little of the wheel's departure into the carried speed (at 0.3 Hz
    /// about 6 % of it per 50 ms), high enough that the accelerometer's error (0.25 m/s^2
    /// while braking) leaves it within the tolerance (0.13 m/s). Not tuned.
    pub const FOLLOW_HZ: f64 = 0.3;
}

/// Wheel-slip detection on the `speed` column (module `super::slip`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SlipSettings<T> {
    /// Detect slip and drop the speed while it lasts. Default true.
    pub enabled: bool,
    /// Cutoff \[Hz\] of the Bessel filter through which the speed (differentiated) and the
    /// accelerometer's longitudinal acceleration (low-passed) are compared. Default: see
    /// [`slip_defaults::HZ`].
    pub hz: T,
    /// Slip when the two longitudinal accelerations differ by more than this \[m/s^2\].
    /// Default: see [`slip_defaults::GATE`].
    pub gate: T,
    /// Slip when the speed's derivative alone is beyond this \[m/s^2\]. Default 1.5 g:
    /// see [`slip_defaults::IMPOSSIBLE`].
    pub impossible: T,
    /// The slip ends once the reading is this close to the carried speed \[m/s\] (plus
    /// [`Self::drift`] times the slip's length; and the
    /// accelerations agree within half the gate) for [`Self::hold`]. Default: see
    /// [`slip_defaults::SPEED_TOLERANCE`].
    pub speed_tolerance: T,
    /// How the speed tolerance grows with the slip's length \[m/s^2\]: the carried speed
    /// integrates the accelerometer's bias and the attitude's error (`g` times it).
    /// Default: see [`slip_defaults::DRIFT`].
    pub drift: T,
    /// How long the reading must agree before the slip ends \[s\]. Default: see
    /// [`slip_defaults::HOLD`].
    pub hold: T,
    /// The longest slip \[s\]: after it the reading is trusted again (the carried speed
    /// drifts with the accelerometer's bias and the attitude's error). Default: see
    /// [`slip_defaults::TIMEOUT`].
    pub timeout: T,
    /// Crossover \[Hz\] of the complementary filter that carries the speed between slips
    /// (the reading below it, the accelerometer above). Default: see
    /// [`slip_defaults::FOLLOW_HZ`].
    pub follow_hz: T,
}

impl<T: Real> Default for SlipSettings<T> {
    fn default() -> Self {
        use slip_defaults as d;
        Self {
            enabled: true,
            hz: T::lit(d::HZ),
            gate: T::lit(d::GATE),
            impossible: T::lit(d::IMPOSSIBLE),
            speed_tolerance: T::lit(d::SPEED_TOLERANCE),
            drift: T::lit(d::DRIFT),
            hold: T::lit(d::HOLD),
            timeout: T::lit(d::TIMEOUT),
            follow_hz: T::lit(d::FOLLOW_HZ),
        }
    }
}

impl<T: Real> SlipSettings<T> {
    /// The same settings in another scalar type.
    pub fn cast<U: Real>(&self) -> SlipSettings<U> {
        let c = |x: T| U::lit(x.to_f64());
        SlipSettings {
            enabled: self.enabled,
            hz: c(self.hz),
            gate: c(self.gate),
            impossible: c(self.impossible),
            speed_tolerance: c(self.speed_tolerance),
            drift: c(self.drift),
            hold: c(self.hold),
            timeout: c(self.timeout),
            follow_hz: c(self.follow_hz),
        }
    }
}

/// The forcing's adaptation, shared with the planar filter ([`crate::adaptation`]);
/// ekf3d's defaults are [`Adaptation::spatial`].
pub use crate::adaptation::Adaptation;

/// Settings of the spatial model-based filter.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Settings<T> {
    /// The pendulum (normalised, MODEL.md 7.3). Default: MODEL.md 7.6's rig.
    pub params: CardanParams<T>,
    /// Sensor noise figures. Default: the planar filter's defaults.
    pub sensors: SensorNoise<T>,
    /// The gyro's full scale (the rig file's `[gyro]`, the planar estimators' one
    /// definition), per axis: a sample with an axis at or beyond it is flagged
    /// [`crate::Flags::SATURATED`] and the attitude is loosened against the joint angles
    /// by the rate the clip may hide, so that the encoders carry it (see
    /// [`super::ModelBased`]). Default: unknown (no check).
    pub gyro: GyroSettings<T>,
    /// The body's motion and vibration. Default: the planar filter's (the scooter).
    pub environment: Environment<T>,
    /// Where the sensors sit: the accelerometer, and the point O the body turns about
    /// (`speed_at`; see [`Mounting`]). Default: both at P1.
    pub mounting: Mounting<T>,
    /// Cutoff \[Hz\] of the smoothing differentiator (Bessel, 4th order) that takes the
    /// body's angular acceleration from the gyro, for the lever arm from O to the pivot
    /// and the accelerometer. Default 10 Hz: see [`DEFAULT_ANGULAR_ACCEL_HZ`].
    pub angular_accel_hz: T,
    /// Take the angular acceleration's filter delay (`2.11 / w_c`, 34 ms at 10 Hz) out by
    /// its second derivative, `wd + delay wd'`. Default true: the delay's phase error
    /// (0.32 rad at 1.5 Hz) left a third of a vehicle's yaw wobble and suspension roll on
    /// a lever arm of a metre in the pendulum's forcing. Measured (ekf3d, 120 s, deg RMS /
    /// max inclination, without -> with): ride3d seeds 1/2/3/5 0.158/0.684, 0.178/0.767,
    /// 0.271/0.629, 0.215/1.256 -> 0.148/0.478, 0.168/0.661, 0.239/0.569, 0.197/0.931;
    /// scooter3d 0.0458 -> 0.0454; ship3d 0.228/0.820 -> 0.235/1.054 (its lever arm, 9.4 m,
    /// carries the second derivative's noise). Without the lead a higher cutoff took ride3d
    /// seed 5 to 1.04 (20 Hz), 1.01 (30 Hz) and seed 2 to 7.0 (60 Hz: the engine).
    pub angular_accel_lead: bool,
    /// How the gyro gives the rate at which the vehicle's path turns and pitches, for O's
    /// centripetal acceleration. Default: [`PathSettings`]'s.
    pub path: PathSettings<T>,
    /// O's forward speed and its rate: the `speed` column's noise and the jerk. Default:
    /// [`SpeedSettings`]'s.
    pub speed: SpeedSettings<T>,
    /// Standard deviation \[rad\] of the encoders' jitter from the vibration above the
    /// pendulum's band, added to their own noise ([`SensorNoise::encoder_variance`]):
    /// the process model forces the pendulum with white noise of the vibration's density
    /// near its natural frequency, but an engine's tones and the road's broadband above it
    /// still move it (1.5 m/s^2 at 18 Hz swings the default pendulum by 0.13 deg), and
    /// two axes vibrating out of phase trace an ellipse that the joint kinematics explain
    /// only as a turn about z: with the encoders' noise alone ekf3d took ride3d's idling
    /// engine for a gyro z bias of 5.3 deg/s within 4 s (true 0.2), roll 1 deg off.
    /// Default 0.05 deg: see [`DEFAULT_ENCODER_JITTER_DEG`].
    pub encoder_jitter: T,
    /// Wheel-slip detection on the `speed` column (it uses the accelerometer whether or
    /// not [`Self::use_accel`] is set). Default on: see [`SlipSettings`].
    pub slip: SlipSettings<T>,
    /// Use the accelerometer as a further measurement of the up direction. Default false:
    /// it reads the vibration unfiltered (as in the planar filter).
    pub use_accel: bool,
    /// Use the encoders. Default true. False gives `imu3d`, the ablation: the same filter
    /// (motion model, bias states, adaptation, guard) with the accelerometer in place of
    /// the encoders as its gravity reference ([`Self::imu_only`]), which tells what the
    /// pendulum itself adds.
    pub use_encoders: bool,
    /// Longest integration step \[s\]; longer sample intervals are split. Default 5 ms.
    pub max_step: T,
    /// Longest gap \[s\] bridged by prediction, between rows or between encoder readings;
    /// after a longer one the filter starts again on the next reading. Default 50 ms (as
    /// the planar filter's, and for the same reason: the prediction cannot follow the
    /// body's motion for long without the pendulum). Without the encoders (imu3d) the
    /// gyro bridges missing accelerometer readings, and only a gap of both restarts.
    pub max_gap: T,
    /// Initial standard deviation of roll and pitch around the first encoder angles
    /// \[rad\]. Default 2 deg (the pendulum is taken as hanging still on the first sample).
    pub initial_angle: T,
    /// Innovation gate on each encoder axis' normalised innovation squared (chi-square
    /// with one degree of freedom for a consistent filter). Default 50, the planar
    /// filter's (see [`crate::ekf::ModelSettings::innovation_gate`]).
    pub innovation_gate: T,
    /// Consecutive rejections after which a measurement is re-acquired: for the encoders,
    /// the joint states start again at the reading (the attitude is left as it is: a
    /// pendulum that tumbled says nothing of the tilt); for the speed, its covariance is
    /// inflated by the innovation and the reading applied without the gate. Default 200
    /// samples.
    pub reacquire_after: u32,
    /// The pendulum's forcing adapted to the log. Default on, [`Adaptation::spatial`]
    /// (docs/real-motion.md).
    pub adaptation: Adaptation<T>,
    /// The guard \[rad\]: when the filter's up direction and the gyro and accelerometer's
    /// ([`crate::spatial::imu::InclinationReference`], the accelerometer less O's known
    /// acceleration) are further apart than this, the filter's attitude is reset to the
    /// reference's and its joint states start again ([`crate::Flags::RESET`]): the
    /// pendulum's model no longer held and the filter followed it. Default 5 deg: the
    /// reference stays within 2-3 deg on BROAD's hand-held motion (docs/real-motion.md),
    /// and a filter that is right never comes near it. Infinite: no guard, and the
    /// reference is not used at all (neither while the pendulum is unused nor for the
    /// gyro's bias at rest).
    pub guard_angle: T,
    /// Time constant \[s\] of the guard's low-pass of the specific force. Default 3 s, VQF's
    /// ([`crate::spatial::imu::DEFAULT_REFERENCE_TAU`]).
    pub guard_tau: T,
    /// Largest inner-joint angle |b| \[rad\] at which the encoders are used: beyond it the
    /// Cardan joint nears its lock (b = 90 deg) and the outer angle says nothing of roll.
    /// Default 70 deg.
    pub pendulum_range: T,
}

impl<T: Real> Default for Settings<T> {
    fn default() -> Self {
        Self {
            params: CardanParams::default(),
            sensors: SensorNoise::default(),
            gyro: GyroSettings::default(),
            environment: Environment::default(),
            mounting: Mounting::default(),
            angular_accel_hz: T::lit(DEFAULT_ANGULAR_ACCEL_HZ),
            angular_accel_lead: true,
            path: PathSettings::default(),
            speed: SpeedSettings::default(),
            encoder_jitter: T::lit(DEFAULT_ENCODER_JITTER_DEG.to_radians()),
            slip: SlipSettings::default(),
            use_accel: false,
            use_encoders: true,
            max_step: T::lit(0.005),
            max_gap: T::lit(0.05),
            initial_angle: T::lit(2.0f64.to_radians()),
            innovation_gate: T::lit(50.0),
            reacquire_after: 200,
            adaptation: Adaptation::spatial(),
            guard_angle: T::lit(5f64.to_radians()),
            guard_tau: T::lit(crate::spatial::imu::DEFAULT_REFERENCE_TAU),
            pendulum_range: T::lit(70f64.to_radians()),
        }
    }
}

impl<T: Real> Settings<T> {
    /// The same settings in another scalar type (an `f64` configuration for an `f32`
    /// filter).
    pub fn cast<U: Real>(&self) -> Settings<U> {
        let c = |x: T| U::lit(x.to_f64());
        Settings {
            params: self.params.cast(),
            sensors: self.sensors.cast(),
            gyro: GyroSettings {
                full_scale: self.gyro.full_scale.map(c),
            },
            environment: self.environment.cast(),
            mounting: self.mounting.cast(),
            angular_accel_hz: c(self.angular_accel_hz),
            angular_accel_lead: self.angular_accel_lead,
            path: self.path.cast(),
            speed: self.speed.cast(),
            encoder_jitter: c(self.encoder_jitter),
            slip: self.slip.cast(),
            use_accel: self.use_accel,
            use_encoders: self.use_encoders,
            max_step: c(self.max_step),
            max_gap: c(self.max_gap),
            initial_angle: c(self.initial_angle),
            innovation_gate: c(self.innovation_gate),
            reacquire_after: self.reacquire_after,
            adaptation: self.adaptation.cast(),
            guard_angle: c(self.guard_angle),
            guard_tau: c(self.guard_tau),
            pendulum_range: c(self.pendulum_range),
        }
    }

    /// These settings as `imu3d`'s: the accelerometer in place of the encoders
    /// ([`Self::use_encoders`]), everything else as it is.
    pub fn imu_only(self) -> Self {
        Self {
            use_encoders: false,
            use_accel: true,
            ..self
        }
    }

    /// The variance of one encoder reading \[rad^2\]: the sensor's and the vibration's
    /// jitter ([`Settings::encoder_jitter`]).
    pub fn encoder_variance(&self) -> T {
        self.sensors.encoder_variance() + self.encoder_jitter * self.encoder_jitter
    }

    /// The process model these settings describe.
    pub fn process_model(&self) -> CardanProcess<T> {
        let p = &self.params;
        let g = p.gravity;
        let d = self.environment.vibration_density;
        CardanProcess {
            params: *p,
            noise: ProcessNoise {
                gyro: self.sensors.gyro_density,
                bias: self.sensors.gyro_bias_walk,
                joints: [d / (g * (p.b_x + p.b_ring)), d / (g * p.b_y)],
                jerk: self.speed.jerk_density,
            },
            pivot_from_centre: self.mounting.from_centre(p.c.map(|c| c * g)),
        }
    }
}

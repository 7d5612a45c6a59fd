//! The planar simulator: an exact model of the pendulum rig on a tilting, vibrating body,
//! with realistic sensors (MODEL.md sections 1, 2, 5 and 6).
//!
//! - [`scenario`]: what to simulate ([`Scenario`]), named defaults, scenario TOML.
//! - [`motion`]: the prescribed body tilt with exact derivatives.
//! - [`vibration`]: engine harmonics, broadband vibration, angular vibration.
//! - [`dynamics`]: the exact pendulum equation.
//! - [`integrator`]: fixed-step RK4 at `substeps` steps per sample.
//! - [`sensors`]: encoder, gyro, accelerometer, potentiometer.
//! - [`output`]: the CSV log and the rig TOML.
//!
//! ```
//! use pendtilt::sim::planar::{simulate, Scenario};
//! let mut s = Scenario::named("sigmoid").unwrap();
//! s.duration = 0.5;
//! let rows = simulate(&s, 1).unwrap();
//! assert_eq!(rows.len(), 500);
//! assert_eq!(rows[0].t, 0.0);
//! ```
//!
//! For long runs iterate a [`Simulator`] (or use [`output::write_log`]): rows are produced
//! one at a time and memory stays flat. Same scenario and seed give the same rows, bit for bit.

pub mod dynamics;
pub mod integrator;
pub mod motion;
pub mod output;
pub mod overrides;
pub mod scenario;
pub mod sensors;
pub mod sines;
pub mod vibration;

pub use scenario::{load_config, load_rig, rig_toml, PendulumTable, Scenario, SCENARIO_NAMES};

use pendtilt_core::model::Sample;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use dynamics::{body_to_world, specific_force, Pendulum};
use integrator::{rk4_step, Node};
use motion::{Kinematics, MotionFn};
use sensors::{SensorBank, TrueSignals};
use vibration::VibrationGen;

/// What can go wrong setting up a simulation.
#[derive(Debug, thiserror::Error)]
pub enum SimError {
    /// A value out of range.
    #[error("{key}: {reason}")]
    Invalid {
        /// The key, as written in a scenario TOML (`pendulum.mass`).
        key: String,
        /// Why it is rejected.
        reason: String,
    },
    /// A scenario name that does not exist.
    #[error("unknown scenario '{name}' (known: {known})")]
    UnknownScenario {
        /// The name asked for.
        name: String,
        /// The names that exist.
        known: String,
    },
    /// A scenario or rig TOML that cannot be read as one.
    #[error("{origin}: {message}")]
    Config {
        /// The file (or `--set ...`) the problem is in.
        origin: String,
        /// What is wrong.
        message: String,
    },
    /// A file that cannot be read or written.
    #[error("{path}: {error}")]
    Io {
        /// The file.
        path: String,
        /// The error (not a `source`: the message holds it, and a chain printed it twice).
        error: std::io::Error,
    },
}

impl SimError {
    /// A [`SimError::Invalid`].
    pub fn invalid(key: impl Into<String>, reason: impl Into<String>) -> Self {
        SimError::Invalid {
            key: key.into(),
            reason: reason.into(),
        }
    }
}

/// The true state behind one log row (not in the CSV; for tests, reports and fits).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Truth {
    /// Body tilt theta \[rad\] (prescribed motion plus angular vibration).
    pub theta: f64,
    /// theta' \[rad/s\].
    pub omega: f64,
    /// theta'' \[rad/s^2\].
    pub alpha: f64,
    /// Pendulum absolute angle beta \[rad\].
    pub beta: f64,
    /// beta' \[rad/s\].
    pub beta_dot: f64,
    /// beta'' \[rad/s^2\].
    pub beta_ddot: f64,
    /// phi = theta - beta \[rad\].
    pub phi: f64,
    /// phi' \[rad/s\].
    pub phi_dot: f64,
    /// phi'' \[rad/s^2\].
    pub phi_ddot: f64,
    /// Specific force at the pivot P2, body axes \[m/s^2\].
    pub f_pivot: [f64; 2],
    /// Specific force at the accelerometer, body axes \[m/s^2\] (before sensor errors).
    pub accel: [f64; 2],
    /// Translational acceleration of P1 (vibration), body axes \[m/s^2\].
    pub a_p1: [f64; 2],
}

/// One log row: the CSV columns of MODEL.md section 5 and the truth behind them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SimRow {
    /// t_k = k / rate \[s\].
    pub t: f64,
    /// t_k - t_(k-1) \[s\] (0 for the first row): the step the estimators take, the same
    /// as a [`pendtilt_core::StepGate`] computes from the written stamps.
    pub dt: f64,
    /// Encoder reading \[rad\].
    pub phi: f64,
    /// Gyro reading \[rad/s\].
    pub gyro: f64,
    /// Accelerometer x reading \[m/s^2\].
    pub ax: f64,
    /// Accelerometer y reading \[m/s^2\].
    pub ay: f64,
    /// Potentiometer reading: the true tilt with its small noise \[rad\].
    pub theta: f64,
    /// The exact state.
    pub truth: Truth,
}

impl SimRow {
    /// The sensor readings as the estimators take them.
    pub fn sample(&self) -> Sample<f64> {
        Sample {
            dt: self.dt,
            phi: self.phi,
            gyro: self.gyro,
            ax: self.ax,
            ay: self.ay,
        }
    }
}

/// Random stream numbers: each random part of a run draws from its own ChaCha8 stream of
/// the seed, so changing one part's settings does not reshuffle the others.
mod stream {
    pub const ENCODER: u64 = 1;
    pub const GYRO: u64 = 2;
    pub const ACCEL: u64 = 3;
    pub const POT: u64 = 4;
    pub const VIBRATION: u64 = 5;
    pub const MOTION: u64 = 6;
}

fn rng(seed: u64, stream: u64) -> ChaCha8Rng {
    let mut r = ChaCha8Rng::seed_from_u64(seed);
    r.set_stream(stream);
    r
}

/// A running simulation: an iterator over the rows of the log, computed on demand.
#[derive(Debug, Clone)]
pub struct Simulator {
    pend: Pendulum,
    motion: MotionFn,
    vib: VibrationGen,
    vib_rng: ChaCha8Rng,
    sensors: SensorBank,
    rate: f64,
    substeps: usize,
    rows: u64,
    k: u64,
    y: [f64; 2],
    /// P2 and the accelerometer, from P1 in body axes \[m\].
    p2: [f64; 2],
    mount: [f64; 2],
    kin: Vec<Kinematics>,
    acc: Vec<[f64; 2]>,
    force: Vec<[f64; 2]>,
}

impl Simulator {
    /// Sets up a run of `scenario` with random parts drawn from `seed`. The pendulum starts
    /// hanging still in the world (beta = 0, beta' = 0; MODEL.md section 6).
    pub fn new(scenario: &Scenario, seed: u64) -> Result<Self, SimError> {
        scenario.validate()?;
        let p = scenario.physical();
        let n = 2 * scenario.substeps as usize + 1;
        let mut vib_rng = rng(seed, stream::VIBRATION);
        let vib = VibrationGen::new(&scenario.vibration, scenario.node_rate(), &mut vib_rng);
        let motion = scenario.motion.build(&mut rng(seed, stream::MOTION));
        let streams =
            [stream::ENCODER, stream::GYRO, stream::ACCEL, stream::POT].map(|s| rng(seed, s));
        let mount = scenario.sensors.accel.mount;
        Ok(Self {
            pend: Pendulum::new(&p),
            motion,
            vib,
            vib_rng,
            sensors: SensorBank::new(&scenario.sensors, scenario.rate, streams),
            rate: scenario.rate,
            substeps: scenario.substeps as usize,
            rows: scenario.rows(),
            k: 0,
            y: [0.0, 0.0],
            p2: [0.0, p.pivot_offset],
            mount: [mount[0], p.pivot_offset + mount[1]],
            kin: vec![[0.0; 3]; n],
            acc: vec![[0.0; 2]; n],
            force: vec![[0.0; 2]; n],
        })
    }

    /// Starts the pendulum at (beta, beta') instead of hanging still (free-decay and energy
    /// experiments). Call before the first row.
    pub fn with_initial_state(mut self, beta: f64, beta_dot: f64) -> Self {
        self.y = [beta, beta_dot];
        self
    }

    /// Total number of rows of the run.
    pub fn total_rows(&self) -> u64 {
        self.rows
    }

    /// Rows produced so far.
    pub fn rows_done(&self) -> u64 {
        self.k
    }

    /// The pendulum model in use.
    pub fn pendulum(&self) -> &Pendulum {
        &self.pend
    }

    fn step(&mut self) -> SimRow {
        let t0 = self.k as f64 / self.rate;
        let h = 1.0 / (self.rate * self.substeps as f64);
        let half = 0.5 * h;
        let g = self.pend.params.gravity;
        self.motion.fill(self.k, t0, half, &mut self.kin);
        self.vib.add_angular(self.k, t0, half, &mut self.kin);
        self.vib
            .fill_accel(self.k, t0, half, &mut self.vib_rng, &mut self.acc);
        let mut sc0 = (0.0, 1.0);
        for j in 0..self.kin.len() {
            let sc = self.kin[j][0].sin_cos();
            if j == 0 {
                sc0 = sc;
            }
            let f = specific_force(&self.kin[j], self.acc[j], self.p2, sc, g);
            self.force[j] = body_to_world(f, sc);
        }

        // The row at t0, from the state before this interval is integrated.
        let [theta, omega, alpha] = self.kin[0];
        let [beta, beta_dot] = self.y;
        let beta_ddot = self.pend.beta_ddot(beta, beta_dot, self.force[0], omega);
        let f_pivot = specific_force(&self.kin[0], self.acc[0], self.p2, sc0, g);
        let accel = specific_force(&self.kin[0], self.acc[0], self.mount, sc0, g);
        let truth = Truth {
            theta,
            omega,
            alpha,
            beta,
            beta_dot,
            beta_ddot,
            phi: theta - beta,
            phi_dot: omega - beta_dot,
            phi_ddot: alpha - beta_ddot,
            f_pivot,
            accel,
            a_p1: self.acc[0],
        };
        let r = self.sensors.read(&TrueSignals {
            phi: truth.phi,
            omega,
            accel,
            theta,
        });

        for i in 0..self.substeps {
            let j = 2 * i;
            let (pend, force, kin) = (&self.pend, &self.force, &self.kin);
            self.y = rk4_step(self.y, h, |node, y| {
                let jj = match node {
                    Node::Start => j,
                    Node::Mid => j + 1,
                    Node::End => j + 2,
                };
                pend.rhs(y, force[jj], kin[jj][1])
            });
        }
        let dt = if self.k == 0 {
            0.0
        } else {
            t0 - (self.k - 1) as f64 / self.rate
        };
        self.k += 1;
        SimRow {
            t: t0,
            dt,
            phi: r.phi,
            gyro: r.gyro,
            ax: r.ax,
            ay: r.ay,
            theta: r.theta,
            truth,
        }
    }
}

impl Iterator for Simulator {
    type Item = SimRow;

    fn next(&mut self) -> Option<SimRow> {
        (self.k < self.rows).then(|| self.step())
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        let left = usize::try_from(self.rows - self.k).unwrap_or(usize::MAX);
        (left, Some(left))
    }
}

/// Runs `scenario` with `seed` and collects every row (for short runs; for long ones
/// iterate a [`Simulator`]).
pub fn simulate(scenario: &Scenario, seed: u64) -> Result<Vec<SimRow>, SimError> {
    Ok(Simulator::new(scenario, seed)?.collect())
}

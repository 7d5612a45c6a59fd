//! The registry ([`REGISTRY`]): every estimator the bank knows, by output column, with
//! how it is built from [`BankSettings`] (what it reads: [`crate::catalogue`]); and
//! [`build_alone`], one entry's estimator on its own.
use pendtilt_core::ekf::{Ekf, Ukf};
use pendtilt_core::estimators::accel::Accel;
use pendtilt_core::estimators::alg2::Alg2Settings;
use pendtilt_core::estimators::complementary::Complementary;
use pendtilt_core::estimators::equations::Equation;
use pendtilt_core::estimators::front_end::{FrontEndSettings, SharedFrontEnd};
use pendtilt_core::estimators::pendulum::{Pendulum, PendulumSettings};
use pendtilt_core::kalman::KalmanSettings;
use pendtilt_core::{Estimate, Estimator, Flags, PlanarEstimator, Sample};

use super::{BankSettings, Inputs};
use crate::catalogue::{self, Listing};
use crate::peers::{self, ahrs_planar};

/// A boxed streaming estimator over `f64`.
pub type BoxedEstimator = Box<dyn PlanarEstimator<f64> + Send>;

/// Picks a measurement variance R [rad^2] from the Kalman settings.
pub type RSelector = fn(&KalmanSettings<f64>) -> f64;

/// A Kalman measurement source: the output it reads and the variance it is given.
pub type KalmanSource = (&'static str, RSelector);

/// A front end and the inversion equation evaluated on it.
pub type InversionSpec = (FrontEndSettings<f64>, Equation<f64>);

/// How an output is computed.
pub enum Kind {
    /// A streaming estimator built from the settings.
    Direct(fn(&BankSettings) -> BoxedEstimator),
    /// One of Algorithms 1-3: an equation on a front end. Consecutive entries whose front
    /// ends are equal share one ([`SharedFrontEnd`]): one differentiator per sample for
    /// all of them, each output the same as its stand-alone estimator's.
    Inversion(fn(&BankSettings) -> InversionSpec),
    /// The angle+bias Kalman filter fed by other outputs, each `(name, r)` with `r` read
    /// from the settings.
    Kalman(&'static [KalmanSource]),
}

/// One estimator the bank knows: its name and how it is built (what it reads and what it
/// is: its row of the catalogue, [`Entry::listing`]).
pub struct Entry {
    /// Output column name (MODEL.md section 5), its catalogue row's.
    pub name: &'static str,
    /// How it is built.
    pub kind: Kind,
    /// Whether it takes the gyro as missing while the gyro clips heavily
    /// ([`pendtilt_core::estimators::clip_gate`]): the model-based filters, which the
    /// biased readings within range would pull off most.
    pub gyro_gated: bool,
}

fn r_accel(k: &KalmanSettings<f64>) -> f64 {
    k.r_accel
}
fn r_pendulum(k: &KalmanSettings<f64>) -> f64 {
    k.r_pendulum
}
fn r_accel_fused(k: &KalmanSettings<f64>) -> f64 {
    k.r_accel_fused.unwrap_or(k.r_accel)
}

impl Entry {
    /// Its row of the catalogue.
    pub fn listing(&self) -> &'static Listing {
        catalogue::expect(self.name)
    }

    /// The sensors it needs.
    pub fn needs(&self) -> Inputs {
        self.listing().reads
    }

    /// One line on what it is, for `--help` and reports.
    pub fn about(&self) -> &'static str {
        self.listing().about
    }
}

/// Every estimator, in output column order (the catalogue's planar rows').
pub static REGISTRY: &[Entry] = &[
    Entry {
        name: "accel",
        kind: Kind::Direct(|s| Box::new(Accel::new(s.rig.accel))),
        gyro_gated: false,
    },
    Entry {
        name: "pendulum",
        kind: Kind::Direct(|_| Box::new(Pendulum::new(PendulumSettings {}))),
        gyro_gated: false,
    },
    Entry {
        name: "alg1",
        kind: Kind::Inversion(|s| {
            // Algorithm 1 does not read theta'': take Algorithm 2's source so that they
            // can share a front end.
            let a = s.rig.alg1_settings();
            let fe = FrontEndSettings {
                theta_dd: s.rig.alg2.front_end.theta_dd,
                ..a.front_end
            };
            (fe, a.equation())
        }),
        gyro_gated: false,
    },
    Entry {
        name: "alg2",
        kind: Kind::Inversion(|s| {
            let a = s.rig.alg2_settings();
            (a.front_end, a.equation())
        }),
        gyro_gated: false,
    },
    Entry {
        name: "alg2_offset",
        kind: Kind::Inversion(|s| {
            let a = Alg2Settings {
                pivot_offset: true,
                ..s.rig.alg2_settings()
            };
            (a.front_end, a.equation())
        }),
        gyro_gated: false,
    },
    Entry {
        name: "alg2_dc",
        kind: Kind::Inversion(|s| {
            let a = Alg2Settings {
                delay_compensation: true,
                ..s.rig.alg2_settings()
            };
            (a.front_end, a.equation())
        }),
        gyro_gated: false,
    },
    Entry {
        name: "alg3",
        kind: Kind::Inversion(|s| {
            let a = s.rig.alg3_settings();
            (a.front_end, Equation::Alg3(a.gains))
        }),
        gyro_gated: false,
    },
    Entry {
        name: "kf_accel",
        kind: Kind::Kalman(&[("accel", r_accel)]),
        gyro_gated: false,
    },
    Entry {
        name: "kf_alg1",
        kind: Kind::Kalman(&[("alg1", r_pendulum)]),
        gyro_gated: false,
    },
    Entry {
        name: "kf_alg2",
        kind: Kind::Kalman(&[("alg2", r_pendulum)]),
        gyro_gated: false,
    },
    Entry {
        name: "kf_alg3",
        kind: Kind::Kalman(&[("alg3", r_pendulum)]),
        gyro_gated: false,
    },
    Entry {
        name: "kf_fused",
        kind: Kind::Kalman(&[("accel", r_accel_fused), ("alg2", r_pendulum)]),
        gyro_gated: false,
    },
    Entry {
        name: "ekf",
        kind: Kind::Direct(|s| {
            Box::new(Ekf::new(s.rig.ekf.apply(peers::model_settings(
                &s.params(),
                s.gravity(),
                &s.peers,
            ))))
        }),
        gyro_gated: true,
    },
    Entry {
        name: "ukf",
        kind: Kind::Direct(|s| {
            Box::new(Ukf::new(s.rig.ekf.apply(peers::model_settings(
                &s.params(),
                s.gravity(),
                &s.peers,
            ))))
        }),
        gyro_gated: true,
    },
    Entry {
        name: "madgwick",
        kind: Kind::Direct(|s| Box::new(ahrs_planar::madgwick(s.peers.madgwick_beta))),
        gyro_gated: false,
    },
    Entry {
        name: "mahony",
        kind: Kind::Direct(|s| Box::new(ahrs_planar::mahony(s.peers.mahony[0], s.peers.mahony[1]))),
        gyro_gated: false,
    },
    Entry {
        name: "complementary",
        kind: Kind::Direct(|s| Box::new(Complementary::new(s.peers.complementary))),
        gyro_gated: false,
    },
];

/// The estimator of registry entry `name` on its own, built from `settings` exactly as
/// [`Bank`](super::Bank) builds it (an inversion on a front end of its own); `None` for a name the
/// registry does not know and for the Kalman outputs, which read other outputs.
pub fn build_alone(name: &str, settings: &BankSettings) -> Option<BoxedEstimator> {
    let entry = REGISTRY.iter().find(|e| e.name == name)?;
    match &entry.kind {
        Kind::Direct(build) => Some(build(settings)),
        Kind::Inversion(build) => {
            let (fe, eq) = build(settings);
            Some(Box::new(Alone(Box::new(SharedFrontEnd::new(&fe, &[eq])?))))
        }
        Kind::Kalman(_) => None,
    }
}

/// A front end with one equation as a stand-alone estimator.
struct Alone(Box<SharedFrontEnd<f64>>);

impl Estimator for Alone {
    type Input = Sample<f64>;
    type Output = Estimate<f64>;

    fn update(&mut self, s: &Sample<f64>) -> Estimate<f64> {
        let mut out = [Estimate {
            theta: f64::NAN,
            flags: Flags::SAMPLE_MISSING,
        }];
        self.0.update(s, &mut out);
        out[0]
    }

    fn reset(&mut self) {
        self.0.reset();
    }
}

//! The registry ([`REGISTRY`]): every estimator the bank knows, by output column, with
//! the sensors it needs and how it is built from [`BankSettings`]; and
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

/// One estimator the bank knows.
pub struct Entry {
    /// Output column name (MODEL.md section 5).
    pub name: &'static str,
    /// The sensors it needs.
    pub needs: Inputs,
    /// How it is built.
    pub kind: Kind,
    /// One line for `--help` and reports.
    pub about: &'static str,
    /// Whether it takes the gyro as missing while the gyro clips heavily
    /// ([`pendtilt_core::estimators::clip_gate`]): the model-based filters, which the
    /// biased readings within range would pull off most.
    pub gyro_gated: bool,
}

const PHI: Inputs = Inputs {
    phi: true,
    gyro: false,
    accel: false,
};
const PHI_GYRO: Inputs = Inputs {
    phi: true,
    gyro: true,
    accel: false,
};
const ACCEL_GYRO: Inputs = Inputs {
    phi: false,
    gyro: true,
    accel: true,
};

fn r_accel(k: &KalmanSettings<f64>) -> f64 {
    k.r_accel
}
fn r_pendulum(k: &KalmanSettings<f64>) -> f64 {
    k.r_pendulum
}
fn r_accel_fused(k: &KalmanSettings<f64>) -> f64 {
    k.r_accel_fused.unwrap_or(k.r_accel)
}

/// Every estimator, in output column order.
pub static REGISTRY: &[Entry] = &[
    Entry {
        name: "accel",
        needs: Inputs {
            phi: false,
            gyro: false,
            accel: true,
        },
        kind: Kind::Direct(|s| Box::new(Accel::new(s.rig.accel))),
        about: "accelerometer, Eq (1)",
        gyro_gated: false,
    },
    Entry {
        name: "pendulum",
        needs: PHI,
        kind: Kind::Direct(|_| Box::new(Pendulum::new(PendulumSettings {}))),
        about: "raw pendulum angle",
        gyro_gated: false,
    },
    Entry {
        name: "alg1",
        needs: PHI,
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
        about: "Algorithm 1, Eq (20)",
        gyro_gated: false,
    },
    Entry {
        name: "alg2",
        needs: PHI_GYRO,
        kind: Kind::Inversion(|s| {
            let a = s.rig.alg2_settings();
            (a.front_end, a.equation())
        }),
        about: "Algorithm 2, Eqs (21)-(22)",
        gyro_gated: false,
    },
    Entry {
        name: "alg2_offset",
        needs: PHI_GYRO,
        kind: Kind::Inversion(|s| {
            let a = Alg2Settings {
                pivot_offset: true,
                ..s.rig.alg2_settings()
            };
            (a.front_end, a.equation())
        }),
        about: "Algorithm 2 with the pivot-offset term (not in the paper)",
        gyro_gated: false,
    },
    Entry {
        name: "alg2_dc",
        needs: PHI_GYRO,
        kind: Kind::Inversion(|s| {
            let a = Alg2Settings {
                delay_compensation: true,
                ..s.rig.alg2_settings()
            };
            (a.front_end, a.equation())
        }),
        about: "Algorithm 2 with the differentiator's delay removed by the gyro (not in the paper)",
        gyro_gated: false,
    },
    Entry {
        name: "alg3",
        needs: PHI_GYRO,
        kind: Kind::Inversion(|s| {
            let a = s.rig.alg3_settings();
            (a.front_end, Equation::Alg3(a.gains))
        }),
        about: "Algorithm 3's Eq (30) with the configured K, L, M, N",
        gyro_gated: false,
    },
    Entry {
        name: "kf_accel",
        needs: ACCEL_GYRO,
        kind: Kind::Kalman(&[("accel", r_accel)]),
        about: "Kalman filter fed by the accelerometer (the classic filter)",
        gyro_gated: false,
    },
    Entry {
        name: "kf_alg1",
        needs: PHI_GYRO,
        kind: Kind::Kalman(&[("alg1", r_pendulum)]),
        about: "Kalman filter fed by Algorithm 1",
        gyro_gated: false,
    },
    Entry {
        name: "kf_alg2",
        needs: PHI_GYRO,
        kind: Kind::Kalman(&[("alg2", r_pendulum)]),
        about: "Kalman filter fed by Algorithm 2",
        gyro_gated: false,
    },
    Entry {
        name: "kf_alg3",
        needs: PHI_GYRO,
        kind: Kind::Kalman(&[("alg3", r_pendulum)]),
        about: "Kalman filter fed by Algorithm 3",
        gyro_gated: false,
    },
    Entry {
        name: "kf_fused",
        needs: Inputs::ALL,
        kind: Kind::Kalman(&[("accel", r_accel_fused), ("alg2", r_pendulum)]),
        about: "Kalman filter fed by the accelerometer and Algorithm 2 in turn",
        gyro_gated: false,
    },
    Entry {
        name: "ekf",
        needs: PHI_GYRO,
        kind: Kind::Direct(|s| {
            Box::new(Ekf::new(s.rig.ekf.apply(peers::model_settings(
                &s.params(),
                s.gravity(),
                &s.peers,
            ))))
        }),
        about: "EKF on the pendulum's own dynamics with l12 (the paper's future work)",
        gyro_gated: true,
    },
    Entry {
        name: "ukf",
        needs: PHI_GYRO,
        kind: Kind::Direct(|s| {
            Box::new(Ukf::new(s.rig.ekf.apply(peers::model_settings(
                &s.params(),
                s.gravity(),
                &s.peers,
            ))))
        }),
        about: "UKF on the same model",
        gyro_gated: true,
    },
    Entry {
        name: "madgwick",
        needs: ACCEL_GYRO,
        kind: Kind::Direct(|s| Box::new(ahrs_planar::madgwick(s.peers.madgwick_beta))),
        about: "Madgwick (ahrs crate), planar use, gain from a search on the scooter ride",
        gyro_gated: false,
    },
    Entry {
        name: "mahony",
        needs: ACCEL_GYRO,
        kind: Kind::Direct(|s| Box::new(ahrs_planar::mahony(s.peers.mahony[0], s.peers.mahony[1]))),
        about: "Mahony (ahrs crate), planar use, gains from a search on the scooter ride",
        gyro_gated: false,
    },
    Entry {
        name: "complementary",
        needs: ACCEL_GYRO,
        kind: Kind::Direct(|s| Box::new(Complementary::new(s.peers.complementary))),
        about: "complementary filter of gyro and accelerometer",
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

//! Fuzzing every estimator's `update` with proptest, in f32 and f64.
//!
//! Inputs are sequences of samples whose every field may be an ordinary value, zero, a
//! subnormal, a huge value, an infinity or NaN, and whose time may go forwards by a normal
//! step, by a subnormal or huge step, stand still, go backwards or be missing. Property:
//! no panic, and every output is finite or carries a flag; once an estimator has returned
//! a finite angle it never returns a non-finite one again.
//!
//! CI runs `PROPTEST_CASES` cases (default 256 per type and estimator family, a few
//! seconds in release). A longer run: `PROPTEST_CASES=200000 cargo test --release -p
//! pendtilt --test fuzz_estimators` (recorded in docs/reliability.md).
use pendtilt::core::ekf::{Ekf, ModelSettings, Ukf};
use pendtilt::core::estimators::accel::{Accel, AccelSettings};
use pendtilt::core::estimators::alg1::{Alg1, Alg1Settings};
use pendtilt::core::estimators::alg2::{Alg2, Alg2Settings};
use pendtilt::core::estimators::alg3::{Alg3, Alg3Settings};
use pendtilt::core::estimators::complementary::{Complementary, ComplementarySettings};
use pendtilt::core::estimators::front_end::FrontEndSettings;
use pendtilt::core::estimators::pendulum::{Pendulum, PendulumSettings};
use pendtilt::core::estimators::theta_dd::ThetaDdSource;
use pendtilt::core::kalman::tilt::KalmanOn;
use pendtilt::core::kalman::KalmanSettings;
use pendtilt::core::supervision::{SupervisedAlg3, SupervisedAlg3Settings};
use pendtilt::core::{PendulumParams, PlanarEstimator, Real, Sample};
use proptest::prelude::*;

/// A value of any class an ADC, a driver or a log can produce.
fn value() -> impl Strategy<Value = f64> {
    prop_oneof![
        6 => -2.0..2.0f64,
        2 => -30.0..30.0f64,
        1 => Just(0.0),
        1 => Just(f64::NAN),
        1 => Just(f64::INFINITY),
        1 => Just(f64::NEG_INFINITY),
        1 => prop_oneof![Just(1e300), Just(-1e300), Just(3.0e38), Just(-3.4e38), Just(1e20)],
        1 => prop_oneof![Just(5e-324), Just(1e-310), Just(1e-40), Just(-1e-45)],
        1 => any::<f64>(),
    ]
}

/// The next time step.
fn step() -> impl Strategy<Value = f64> {
    prop_oneof![
        20 => Just(1e-3),
        4 => 1e-4..0.05f64,
        1 => Just(0.0),
        1 => -0.1..0.0f64,
        1 => Just(f64::NAN),
        1 => Just(1e-300),
        1 => Just(1e-9),
        1 => Just(1e6),
        1 => Just(f64::INFINITY),
    ]
}

fn samples() -> impl Strategy<Value = (f64, Vec<(f64, [f64; 4])>)> {
    (
        prop_oneof![Just(0.0), -10.0..1e5f64, Just(1e7)],
        prop::collection::vec((step(), [value(), value(), value(), value()]), 1..120),
    )
}

/// Builds the series: the steps go to the estimators as they are (negative, zero, NaN,
/// huge: what a caller without a [`pendtilt::core::StepGate`] might pass), the first
/// row's step is `dt0` (ignored by a well-behaved estimator unless it is not finite).
fn series<T: Real>(dt0: f64, rows: &[(f64, [f64; 4])]) -> Vec<Sample<T>> {
    rows.iter()
        .enumerate()
        .map(|(k, (dt, v))| Sample {
            dt: T::lit(if k == 0 { dt0 } else { *dt }),
            phi: T::lit(v[0]),
            gyro: T::lit(v[1]),
            ax: T::lit(v[2]),
            ay: T::lit(v[3]),
        })
        .collect()
}

fn check<T: Real, E: PlanarEstimator<T>>(
    name: &str,
    mut e: E,
    s: &[Sample<T>],
) -> Result<(), String> {
    let mut had_finite = false;
    for (k, x) in s.iter().enumerate() {
        let out = e.update(x);
        let finite = out.theta.is_finite();
        if !finite && out.flags.is_empty() {
            return Err(format!(
                "{name}: row {k}: {:?} unflagged from {x:?}",
                out.theta
            ));
        }
        if had_finite && !finite {
            return Err(format!(
                "{name}: row {k}: {:?} ({:?}) after a finite estimate, from {x:?}",
                out.theta, out.flags
            ));
        }
        had_finite |= finite;
    }
    Ok(())
}

fn all_estimators<T: Real>(s: &[Sample<T>]) -> Result<(), String> {
    let p = PendulumParams::<T>::default();
    check("accel", Accel::new(AccelSettings::default()), s)?;
    check(
        "accel_prefiltered",
        Accel::new(AccelSettings {
            prefilter_hz: Some(T::lit(5.0)),
            full_scale: Some(T::lit(39.2)),
        }),
        s,
    )?;
    check("pendulum", Pendulum::new(PendulumSettings {}), s)?;
    check("alg1", Alg1::new(Alg1Settings::from_params(p)), s)?;
    check("alg2", Alg2::<T>::new(Alg2Settings::from_params(p)), s)?;
    check(
        "alg2_offset_eq22",
        Alg2::<T>::new(Alg2Settings {
            pivot_offset: true,
            front_end: FrontEndSettings {
                theta_dd: ThetaDdSource::Window { span: T::lit(0.02) },
                ..FrontEndSettings::from_params(PendulumParams {
                    c: T::lit(0.005),
                    ..p
                })
            },
            delay_compensation: false,
        }),
        s,
    )?;
    check("alg3", Alg3::<T>::new(Alg3Settings::from_params(p)), s)?;
    check(
        "complementary",
        Complementary::new(ComplementarySettings::default()),
        s,
    )?;
    let k = KalmanSettings::default();
    check(
        "kf_accel",
        KalmanOn::new(Accel::new(AccelSettings::default()), T::lit(0.03), k),
        s,
    )?;
    check(
        "kf_alg2",
        KalmanOn::new(
            Alg2::<T>::new(Alg2Settings::from_params(p)),
            T::lit(0.001),
            k,
        ),
        s,
    )?;
    let sup = SupervisedAlg3::<T>::new(SupervisedAlg3Settings::default())
        .map_err(|e| format!("supervised settings: {e:?}"))?;
    check("alg3_supervised", sup, s)?;
    check("ekf", Ekf::<T>::new(ModelSettings::default()), s)?;
    check("ukf", Ukf::<T>::new(ModelSettings::default()), s)?;
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn every_estimator_f64_never_panics_and_flags_non_finite((t0, rows) in samples()) {
        let s = series::<f64>(t0, &rows);
        prop_assert!(all_estimators(&s).is_ok(), "{}", all_estimators(&s).unwrap_err());
    }

    #[test]
    fn every_estimator_f32_never_panics_and_flags_non_finite((t0, rows) in samples()) {
        let s = series::<f32>(t0, &rows);
        prop_assert!(all_estimators(&s).is_ok(), "{}", all_estimators(&s).unwrap_err());
    }
}

/// Hand-picked sequences the generator may take long to hit.
#[test]
fn hand_picked_sequences() {
    let cases: &[&[(f64, [f64; 4])]] = &[
        // Starting with nothing, then good data.
        &[(0.0, [f64::NAN; 4]), (1e-3, [0.1, 0.0, 1.0, 9.7])],
        // Time standing still, then going back, then on.
        &[
            (0.0, [0.1, 0.0, 1.0, 9.7]),
            (0.0, [0.1, 0.0, 1.0, 9.7]),
            (-1.0, [0.1, 0.0, 1.0, 9.7]),
            (2.0, [0.1, 0.0, 1.0, 9.7]),
        ],
        // A subnormal time step: phi'' would overflow without the checks.
        &[
            (0.0, [0.1, 0.0, 1.0, 9.7]),
            (5e-324, [0.2, 1.0, 1.0, 9.7]),
            (1e-3, [0.1, 0.0, 1.0, 9.7]),
        ],
        // Huge values on every channel.
        &[
            (0.0, [1e300, -1e300, 1e300, -1e300]),
            (1e-3, [-1e300, 1e300, -1e300, 1e300]),
            (1e-3, [0.1, 0.0, 1.0, 9.7]),
        ],
        // Accelerometer at exactly zero (atan2(0, 0)).
        &[(0.0, [0.0, 0.0, 0.0, 0.0]), (1e-3, [0.0, 0.0, 0.0, 0.0])],
    ];
    for rows in cases {
        let rows: Vec<_> = rows.to_vec();
        // Times are cumulative from t0 = 0 with the first step as given.
        all_estimators(&series::<f64>(0.0, &rows)).unwrap();
        all_estimators(&series::<f32>(0.0, &rows)).unwrap();
        all_estimators(&series::<f64>(1e7, &rows)).unwrap();
        all_estimators(&series::<f32>(1e7, &rows)).unwrap();
    }
}

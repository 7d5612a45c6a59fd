//! RK4 convergence of the whole simulator: the error of beta falls about 16-fold each time
//! the step is halved (substeps doubled), with the body tilting, vibrating and l12 != 0.

use pendtilt::sim::planar::motion::{Motion, Sine};
use pendtilt::sim::planar::vibration::{AngularHarmonic, Harmonic};
use pendtilt::sim::planar::{simulate, Scenario};

fn scenario(substeps: u32) -> Scenario {
    let mut s = Scenario::with_motion(
        Motion::Sine(Sine {
            amplitude: 0.4,
            frequency: 2.0,
            ..Sine::default()
        }),
        2.0,
    );
    s.rate = 100.0;
    s.substeps = substeps;
    s.pendulum.pivot_offset = 0.1;
    s.sensors = s.sensors.ideal();
    s.vibration.harmonics = vec![Harmonic {
        frequency: 7.0,
        amplitude: 3.0,
        axis: [0.6, 0.8],
        phase: 0.4,
    }];
    s.vibration.angular = vec![AngularHarmonic {
        frequency: 9.0,
        amplitude: 0.02,
        phase: 0.1,
    }];
    s
}

fn beta(substeps: u32) -> Vec<f64> {
    simulate(&scenario(substeps), 1)
        .unwrap()
        .iter()
        .map(|r| r.truth.beta)
        .collect()
}

#[test]
fn error_falls_sixteen_fold_per_halving_of_the_step() {
    let reference = beta(512);
    let err = |n: u32| {
        beta(n)
            .iter()
            .zip(&reference)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max)
    };
    let e: Vec<f64> = [2, 4, 8, 16].iter().map(|&n| err(n)).collect();
    for w in e.windows(2) {
        let ratio = w[0] / w[1];
        assert!(
            (12.0..20.0).contains(&ratio),
            "errors {e:?}: ratio {ratio} is not about 16"
        );
    }
    // 16 steps per 100 Hz sample (the step of the default 2 per 1 kHz sample, within 20 %)
    // is far below any sensor's resolution.
    assert!(e[3] < 1e-6, "{e:?}");
}

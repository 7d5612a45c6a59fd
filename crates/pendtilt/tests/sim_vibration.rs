//! Vibration reaches the sensors as it should: a deterministic harmonic arrives at the
//! accelerometer with its amplitude and phase, and at the pendulum attenuated as the linear
//! transfer function predicts; broadband vibration has its RMS; angular vibration reaches
//! the gyro.

use pendtilt::sim::planar::motion::{Motion, Still};
use pendtilt::sim::planar::vibration::{AngularHarmonic, Broadband, Harmonic};
use pendtilt::sim::planar::{simulate, Scenario};
use std::f64::consts::{PI, TAU};

mod common;
use common::{fit_sine, ideal};

fn still_clean(duration: f64) -> Scenario {
    ideal(Motion::Still(Still { angle: 0.0 }), duration)
}

fn wrap(a: f64) -> f64 {
    (a + PI).rem_euclid(TAU) - PI
}

#[test]
fn harmonic_reaches_accelerometer_and_pendulum_as_predicted() {
    let (f, amp, phase) = (20.0, 2.0, 0.7);
    let mut s = still_clean(6.0);
    s.vibration.harmonics = vec![
        Harmonic {
            frequency: f,
            amplitude: amp,
            axis: [1.0, 0.0],
            phase,
        },
        // A vertical harmonic at another frequency: it must not leak into ax.
        Harmonic {
            frequency: 33.0,
            amplitude: 1.0,
            axis: [0.0, 1.0],
            phase: 0.2,
        },
    ];
    let rows = simulate(&s, 1).unwrap();
    let w = TAU * f;
    let tail = |g: &dyn Fn(&pendtilt::sim::planar::SimRow) -> f64| -> Vec<(f64, f64)> {
        rows.iter()
            .filter(|r| r.t >= 4.0)
            .map(|r| (r.t, g(r)))
            .collect()
    };
    // The accelerometer (at P2, body still and level) reads the vibration itself.
    let (a, p, c) = fit_sine(&tail(&|r| r.ax), w);
    assert!((a - amp).abs() < 1e-9, "ax amplitude {a}");
    assert!(wrap(p - phase).abs() < 1e-9, "ax phase {p}");
    assert!(c.abs() < 1e-9);
    let (a, p, c) = fit_sine(&tail(&|r| r.ay), TAU * 33.0);
    assert!(
        (a - 1.0).abs() < 1e-9 && wrap(p - 0.2).abs() < 1e-9,
        "ay {a} {p}"
    );
    assert!((c - s.pendulum.gravity).abs() < 1e-9);

    // The pendulum: I beta'' + C beta' + m g l beta = -m l a_x, phi = -beta, so
    // phi / a_x = m l / (m g l - I w^2 + i C w).
    let pp = s.physical();
    let mgl = pp.mass * pp.gravity * pp.length;
    let (re, im) = (mgl - pp.inertia * w * w, pp.damping * w);
    let gain = pp.mass * pp.length / re.hypot(im);
    let lag = -im.atan2(re);
    let (a, p, _) = fit_sine(&tail(&|r| r.truth.phi), w);
    assert!(
        (a / (gain * amp) - 1.0).abs() < 0.01,
        "phi amplitude {a} vs {}",
        gain * amp
    );
    assert!(wrap(p - (phase + lag)).abs() < 0.01, "phi phase {p}");
    // It is strongly attenuated: 2 m/s^2 at 20 Hz moves it by about 0.14 deg.
    assert!(a < 0.003, "{a}");
}

#[test]
fn broadband_vibration_has_its_rms_and_band() {
    let mut s = still_clean(30.0);
    s.vibration.broadband = Broadband {
        rms: [1.5, 2.5],
        band: [5.0, 200.0],
    };
    let rows = simulate(&s, 3).unwrap();
    let n = rows.len() as f64;
    let g = s.pendulum.gravity;
    let rx = (rows.iter().map(|r| r.truth.a_p1[0].powi(2)).sum::<f64>() / n).sqrt();
    let ry = (rows.iter().map(|r| r.truth.a_p1[1].powi(2)).sum::<f64>() / n).sqrt();
    assert!((rx / 1.5 - 1.0).abs() < 0.05, "x rms {rx}");
    assert!((ry / 2.5 - 1.0).abs() < 0.05, "y rms {ry}");
    // The accelerometer sees it on top of gravity.
    let mean_ay = rows.iter().map(|r| r.ay).sum::<f64>() / n;
    assert!((mean_ay - g).abs() < 0.1, "{mean_ay}");
    // The 2nd-order high-pass at 5 Hz leaves little below 1 Hz: a 1 s moving average of
    // a_x is much smaller than the RMS.
    let k = s.rate as usize;
    let avg: Vec<f64> = rows
        .chunks(k)
        .map(|c| c.iter().map(|r| r.truth.a_p1[0]).sum::<f64>() / k as f64)
        .collect();
    let avg_rms = (avg.iter().map(|x| x * x).sum::<f64>() / avg.len() as f64).sqrt();
    assert!(avg_rms < 0.05 * rx, "{avg_rms}");
    // And the pendulum, a 2.2 Hz low-pass, barely moves.
    let phi_rms = (rows.iter().map(|r| r.truth.phi.powi(2)).sum::<f64>() / n).sqrt();
    let accel_angle_rms = (rows.iter().map(|r| r.ax.atan2(r.ay).powi(2)).sum::<f64>() / n).sqrt();
    assert!(
        phi_rms < accel_angle_rms / 5.0,
        "{phi_rms} vs {accel_angle_rms}"
    );
}

#[test]
fn angular_vibration_reaches_the_gyro_and_tilt() {
    let (f, amp, phase) = (40.0, 1e-3, 0.3);
    let mut s = still_clean(2.0);
    s.vibration.angular = vec![AngularHarmonic {
        frequency: f,
        amplitude: amp,
        phase,
    }];
    let rows = simulate(&s, 1).unwrap();
    let w = TAU * f;
    let g: Vec<(f64, f64)> = rows.iter().map(|r| (r.t, r.gyro)).collect();
    let (a, p, _) = fit_sine(&g, w);
    assert!((a - amp * w).abs() < 1e-9, "gyro amplitude {a}");
    assert!(wrap(p - (phase + PI / 2.0)).abs() < 1e-9);
    let th: Vec<(f64, f64)> = rows.iter().map(|r| (r.t, r.theta)).collect();
    let (a, p, _) = fit_sine(&th, w);
    assert!((a - amp).abs() < 1e-12 && wrap(p - phase).abs() < 1e-9);
}

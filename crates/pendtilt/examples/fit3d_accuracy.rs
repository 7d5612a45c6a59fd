//! The 3-D fit's accuracy on simulated logs: a rig, a scenario, the fitted parameters
//! against the rig's own, per target.
//!
//! `cargo run --release -p pendtilt --example fit3d_accuracy -- [SCENARIO] [SECONDS] [SEEDS]`
//! (defaults scooter3d, 60, 1-3); the rigs are MODEL.md 7.6's and four others (1.2 Hz at
//! zeta 0.15 with a 5 mm pivot offset and consumer-grade gyro noise, a ring, an asymmetric
//! pendulum, an accelerometer away from P1). Environment: `FIT3D_NOISECORR=1` gives the fit
//! the sensors' noise densities (as `--accel-noise`, `--gyro-noise` do); `FIT3D_RIGS=a,b`
//! runs only those rigs; `FIT3D_CZ=X` sets the c_z sensitivity threshold; `FIT3D_NOVIB=1`,
//! `FIT3D_IDEAL=1` and `FIT3D_NOISE=gyro,accel,enc` take the vibration or sensor errors out.
use pendtilt::fit::cardan::{fit_cardan, Fit3dSettings, Log3dColumns, NoiseDensities, NAMES};
use pendtilt::fit::Target;
use pendtilt::sim::spatial::{Pendulum3d, Scenario3d};

/// A pendulum of natural frequency `hz` and damping ratio `zeta` on both axes (MODEL.md
/// 7.6's mass and length).
fn rig(hz: f64, zeta: f64) -> Pendulum3d {
    let p = Pendulum3d::default();
    let mgl = p.mgl();
    let inertia = mgl / (std::f64::consts::TAU * hz).powi(2);
    let damping = zeta * 2.0 * (inertia * mgl).sqrt();
    Pendulum3d {
        inertia_xx: inertia,
        inertia_yy: inertia,
        damping_x: damping,
        damping_y: damping,
        ..p
    }
}

/// A rig under test: its name, pendulum, accelerometer position \[m\] and the factor on
/// the scenario's gyro noise.
type Rig = (&'static str, Pendulum3d, [f64; 3], f64);

/// The rigs compared: MODEL.md 7.6's and the four the module documentation names.
fn rigs() -> Vec<Rig> {
    vec![
        ("default", Pendulum3d::default(), [0.0; 3], 1.0),
        (
            "1.2Hz_z0.15_5mm_consumer",
            Pendulum3d {
                pivot_offset: [0.0, 0.0, 0.005],
                ..rig(1.2, 0.15)
            },
            [0.0; 3],
            10.0,
        ),
        ("1.2Hz_z0.15", rig(1.2, 0.15), [0.0; 3], 1.0),
        (
            "1.2Hz_z0.15_5mm",
            Pendulum3d {
                pivot_offset: [0.0, 0.0, 0.005],
                ..rig(1.2, 0.15)
            },
            [0.0; 3],
            1.0,
        ),
        ("1.2Hz_z0.15_consumer", rig(1.2, 0.15), [0.0; 3], 10.0),
        (
            "ring",
            Pendulum3d {
                ring_inertia: 4e-5,
                pivot_offset: [0.0, 0.0, -0.01],
                ..rig(1.8, 0.25)
            },
            [0.0; 3],
            1.0,
        ),
        (
            "asym_3Hz",
            Pendulum3d {
                inertia_yy: rig(3.0, 0.3).inertia_xx * 0.8,
                ..rig(3.0, 0.4)
            },
            [0.0; 3],
            3.0,
        ),
        ("accel_at", rig(2.5, 0.2), [0.02, -0.01, 0.03], 1.0),
    ]
}

/// `FIT3D_NOISE=gyro,accel,enc`: ideal sensors but for the errors named, which keep the
/// scenario's own.
fn keep_only_noise(s: &mut Scenario3d, keep: &str) {
    let full = s.sensors.clone();
    s.sensors = s.sensors.clone().ideal();
    for k in keep.split(',') {
        match k {
            "gyro" => {
                s.sensors.gyro_noise_density = full.gyro_noise_density;
                s.sensors.gyro_bias_walk = full.gyro_bias_walk;
                s.sensors.gyro_bias = full.gyro_bias;
            }
            "accel" => {
                s.sensors.accel_noise_density = full.accel_noise_density;
                s.sensors.accel_bias = full.accel_bias;
            }
            "enc" => {
                s.sensors.encoder_noise = full.encoder_noise;
                s.sensors.encoder_bits = full.encoder_bits;
            }
            _ => panic!("FIT3D_NOISE: gyro, accel, enc"),
        }
    }
}

/// The named scenario on `rig`, `seconds` long, with the environment's changes to its
/// vibration and sensors.
fn scenario_on(scenario: &str, seconds: f64, seed: u64, rig: &Rig) -> Scenario3d {
    let (_, p, accel_at, gyro_scale) = rig;
    let mut s = Scenario3d::named(scenario, seed).expect("scenario");
    s.duration = seconds;
    s.rig.pendulum3d = *p;
    s.rig.mounting.accel_at = *accel_at;
    if std::env::var("FIT3D_NOVIB").is_ok() {
        s.motion = s.motion.without_vibration();
    }
    if std::env::var("FIT3D_IDEAL").is_ok() {
        s.sensors = s.sensors.clone().ideal();
    }
    if let Ok(keep) = std::env::var("FIT3D_NOISE") {
        keep_only_noise(&mut s, &keep);
    }
    s.sensors.gyro_noise_density *= gyro_scale;
    s.sensors.gyro_bias_walk *= gyro_scale;
    s
}

/// The fit's settings for `target`, with the sensors' densities of `s` when
/// `FIT3D_NOISECORR` is set and the c_z threshold of `FIT3D_CZ`.
fn settings(target: Target, s: &Scenario3d) -> Fit3dSettings {
    let noise = std::env::var("FIT3D_NOISECORR")
        .is_ok()
        .then_some(NoiseDensities {
            accel: [s.sensors.accel_noise_density; 2],
            gyro: [s.sensors.gyro_noise_density; 2],
        });
    let mut settings = Fit3dSettings {
        target,
        noise,
        ..Fit3dSettings::default()
    };
    if let Ok(v) = std::env::var("FIT3D_CZ") {
        settings.min_offset_sensitivity = v.parse().expect("FIT3D_CZ");
    }
    settings
}

/// Each fitted parameter's error against `p`'s own: a, b in %, c_z in mm.
fn errors(fitted: &[f64], p: &Pendulum3d) -> String {
    let truth = p.normalised();
    let want = [
        truth.a_x,
        truth.a_y,
        truth.b_x + truth.b_ring,
        truth.b_y,
        truth.c[2],
    ];
    let errs: Vec<String> = (0..5)
        .map(|j| {
            if j == 4 {
                format!("{}={:+.2}mm", NAMES[j], (fitted[4] - want[4]) * 9.80665e3)
            } else {
                format!("{}={:+.2}%", NAMES[j], 100.0 * (fitted[j] / want[j] - 1.0))
            }
        })
        .collect();
    errs.join(" ")
}

/// Fits one simulated log of `rig` against `target` and prints a line: the errors, the
/// offsets, the cost, the iterations and the time taken.
fn fit_one(target: Target, rig: &Rig, scenario: &str, seconds: f64, seed: u64) {
    let (name, p, accel_at, _) = rig;
    let s = scenario_on(scenario, seconds, seed, rig);
    let rows: Vec<_> = s.run(seed).expect("run").map(|(_, r)| r).collect();
    let log = Log3dColumns::from_rows(&rows);
    let settings = settings(target, &s);
    let start = pendtilt_core::spatial::cardan::CardanParams::default();
    let t0 = std::time::Instant::now();
    match fit_cardan(&log, &start, *accel_at, &settings, |_| {}) {
        Ok(r) => println!(
            "{target:?} {name} seed {seed}: {} off [{:.3},{:.3}]mrad rms {:.3e} it {} {:?} {:.2}s cz_sens {:.2e}",
            errors(r.params.as_slice(), p),
            r.params[5] * 1e3,
            r.params[6] * 1e3,
            r.cost,
            r.iterations.len() - 1,
            r.stop,
            t0.elapsed().as_secs_f64(),
            r.offset_sensitivity,
        ),
        Err(e) => println!("{target:?} {name} seed {seed}: {e}"),
    }
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let scenario = args.first().map_or("scooter3d", |s| s.as_str()).to_string();
    let seconds: f64 = args.get(1).map_or(60.0, |s| s.parse().expect("seconds"));
    let seeds: Vec<u64> = match args.get(2) {
        Some(s) => s.split(',').map(|x| x.parse().expect("seed")).collect(),
        None => vec![1, 2, 3],
    };
    let rigs = rigs();
    let only = std::env::var("FIT3D_RIGS").unwrap_or_default();
    for target in [Target::Truth, Target::Gyro] {
        for rig in &rigs {
            if !only.is_empty() && !only.split(',').any(|o| o == rig.0) {
                continue;
            }
            for &seed in &seeds {
                fit_one(target, rig, &scenario, seconds, seed);
            }
        }
    }
}

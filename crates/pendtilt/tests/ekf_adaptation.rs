//! The planar ekf's adaptation (`ModelSettings::adaptation`, docs/adaptation.md): the
//! pendulum's forcing follows the encoder's innovations, so the same defaults serve a rig
//! shaken far harder than the default scooter and a quiet one; the rig file's
//! `[ekf] adapt` switches it. Prints the measured figures with `-- --nocapture`.
mod ekf_common;
use ekf_common::*;
use pendtilt::config::RigConfig;
use pendtilt::core::ekf::{Ekf, ModelSettings, Ukf};
use pendtilt::core::Estimator;
use pendtilt::sim::planar::Scenario;

/// RMS error \[deg\] after [`SKIP`] and the last forcing factor of `e` over `r`.
fn run(e: &mut Ekf<f64>, r: &Ride) -> (f64, f64) {
    let est: Vec<f64> = r.samples.iter().map(|s| e.update(s).theta).collect();
    let n = est.len() - SKIP;
    let ss: f64 = est[SKIP..]
        .iter()
        .zip(&r.truth[SKIP..])
        .map(|(a, b)| (a - b).powi(2))
        .sum();
    ((ss / n as f64).sqrt().to_degrees(), e.forcing_factor())
}

/// The scooter ride with its broadband vibration scaled by `k` (1: the defaults' scooter).
fn shaken(k: f64, seconds: f64) -> Ride {
    let mut sc = scooter(seconds);
    for r in &mut sc.vibration.broadband.rms {
        *r *= k;
    }
    for h in &mut sc.vibration.harmonics {
        h.amplitude *= k;
    }
    ride(&sc, 2)
}

/// A quiet rig: the scooter's slow manoeuvres on a floor that does not vibrate.
fn quiet(seconds: f64) -> Ride {
    let mut sc = scooter(seconds);
    sc.vibration = Default::default();
    ride(&sc, 2)
}

/// The best fixed forcing (the defaults' density times 10^k, k = -4..=3) on `r` and its
/// RMS \[deg\]: what a rig's own figure, known in advance, would give.
fn best_fixed(r: &Ride) -> (f64, f64) {
    let base = ModelSettings::from_params(r.params, r.gravity).fixed();
    (-4..=3)
        .map(|k| {
            let f = 10f64.powi(k);
            let mut s = base;
            s.process.pendulum *= f;
            (f, run(&mut Ekf::new(s), r).0)
        })
        .fold(
            (f64::NAN, f64::INFINITY),
            |b, x| if x.1 < b.1 { x } else { b },
        )
}

#[test]
fn the_factor_rises_on_a_shaken_rig_falls_on_a_quiet_one_and_stays_on_the_scooter() {
    let defaults = |r: &Ride| ModelSettings::from_params(r.params, r.gravity);
    let loud = shaken(5.0, 30.0);
    let (rms_loud, f_loud) = run(&mut Ekf::new(defaults(&loud)), &loud);
    let calm = quiet(30.0);
    let (rms_calm, f_calm) = run(&mut Ekf::new(defaults(&calm)), &calm);
    let plain = shaken(1.0, 30.0);
    let (rms_plain, f_plain) = run(&mut Ekf::new(defaults(&plain)), &plain);
    println!(
        "forcing factor after 30 s: vibration x5 {f_loud:.3} ({rms_loud:.4} deg RMS), \
         scooter {f_plain:.3} ({rms_plain:.4}), no vibration {f_calm:.4} ({rms_calm:.4})"
    );
    assert!(f_loud > 5.0, "{f_loud}");
    assert!(f_calm < 0.1, "{f_calm}");
    assert!(f_calm < f_plain && f_plain < f_loud);
    // The ukf shares the estimator, and the adaptation with it.
    let mut u = Ukf::new(defaults(&loud));
    for s in &loud.samples {
        u.update(s);
    }
    assert!(u.forcing_factor() > 5.0, "{}", u.forcing_factor());
}

/// A quiet rig, far below the defaults' scooter: at the defaults the ekf comes within 1.5x
/// of the best fixed forcing (measured 0.0068 against 0.0047 deg; 0.0436 fixed). The
/// shaken rigs are printed, not asserted: there the factor overshoots (docs/adaptation.md).
#[test]
fn at_defaults_a_quiet_rig_comes_near_its_best_fixed_forcing() {
    let shaken_rigs = [2.0, 3.0, 5.0].map(|k| (k, shaken(k, 40.0)));
    let quiet_rig = quiet(40.0);
    let rigs = shaken_rigs
        .iter()
        .map(|(k, r)| (format!("vibration x{k}"), r))
        .chain(std::iter::once(("no vibration".to_string(), &quiet_rig)));
    for (name, r) in rigs {
        let st = ModelSettings::from_params(r.params, r.gravity);
        let (adaptive, _) = run(&mut Ekf::new(st), r);
        let (fixed, _) = run(&mut Ekf::new(st.fixed()), r);
        let (factor, best) = best_fixed(r);
        println!(
            "{name}: defaults {fixed:.4} deg RMS fixed, {adaptive:.4} adaptive; best fixed \
             forcing (x{factor:.0e}) {best:.4}"
        );
        if name == "no vibration" {
            assert!(adaptive < 1.5 * best, "{name}: {adaptive} against {best}");
            assert!(adaptive < 0.5 * fixed, "{name}: {adaptive} against {fixed}");
        }
    }
}

#[test]
fn the_adapt_key_round_trips_through_the_rig_file_and_reaches_the_filter() {
    let mut rig = RigConfig::default();
    assert_eq!(rig.ekf.adapt, None);
    let on = rig.ekf.apply(ModelSettings::default());
    assert!(on.adaptation.enabled);
    rig.ekf.adapt = Some(false);
    let text = rig.to_toml_string();
    assert!(text.contains("adapt = false"), "{text}");
    let back = RigConfig::from_toml_str(&text, "test").unwrap();
    assert_eq!(back.ekf, rig.ekf);
    let off = back.ekf.apply(ModelSettings::default());
    assert!(!off.adaptation.enabled);
    assert_eq!(off, ModelSettings::default().fixed());
}

#[test]
fn without_the_adaptation_the_figures_stay_the_settings() {
    // On the shaken rig, where the adaptation moves both: the factor stays 1 and the
    // encoder's variance the settings'; the estimates differ from the adaptive filter's.
    let r = shaken(5.0, 10.0);
    let st = ModelSettings::from_params(r.params, r.gravity);
    let mut fixed = Ekf::new(st.fixed());
    let mut adaptive = Ekf::new(st);
    let mut differ = false;
    for s in &r.samples {
        let (a, b) = (fixed.update(s), adaptive.update(s));
        assert_eq!(fixed.forcing_factor(), 1.0);
        assert_eq!(fixed.encoder_variance(), st.encoder_variance());
        differ |= a.theta != b.theta;
    }
    assert!(differ);
    assert!(adaptive.encoder_variance() >= st.encoder_variance());
}

/// A noisier encoder than the settings say (0.05 deg white noise on a 12-bit one): the
/// measured second difference floors its variance, so the noise is not taken for forcing.
#[test]
fn a_noisy_encoder_is_measured_not_taken_for_forcing() {
    let mut sc: Scenario = scooter(20.0);
    sc.sensors.encoder.noise = 0.05f64.to_radians();
    let r = ride(&sc, 2);
    let st = ModelSettings::from_params(r.params, r.gravity);
    let mut e = Ekf::new(st);
    let (rms, f) = run(&mut e, &r);
    let sd = e.encoder_variance().sqrt().to_degrees();
    println!("0.05 deg encoder noise: measured {sd:.4} deg, factor {f:.3}, {rms:.4} deg RMS");
    assert!((0.04..0.07).contains(&sd), "{sd}");
    assert!(f < 5.0, "{f}");
}

/// The defaults' own rig, the scooter ride (l12 = 0.2 m, 60 s, seeds 1-3): the adaptation
/// costs it nothing.
#[test]
fn on_the_defaults_scooter_the_adaptation_costs_nothing() {
    for seed in 1..=3 {
        let r = ride(&scooter(60.0), seed);
        let st = ModelSettings::from_params(r.params, r.gravity);
        let (adaptive, f) = run(&mut Ekf::new(st), &r);
        let (fixed, _) = run(&mut Ekf::new(st.fixed()), &r);
        println!(
            "scooter seed {seed}: {adaptive:.4} deg RMS adaptive (factor {f:.3}), {fixed:.4} fixed"
        );
        assert!(
            adaptive < 1.05 * fixed,
            "seed {seed}: {adaptive} against {fixed}"
        );
    }
}

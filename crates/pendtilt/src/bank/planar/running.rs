//! The running bank ([`Bank`]): the registry's entries that a log's inputs allow, run
//! side by side one sample at a time, restarted after long sensor gaps.
use pendtilt_core::estimators::clip_gate::ClipGate;
use pendtilt_core::estimators::front_end::SharedFrontEnd;
use pendtilt_core::kalman::tilt::UNUSABLE;
use pendtilt_core::kalman::TiltKalman;
use pendtilt_core::{Estimate, Flags, Sample};

use super::registry::Entry;
use super::{BankSettings, BoxedEstimator, Inputs, Kind, REGISTRY};
use crate::sensors::{GapEnd, GapWatch, Sensor};

enum Slot {
    Direct(BoxedEstimator),
    /// Several consecutive outputs from one front end.
    Shared(Box<SharedFrontEnd<f64>>),
    Kalman {
        kf: TiltKalman<f64>,
        sources: Vec<(usize, f64)>,
    },
}

/// An estimator that was not run, and why.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Skipped {
    /// Its name.
    pub name: &'static str,
    /// The sensors the log lacks.
    pub lacking: Vec<&'static str>,
}

/// A restart of estimators after a long gap in one or more sensors.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Restart {
    /// The sensors that came back after the gap.
    pub sensors: Inputs,
    /// The longest of their gaps \[s\].
    pub gap: f64,
    /// How many outputs were restarted.
    pub outputs: usize,
}

/// The estimators that a log's inputs allow, run side by side.
pub struct Bank {
    names: Vec<&'static str>,
    /// The sensors each output reads (its registry entry's needs).
    needs: Vec<Inputs>,
    slots: Vec<Slot>,
    /// The sensors each slot reads (the union over its outputs).
    slot_needs: Vec<Inputs>,
    inputs: Inputs,
    settings: BankSettings,
    /// The time since each sensor's last reading, for the restart rule.
    gaps: GapWatch,
    restart: Option<Restart>,
    skipped: Vec<Skipped>,
    /// Outputs not asked for by `only` but read by one that was: (output, reader).
    pulled: Vec<(&'static str, &'static str)>,
    measurements: Vec<(f64, f64)>,
    blank: Estimate<f64>,
    /// The gyro full scale the estimators were last given (the rig's, or a clip's level).
    gyro_full_scale: Option<f64>,
    /// Whether each slot takes the gyro as missing while it clips heavily
    /// ([`super::registry::Entry::gyro_gated`]), and the gate that says when.
    gated: Vec<bool>,
    clip_gate: ClipGate<f64>,
}

/// An error for a name in `only` (as given to [`Bank::new`]) that the registry does not
/// know, with the name meant when it is one (another case, a 3-D estimator).
fn check_only(only: &[String]) -> Result<(), String> {
    for n in only {
        if !REGISTRY.iter().any(|e| e.name == n.trim()) {
            let known: Vec<_> = REGISTRY.iter().map(|e| e.name).collect();
            let spatial = crate::catalogue::listing(n.trim())
                .is_some_and(|l| l.model == crate::catalogue::Model::Spatial);
            let hint = if spatial {
                "; it is a 3-D estimator, and this log is planar".to_string()
            } else if let Some(e) = REGISTRY
                .iter()
                .find(|e| e.name.eq_ignore_ascii_case(n.trim()))
            {
                format!("; did you mean `{}`?", e.name)
            } else {
                String::new()
            };
            return Err(format!(
                "unknown estimator `{n}`{hint} (known: {})",
                known.join(", ")
            ));
        }
    }
    Ok(())
}

impl std::fmt::Debug for Bank {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Bank")
            .field("names", &self.names)
            .field("skipped", &self.skipped)
            .finish_non_exhaustive()
    }
}

impl Bank {
    /// Every registry entry whose inputs are in `inputs` (and, if `only` is given, whose
    /// name is in it). Errors on a name in `only` that the registry does not know.
    pub fn new(
        settings: &BankSettings,
        inputs: Inputs,
        only: Option<&[String]>,
    ) -> Result<Self, String> {
        if let Some(only) = only {
            check_only(only)?;
        }
        // `--only "alg2, kf_alg2"`: the space after the comma is not part of a name.
        let asked = |name: &str| only.is_none_or(|o| o.iter().any(|n| n.trim() == name));
        // A Kalman output asked for brings the outputs it reads (their columns are written
        // too: hidden outputs would complicate the one-row contract).
        let mut pulled: Vec<(&'static str, &'static str)> = Vec::new();
        for e in REGISTRY.iter().filter(|e| asked(e.name)) {
            if let Kind::Kalman(sources) = &e.kind {
                for (src, _) in sources.iter() {
                    if !asked(src) && !pulled.iter().any(|(p, _)| p == src) {
                        pulled.push((src, e.name));
                    }
                }
            }
        }
        let wanted = |name: &str| asked(name) || pulled.iter().any(|(p, _)| *p == name);
        let mut bank = Bank {
            names: Vec::new(),
            needs: Vec::new(),
            slots: Vec::new(),
            slot_needs: Vec::new(),
            inputs,
            settings: settings.clone(),
            gaps: GapWatch::new(),
            restart: None,
            skipped: Vec::new(),
            pulled: pulled.clone(),
            measurements: Vec::with_capacity(4),
            blank: Estimate {
                theta: f64::NAN,
                flags: Flags::SAMPLE_MISSING,
            },
            gyro_full_scale: settings.rig.gyro.checked_full_scale(),
            gated: Vec::new(),
            clip_gate: ClipGate::new(),
        };
        for e in REGISTRY.iter().filter(|e| wanted(e.name)) {
            bank.add(e, settings)?;
        }
        Ok(bank)
    }

    /// Adds registry entry `e`, or says it was skipped for the sensors it lacks. One pass
    /// over the registry: each entry's slot depends on the slots built before it (a shared
    /// front end, a Kalman filter's sources).
    fn add(&mut self, e: &Entry, settings: &BankSettings) -> Result<(), String> {
        let inputs = self.inputs;
        if !inputs.covers(e.needs()) {
            self.skipped.push(Skipped {
                name: e.name,
                lacking: inputs.lacking(e.needs()),
            });
            return Ok(());
        }
        let slot = match &e.kind {
            Kind::Direct(build) => Slot::Direct(build(settings)),
            Kind::Inversion(build) => {
                let (fe, eq) = build(settings);
                if let Some(Slot::Shared(front)) = self.slots.last_mut() {
                    if *front.settings() == fe && front.push(eq) {
                        self.names.push(e.name);
                        self.needs.push(e.needs());
                        if let Some(n) = self.slot_needs.last_mut() {
                            *n = n.union(e.needs());
                        }
                        return Ok(());
                    }
                }
                match SharedFrontEnd::new(&fe, &[eq]) {
                    Some(front) => Slot::Shared(Box::new(front)),
                    None => return Err(format!("`{}`: cannot build its front end", e.name)),
                }
            }
            Kind::Kalman(sources) => {
                let kalman = settings.rig.kalman_settings();
                let mut idx = Vec::new();
                for (src, r) in sources.iter() {
                    // Its sources come first in the registry and were pulled in: a
                    // source is missing only when the log lacks its inputs.
                    let Some(i) = self.names.iter().position(|n| n == src) else {
                        self.skipped.push(Skipped {
                            name: e.name,
                            lacking: inputs.lacking(e.needs()),
                        });
                        return Ok(());
                    };
                    idx.push((i, r(&kalman)));
                }
                Slot::Kalman {
                    kf: TiltKalman::new(kalman),
                    sources: idx,
                }
            }
        };
        self.names.push(e.name);
        self.needs.push(e.needs());
        self.slots.push(slot);
        self.slot_needs.push(e.needs());
        self.gated.push(e.gyro_gated);
        Ok(())
    }

    /// The output names, in column order.
    pub fn names(&self) -> &[&'static str] {
        &self.names
    }

    /// The estimators not run, with the sensors they lacked.
    pub fn skipped(&self) -> &[Skipped] {
        &self.skipped
    }

    /// The outputs `only` did not name but that an output it named reads, each with the
    /// first reader: `(alg2, kf_alg2)` for `--only kf_alg2`.
    pub fn pulled_in(&self) -> &[(&'static str, &'static str)] {
        &self.pulled
    }

    /// The settings the bank was built from.
    pub fn settings(&self) -> &BankSettings {
        &self.settings
    }

    /// The restart the last [`Bank::update`] did before running the estimators, if any.
    pub fn restarted(&self) -> Option<Restart> {
        self.restart
    }

    /// Adds [`Flags::IMPLAUSIBLE`] to every output in `out` that reads one of `sensors`
    /// (the sensors whose readings of this row were impossible and read as missing).
    pub fn flag_implausible(&self, sensors: Inputs, out: &mut [Estimate<f64>]) {
        if sensors.is_empty() {
            return;
        }
        for (e, need) in out.iter_mut().zip(&self.needs) {
            if need.intersects(sensors) {
                e.flags |= Flags::IMPLAUSIBLE;
            }
        }
    }

    /// Restarts the estimators reading a sensor that comes back on `sample` after a gap
    /// longer than the restart gap, so that they start afresh from this reading instead of
    /// resuming from a state the gap has made stale.
    fn restart_after_gaps(&mut self, sample: &Sample<f64>) {
        self.restart = None;
        // Only the sensors some estimator reads: a gap of another restarts nothing.
        let good = Inputs::from_fn(|s| self.inputs.has(s) && sample.complete(s));
        let restart_gap = self.settings.restart_gap;
        let Some(GapEnd { sensors, gap }) = self.gaps.observe(sample.dt, good, restart_gap) else {
            return;
        };
        let mut outputs = 0;
        let mut first_output = 0;
        for (slot, need) in self.slots.iter_mut().zip(&self.slot_needs) {
            let width = match slot {
                Slot::Shared(f) => f.equations().len(),
                _ => 1,
            };
            if need.intersects(sensors) {
                match slot {
                    // Resume, not reset: an estimator may keep what the gap cannot have
                    // changed (the EKF's gyro bias).
                    Slot::Direct(e) => e.resume(),
                    Slot::Shared(f) => f.reset(),
                    Slot::Kalman { kf, .. } => kf.reset(),
                }
                outputs += width;
            }
            first_output += width;
        }
        debug_assert_eq!(first_output, self.names.len());
        self.restart = Some(Restart {
            sensors,
            gap,
            outputs,
        });
    }

    /// Runs every estimator on `sample`; `out` gets one estimate per name. A sensor back
    /// after a gap longer than [`BankSettings::restart_gap`] first restarts the estimators
    /// that read it ([`Bank::restarted`]).
    pub fn update(&mut self, sample: &Sample<f64>, out: &mut Vec<Estimate<f64>>) {
        self.update_clipped(sample, Inputs::NONE, out);
    }

    /// [`Bank::update`] on a row whose `clipped` sensors read a clip found in the log
    /// itself ([`crate::io::plateau`]) rather than at a full scale the rig gives: each is
    /// taken exactly as a reading at a known full scale (a clipped gyro holds theta'' in
    /// alg2/alg3 and grows the Kalman filters' angle variance by `(level dt)^2`: the same
    /// estimates). A clipped reading, found or at the rig's full scale, is flagged
    /// [`Flags::SATURATED`] by every estimator reading that sensor.
    pub fn update_clipped(
        &mut self,
        sample: &Sample<f64>,
        clipped: Inputs,
        out: &mut Vec<Estimate<f64>>,
    ) {
        out.clear();
        self.restart_after_gaps(sample);
        let fs = self.set_gyro_full_scale(sample, clipped);
        // A gyro that clips heavily: its readings within range are the vibration's
        // troughs, which the gated estimators take as missing.
        let gyro_at_scale = fs.is_some_and(|f| sample.gyro.abs() >= f);
        let heavy = self.clip_gate.offer(sample.dt, gyro_at_scale);
        self.step_slots(sample, heavy, out);
        // Beyond the restart gap a sensor's estimators have nothing to go on: what they
        // would give (the gyro's last mean integrated for seconds, 170 deg off after a 10 s
        // gap) is no estimate. They restart when it is back.
        let stale = self.gaps.stale();
        if !stale.is_empty() {
            for (e, need) in out.iter_mut().zip(&self.needs) {
                if need.intersects(stale) {
                    e.theta = f64::NAN;
                    e.flags |= Flags::SAMPLE_MISSING;
                }
            }
        }
        // Every estimator reading a clipped sensor says so, the peers too, whether the
        // clip was found in the log or is at the rig's full scale.
        let accel_at_scale = (self.settings.rig.accel.checked_full_scale())
            .is_some_and(|fs| sample.ax.abs() >= fs || sample.ay.abs() >= fs);
        let saturated = Inputs::from_fn(|s| match s {
            Sensor::Gyro => gyro_at_scale,
            Sensor::Accel => clipped.has(Sensor::Accel) || accel_at_scale,
            _ => false,
        });
        if !saturated.is_empty() {
            for (e, need) in out.iter_mut().zip(&self.needs) {
                if need.intersects(saturated) {
                    e.flags |= Flags::SATURATED;
                }
            }
        }
    }

    /// The gyro's full scale for this row, given to the estimators when it changed: the
    /// clip's level when the gyro is `clipped` (the estimators then take it exactly as the
    /// rig's full scale), else the rig's.
    fn set_gyro_full_scale(&mut self, sample: &Sample<f64>, clipped: Inputs) -> Option<f64> {
        let fs = if clipped.has(Sensor::Gyro) {
            Some(sample.gyro.abs())
        } else {
            self.settings.rig.gyro.checked_full_scale()
        };
        if fs != self.gyro_full_scale {
            self.gyro_full_scale = fs;
            for slot in &mut self.slots {
                match slot {
                    Slot::Shared(front) => front.set_gyro_full_scale(fs),
                    Slot::Kalman { kf, .. } => kf.set_gyro_full_scale(fs),
                    Slot::Direct(_) => {}
                }
            }
        }
        fs
    }

    /// Every slot's estimates of `sample` into `out`, in column order (a gated slot takes
    /// the gyro as missing while it clips `heavy`ly).
    fn step_slots(&mut self, sample: &Sample<f64>, heavy: bool, out: &mut Vec<Estimate<f64>>) {
        for (slot, &gated) in self.slots.iter_mut().zip(&self.gated) {
            let e = match slot {
                Slot::Direct(est) if gated && heavy => {
                    let censored = Sample {
                        gyro: f64::NAN,
                        ..*sample
                    };
                    let mut e = est.update(&censored);
                    e.flags |= Flags::SATURATED;
                    e
                }
                Slot::Direct(est) => est.update(sample),
                Slot::Shared(front) => {
                    let n = front.equations().len();
                    let start = out.len();
                    out.resize(start + n, self.blank);
                    front.update(sample, &mut out[start..]);
                    continue;
                }
                Slot::Kalman { kf, sources } => {
                    self.measurements.clear();
                    for &(i, r) in sources.iter() {
                        let m = out[i];
                        let z = if m.flags.intersects(UNUSABLE) {
                            f64::NAN
                        } else {
                            m.theta
                        };
                        self.measurements.push((z, r));
                    }
                    kf.step(sample.dt, sample.gyro, &self.measurements)
                }
            };
            out.push(e);
        }
    }

    /// Forgets all history.
    pub fn reset(&mut self) {
        self.clip_gate = ClipGate::new();
        for slot in &mut self.slots {
            match slot {
                Slot::Direct(e) => e.reset(),
                Slot::Shared(f) => f.reset(),
                Slot::Kalman { kf, .. } => kf.reset(),
            }
        }
    }
}

/// Flags of one estimate, for tests and summaries.
pub fn any_flag(estimates: &[Estimate<f64>], flag: Flags) -> bool {
    estimates.iter().any(|e| e.flags.contains(flag))
}

#[cfg(test)]
mod tests {
    use super::*;
    use pendtilt_core::estimators::alg2::Alg2Settings;
    use pendtilt_core::{PendulumParams, PlanarEstimator};

    #[test]
    fn skips_what_the_inputs_do_not_allow() {
        let s = BankSettings::from_params(PendulumParams::default());
        let b = Bank::new(&s, Inputs::PHI, None).unwrap();
        assert_eq!(b.names(), &["pendulum", "alg1"]);
        let sk: Vec<_> = b.skipped().iter().map(|s| s.name).collect();
        assert!(sk.contains(&"alg2") && sk.contains(&"kf_accel") && sk.contains(&"accel"));
        let alg2 = b.skipped().iter().find(|s| s.name == "alg2").unwrap();
        assert_eq!(alg2.lacking, vec!["gyro"]);
    }

    #[test]
    fn all_inputs_run_everything_and_kalman_follows_its_source() {
        let s = BankSettings::from_params(PendulumParams::default());
        let mut b = Bank::new(&s, Inputs::ALL, None).unwrap();
        assert_eq!(b.names().len(), REGISTRY.len());
        let mut out = Vec::new();
        // Body still at 0.1 rad for 10 s: every estimator converges there (the gradient
        // peers, Madgwick and Mahony, take seconds).
        for k in 0..10_000 {
            let s = Sample {
                dt: if k == 0 { 0.0 } else { 1e-3 },
                phi: 0.1,
                gyro: 0.0,
                ax: 9.80665 * 0.1f64.sin(),
                ay: 9.80665 * 0.1f64.cos(),
            };
            b.update(&s, &mut out);
        }
        for (n, e) in b.names().iter().zip(&out) {
            // Madgwick's gradient step is normalised, so at rest it chatters within about
            // 2 beta dt (2.4 mrad at beta = 1.18, 1 kHz); everything else settles far closer.
            let tol = if *n == "madgwick" { 3e-3 } else { 1e-4 };
            assert!((e.theta - 0.1).abs() < tol, "{n}: {}", e.theta);
        }
    }

    #[test]
    fn unknown_or_orphan_names_are_errors() {
        let s = BankSettings::from_params(PendulumParams::default());
        let only = vec!["alg9".to_string()];
        assert!(Bank::new(&s, Inputs::ALL, Some(&only))
            .unwrap_err()
            .contains("alg9"));
    }

    /// `--only kf_alg2` runs alg2 too (it used to fail, "needs alg2: request it too"), and
    /// says so; the Kalman output equals the one the whole bank gives.
    #[test]
    fn a_kalman_output_pulls_in_the_outputs_it_reads() {
        let s = BankSettings::from_params(PendulumParams::default());
        let only = vec!["kf_alg2".to_string()];
        let mut b = Bank::new(&s, Inputs::ALL, Some(&only)).unwrap();
        assert_eq!(b.names(), ["alg2", "kf_alg2"]);
        assert_eq!(b.pulled_in(), [("alg2", "kf_alg2")]);
        let only = vec!["kf_fused".to_string(), "alg2".to_string()];
        let fused = Bank::new(&s, Inputs::ALL, Some(&only)).unwrap();
        assert_eq!(fused.names(), ["accel", "alg2", "kf_fused"]);
        assert_eq!(fused.pulled_in(), [("accel", "kf_fused")]);
        let mut all = Bank::new(&s, Inputs::ALL, None).unwrap();
        assert!(all.pulled_in().is_empty());
        let k = all.names().iter().position(|n| *n == "kf_alg2").unwrap();
        let (mut one, mut every) = (Vec::new(), Vec::new());
        for i in 0..2000 {
            let t = i as f64 * 1e-3;
            let x = Sample {
                dt: 1e-3,
                phi: 0.1 * (3.0 * t).sin(),
                gyro: 0.3 * (3.0 * t).cos(),
                ax: 0.98 * (3.0 * t).sin(),
                ay: 9.8,
            };
            b.update(&x, &mut one);
            all.update(&x, &mut every);
            assert_eq!(one[1].theta.to_bits(), every[k].theta.to_bits(), "row {i}");
        }
        // Without the pendulum, kf_alg2 is skipped as alg2 is, not an error.
        let imu = Inputs::ALL.without(Sensor::Encoder);
        let only = vec!["kf_alg2".to_string()];
        let b = Bank::new(&s, imu, Some(&only)).unwrap();
        assert!(b.names().is_empty());
        let sk: Vec<_> = b.skipped().iter().map(|s| s.name).collect();
        assert_eq!(sk, ["alg2", "kf_alg2"]);
    }

    #[test]
    fn only_names_take_spaces_and_a_near_miss_is_named() {
        // `--only "alg2, kf_alg2"` was refused as "unknown estimator ` kf_alg2`" (the 3-D
        // bank already trimmed its names).
        let s = BankSettings::from_params(PendulumParams::default());
        let only = vec!["alg2".to_string(), " kf_alg2".to_string()];
        let bank = Bank::new(&s, Inputs::ALL, Some(&only)).unwrap();
        assert_eq!(bank.names(), ["alg2", "kf_alg2"]);
        let only = vec!["ALG2".to_string()];
        let e = Bank::new(&s, Inputs::ALL, Some(&only)).unwrap_err();
        assert!(
            e.starts_with("unknown estimator `ALG2`; did you mean `alg2`?"),
            "{e}"
        );
        let only = vec!["ekf3d".to_string()];
        let e = Bank::new(&s, Inputs::ALL, Some(&only)).unwrap_err();
        assert!(
            e.contains("it is a 3-D estimator, and this log is planar"),
            "{e}"
        );
    }

    /// Algorithms 1-3 in the bank share a front end; each output must equal its
    /// stand-alone estimator's, also when Algorithm 1's front end differs (its phi
    /// filtered: then it gets a front end of its own).
    #[test]
    fn shared_front_end_outputs_equal_the_stand_alone_estimators() {
        use pendtilt_core::estimators::alg1::Alg1;
        use pendtilt_core::estimators::alg2::Alg2;
        use pendtilt_core::estimators::alg3::Alg3;
        use pendtilt_core::estimators::PhiSource;
        use pendtilt_core::filters::diff::Cutoff;
        let p = PendulumParams {
            c: 0.02,
            ..Default::default()
        };
        for alg1_filtered in [false, true] {
            let mut s = BankSettings::from_params(p);
            if alg1_filtered {
                s.rig.alg1.settings.front_end.phi = PhiSource::Filtered;
            }
            s.rig.alg3.gains.n = 0.003;
            // As a rig file from `simulate` has it: alg1 must still share.
            s.rig.gyro.full_scale = Some(0.15);
            s.rig.differentiator.cutoff = Cutoff::Hz(4.0);
            let mut b = Bank::new(&s, Inputs::ALL, None).unwrap();
            let shared = b
                .slots
                .iter()
                .filter(|x| matches!(x, Slot::Shared(_)))
                .count();
            assert_eq!(shared, if alg1_filtered { 2 } else { 1 });
            let (alg1, alg2, alg3) = (
                s.rig.alg1_settings(),
                s.rig.alg2_settings(),
                s.rig.alg3_settings(),
            );
            let mut alone: Vec<(&str, Box<dyn PlanarEstimator<f64>>)> = vec![
                ("alg1", Box::new(Alg1::new(alg1))),
                ("alg2", Box::new(Alg2::<f64>::new(alg2))),
                (
                    "alg2_offset",
                    Box::new(Alg2::<f64>::new(Alg2Settings {
                        pivot_offset: true,
                        ..alg2
                    })),
                ),
                (
                    "alg2_dc",
                    Box::new(Alg2::<f64>::new(Alg2Settings {
                        delay_compensation: true,
                        ..alg2
                    })),
                ),
                ("alg3", Box::new(Alg3::<f64>::new(alg3))),
            ];
            let col = |n: &str| b.names().iter().position(|x| *x == n).unwrap();
            let cols: Vec<usize> = alone.iter().map(|(n, _)| col(n)).collect();
            let mut out = Vec::new();
            for k in 0..5000 {
                let t = k as f64 * 1e-3;
                let th = 0.2 * (0.9 * t).sin() + 0.005 * (180.0 * t).sin();
                let smp = Sample {
                    dt: if k == 0 { 0.0 } else { 1e-3 },
                    phi: if k == 700 { f64::NAN } else { 0.95 * th },
                    gyro: if k == 900 {
                        f64::NAN
                    } else {
                        0.18 * (0.9 * t).cos()
                    },
                    ax: 9.8 * th.sin(),
                    ay: 9.8 * th.cos(),
                };
                b.update(&smp, &mut out);
                assert_eq!(out.len(), b.names().len());
                for ((n, e), &c) in alone.iter_mut().zip(&cols) {
                    let want = e.update(&smp);
                    assert_eq!(out[c].flags, want.flags, "{n} at {t}");
                    assert!((out[c].theta - want.theta).abs() < 1e-12, "{n} at {t}");
                }
            }
        }
    }
}

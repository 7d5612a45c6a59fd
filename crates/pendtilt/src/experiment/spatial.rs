//! The 3-D part of `reproduce`: MODEL.md 7.8's scenarios simulated with
//! fixed seeds ([`Scenario3d::named`]), every estimator of the 3-D registry
//! ([`crate::bank::spatial::REGISTRY3D`], so a new entry appears here by itself) with the
//! scenario's rig and sensor figures (as `pendtilt estimate --scenario` takes them), one
//! [`SpatialReport`] per scenario, and the inclination error table of the top page.
use std::path::Path;
use std::time::Instant;

use anyhow::Context;
use pendtilt_core::spatial::SpatialSample;
use pendtilt_core::StepGate;

use super::progress::{Progress, CHUNK};
use super::Timings;
use crate::bank::spatial::ride::WithoutSpeed;
use crate::bank::spatial::{Bank3d, Settings3d};
use crate::report::claims::fmt_sig;
use crate::report::html::TextTable;
use crate::report::spatial::{secs, Ride, RollPitch, SpatialOutput, SpatialReport};
use crate::sim::spatial::Scenario3d;

/// One 3-D scenario of `reproduce`.
#[derive(Debug, Clone, PartialEq)]
pub struct SpatialRide {
    /// Its name in [`crate::sim::spatial::SCENARIO3D_NAMES`]; also the report's directory.
    pub name: String,
    /// The seed of its random parts and sensor noise.
    pub seed: u64,
    /// Only the first this many seconds of it \[s\] (the scenario's motion unchanged);
    /// `None`: all of it.
    pub duration: Option<f64>,
}

/// The default 3-D part: `still3d` whole (6 s), the first 60 s of `scooter3d` and of
/// `ship3d` (120 s each; halved to keep `reproduce` quick), and `ride3d` whole (120 s: its
/// braking and turns run to 111 s), all with `seed`.
pub fn default_rides(seed: u64) -> Vec<SpatialRide> {
    [
        ("still3d", None),
        ("scooter3d", Some(60.0)),
        ("ship3d", Some(60.0)),
        ("ride3d", None),
    ]
    .into_iter()
    .map(|(name, duration)| SpatialRide {
        name: name.into(),
        seed,
        duration,
    })
    .collect()
}

/// A simulated 3-D record in memory: the samples as the estimators get them and the
/// true roll and pitch.
#[derive(Debug, Clone, PartialEq)]
pub struct Record3d {
    /// Time of each row \[s\].
    pub t: Vec<f64>,
    /// The sensor samples (the time step from a [`StepGate`], as `estimate` makes it).
    pub samples: Vec<SpatialSample<f64>>,
    /// True roll and pitch \[rad\].
    pub truth: RollPitch,
}

/// Simulates `scenario` with `seed` into memory, reporting progress per chunk of rows.
pub fn simulate3d(
    label: &str,
    scenario: &Scenario3d,
    seed: u64,
    progress: &dyn Progress,
) -> anyhow::Result<Record3d> {
    let run = scenario.run(seed)?;
    let n = usize::try_from(scenario.rows()).unwrap_or(0);
    progress.stage(&format!("simulating {label}"), n as u64);
    let mut rec = Record3d {
        t: Vec::with_capacity(n),
        samples: Vec::with_capacity(n),
        truth: RollPitch {
            name: "truth".into(),
            roll: Vec::with_capacity(n),
            pitch: Vec::with_capacity(n),
        },
    };
    let mut gate = StepGate::new();
    for (k, (_, row)) in run.enumerate() {
        rec.t.push(row.t);
        rec.samples.push(row.sample(gate.step(row.t)));
        rec.truth.roll.push(row.roll);
        rec.truth.pitch.push(row.pitch);
        if (k as u64 + 1) % CHUNK == 0 {
            progress.advance(CHUNK);
        }
    }
    Ok(rec)
}

/// Every estimator of the 3-D registry over `rec`: their roll and pitch, registry order.
pub fn estimate3d(rec: &Record3d, settings: &Settings3d) -> anyhow::Result<Vec<RollPitch>> {
    let mut bank = Bank3d::new(settings, None).map_err(anyhow::Error::msg)?;
    let mut out: Vec<RollPitch> = bank
        .names()
        .into_iter()
        .map(|n| RollPitch {
            name: n.to_string(),
            roll: Vec::with_capacity(rec.t.len()),
            pitch: Vec::with_capacity(rec.t.len()),
        })
        .collect();
    for s in &rec.samples {
        for (o, a) in out.iter_mut().zip(bank.update(s)) {
            o.roll.push(a.roll);
            o.pitch.push(a.pitch);
        }
    }
    Ok(out)
}

/// One 3-D scenario simulated, estimated and reported into `out/<name>`.
pub fn ride3d_report(
    spec: &SpatialRide,
    out: &Path,
    progress: &dyn Progress,
    timings: &mut Timings,
) -> anyhow::Result<SpatialOutput> {
    let started = Instant::now();
    let mut scenario = Scenario3d::named(&spec.name, spec.seed)?;
    let whole = scenario.duration;
    if let Some(d) = spec.duration {
        scenario.duration = d.min(whole);
    }
    let label = format!("{} (seed {})", spec.name, spec.seed);
    let rec = simulate3d(&label, &scenario, spec.seed, progress)?;
    timings.simulate += started.elapsed();
    let started = Instant::now();
    progress.stage(&format!("3-D estimators on {label}"), 0);
    let settings = Settings3d::of_scenario(&scenario);
    let series = estimate3d(&rec, &settings)?;
    let mut without = WithoutSpeed::new(&settings);
    for s in &rec.samples {
        without.update(s);
    }
    let ride = Ride::of(
        without,
        rec.samples.iter().map(|s| s.speed).collect(),
        rec.samples.iter().map(|s| s.gyro[2]).collect(),
    );
    timings.estimate += started.elapsed();
    let started = Instant::now();
    progress.stage(&format!("metrics and figures of {label}"), 0);
    let length = if scenario.duration < whole {
        format!(
            "the first {} s of its {} s (shortened to keep `reproduce` quick)",
            secs(scenario.duration),
            secs(whole)
        )
    } else {
        format!("{} s", secs(whole))
    };
    let mut report = SpatialReport::new(
        &format!("{} (3-D, seed {})", spec.name, spec.seed),
        rec.t,
        rec.truth.roll,
        rec.truth.pitch,
        scenario.score_from,
    )?
    .intro(&format!(
        "`Scenario3d::named(\"{}\", {})` of MODEL.md 7.8, {length}, simulated in memory; \
         every 3-D estimator with the scenario's rig and sensor noise figures (as `pendtilt \
         estimate --scenario` takes them); the peers at their default gains, not tuned.",
        spec.name, spec.seed
    ));
    for s in series {
        report = report.estimate(s)?;
    }
    if let Some(r) = ride {
        report = report.ride(r)?;
    }
    let dir = out.join(&spec.name);
    let written = report
        .write(&dir)
        .with_context(|| format!("writing the {} report into {}", spec.name, dir.display()))?;
    timings.report += started.elapsed();
    Ok(written)
}

/// The top page's table: one row per estimator, "RMS / max" per scenario \[deg\].
pub fn summary_table(rides: &[SpatialRide], outputs: &[SpatialOutput]) -> TextTable {
    let mut columns = vec!["estimator".to_string()];
    columns.extend(rides.iter().zip(outputs).map(|(r, o)| {
        format!(
            "{} from {} s: RMS / max [deg]",
            r.name,
            secs(o.data.score_from_s)
        )
    }));
    let names: Vec<&str> = outputs
        .first()
        .map(|o| o.data.inclination.iter().map(|r| r.name.as_str()).collect())
        .unwrap_or_default();
    let rows = names
        .iter()
        .map(|n| {
            let mut row = vec![n.to_string()];
            row.extend(outputs.iter().map(|o| {
                o.data
                    .inclination
                    .iter()
                    .find(|r| r.name == *n)
                    .map_or("n/a".into(), |r| {
                        format!("{} / {}", fmt_sig(r.rms_deg), fmt_sig(r.max_deg))
                    })
            }));
            row
        })
        .collect();
    TextTable {
        heading: "3-D: inclination error (MODEL.md 7.9)".into(),
        columns,
        rows,
        definitions: vec![(
            "RMS / max".into(),
            "of the angle between the estimated and the true up direction, over each \
             scenario's rows from its score_from on (the start-up left out), as `pendtilt \
             estimate` prints it"
                .into(),
        )],
    }
}

//! `pendtilt simulate --scenario still3d|scooter3d|ship3d|ride3d|ride3d_yawbias|ride3d_slip`: the 3-D branch of
//! `simulate` (MODEL.md 7.8). Same files as the planar branch: the log (columns of 7.6), the
//! rig TOML (`[pendulum3d]`, `[mounting]`) and the resolved scenario beside it, written
//! safely and renamed into place together.
//!
//! Settings, in order: the named scenario (its random parts from the seed) or a scenario
//! file written by an earlier run (`--config`), then `--duration`, `--rate`, `--substeps`,
//! and last `--no-noise`, `--ideal-sensors`, `--no-vibration`. The planar rig and motion
//! flags do not apply and are refused.

use std::io::BufWriter;
use std::path::Path;
use std::time::Instant;

use anyhow::{bail, Context};

use super::simulate::{progress_bar, write_files, Args, Outputs, DEFAULT_SEED};
use crate::io::output::{NamedPath, OutputFile};
use crate::sim::spatial::{output, Scenario3d, SCENARIO3D_NAMES};

/// True when `path` reads as a scenario file of a 3-D scenario (`scenario = "...3d"`).
/// Anything else (unreadable, not TOML, planar) is left to the planar loader's errors.
pub fn is_3d_config(path: &Path) -> bool {
    let Ok(text) = std::fs::read_to_string(path) else {
        return false;
    };
    let Ok(table) = text.parse::<toml::Table>() else {
        return false;
    };
    matches!(table.get("scenario"), Some(toml::Value::String(n)) if SCENARIO3D_NAMES.contains(&n.as_str()))
}

/// The planar-only options that were given (they are refused for a 3-D scenario).
fn planar_only(args: &Args) -> Vec<&'static str> {
    let o = &args.settings;
    let given = [
        ("--rig", o.rig.is_some()),
        ("--mass", o.mass.is_some()),
        ("--length", o.length.is_some()),
        ("--inertia", o.inertia.is_some()),
        ("--damping", o.damping.is_some()),
        ("--pivot-offset", o.pivot_offset.is_some()),
        ("--amplitude", o.amplitude.is_some()),
        ("--frequency", o.frequency.is_some()),
        ("--engine-hz", o.engine_hz.is_some()),
        ("--vibration-scale", o.vibration_scale.is_some()),
        ("--accel-mount", o.accel_mount.is_some()),
        ("--encoder-bits", o.encoder_bits.is_some()),
        ("--set", !o.set.is_empty()),
    ];
    given.iter().filter(|g| g.1).map(|g| g.0).collect()
}

/// The scenario, its name and the seed the options describe.
pub fn resolve(args: &Args) -> anyhow::Result<(Scenario3d, String, u64)> {
    let refused = planar_only(args);
    if !refused.is_empty() {
        bail!(
            "{}: for the planar scenarios only; a 3-D scenario ({}) takes --seed, \
             --duration, --rate, --substeps, --no-noise, --ideal-sensors, --no-vibration, \
             or a scenario file (--config)",
            refused.join(", "),
            SCENARIO3D_NAMES.join(", ")
        );
    }
    let (mut s, name, seed) = match &args.config {
        Some(path) => of_config(args, path)?,
        None => {
            let name = args.scenario.clone().unwrap_or_default();
            let seed = args.seed.unwrap_or(DEFAULT_SEED);
            (Scenario3d::named(&name, seed)?, name, seed)
        }
    };
    if let Some(d) = args.duration {
        s.duration = d;
    }
    if let Some(r) = args.rate {
        s.rate = r;
    }
    if let Some(n) = args.settings.substeps {
        s.substeps = n;
    }
    if args.settings.no_noise {
        s.sensors = s.sensors.without_noise();
    }
    if args.settings.ideal_sensors {
        s.sensors = s.sensors.ideal();
    }
    if args.settings.no_vibration {
        s.motion = s.motion.without_vibration();
    }
    s.validate()?;
    super::simulate::at_least_one_row(s.duration, s.rate, s.rows())?;
    // Only a --config file sets the 3-D pendulum (no option does), so it is named.
    if let (Some(path), false) = (&args.config, args.quiet) {
        let p = crate::bank::spatial::rig::Pendulum3dConfig::Physical(s.rig.pendulum3d);
        for d in p.length_doubts("rig.pendulum3d") {
            eprintln!(
                "warning: {}: {}",
                path.display(),
                d.in_file("scenario file")
            );
        }
    }
    Ok((s, name, seed))
}

/// The scenario of the `--config` file at `path`: its keys on top of the named scenario
/// (`--scenario`, else the file's `scenario` key), with its name and the seed.
fn of_config(args: &Args, path: &std::path::Path) -> anyhow::Result<(Scenario3d, String, u64)> {
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("cannot read --config {}", path.display()))?;
    let table = text.parse::<toml::Table>().ok();
    let file_name = table
        .as_ref()
        .and_then(|t| t.get("scenario")?.as_str().map(String::from));
    let origin = path.display().to_string();
    if let (Some(n), Some(f)) = (&args.scenario, &file_name) {
        if n != f {
            bail!(
                "--scenario {n}: the --config file {origin} is a {f} scenario (its \
                 `scenario` key): give one of them"
            );
        }
    }
    // The file's keys on top of the named scenario, key by key as a planar file's:
    // a file of some keys was read as a whole scenario, and refused (`is a  scenario`
    // with --scenario; `missing field `duration`` with its own `scenario` key).
    let Some(name) = args.scenario.clone().or(file_name) else {
        bail!(
            "{origin}: no base scenario: give --scenario NAME or a top-level \
             `scenario = \"NAME\"` (a 3-D one: {})",
            SCENARIO3D_NAMES.join(", ")
        );
    };
    // The seed draws the base's random parts: the file's, if it has one.
    let file_seed = match &table {
        Some(t) => crate::sim::planar::scenario::seed_of(t, &origin)?,
        None => None,
    };
    let seed = args.seed.or(file_seed).unwrap_or(DEFAULT_SEED);
    let (s, _) = Scenario3d::named(&name, seed)?.merged(&text, &origin)?;
    Ok((s, name, seed))
}

/// Simulates into the (uncommitted) log; returns the number of rows.
fn write_log(s: &Scenario3d, seed: u64, log: &OutputFile, quiet: bool) -> anyhow::Result<u64> {
    let run = s.run(seed)?;
    // 228 bytes a row on scooter3d.
    if let Some(w) = super::simulate::size_warning(log.target(), run.remaining(), 228.0) {
        if !quiet {
            eprintln!("{w}");
        }
    }
    let bar = progress_bar(run.remaining(), quiet);
    let n = output::write_log(
        run,
        BufWriter::with_capacity(1 << 20, log.writer()?),
        |done| bar.set_position(done),
    )
    .with_context(|| format!("cannot write the log {}", log.target().display()))?;
    bar.finish_and_clear();
    Ok(n)
}

/// Runs the 3-D branch of `pendtilt simulate`.
pub fn run(args: Args) -> anyhow::Result<()> {
    let (s, name, seed) = resolve(&args)?;
    let scenario_text = format!(
        "# Resolved 3-D scenario written by `pendtilt simulate` (MODEL.md 7.8). Units: the\n\
         # amplitudes of the [motion] roll, pitch and yaw terms in degrees (their rates in\n\
         # deg/s); everything else SI: phases and [sensors] angles in rad, rates in rad/s,\n\
         # lengths in m, frequencies in Hz. Rerun with\n\
         # pendtilt simulate --config THIS_FILE -o NEW.csv\n\
         scenario = \"{name}\"\nseed = {seed}\n{}",
        s.to_toml()?
    );
    if args.print_scenario {
        print!("{scenario_text}");
        return Ok(());
    }
    let inputs: Vec<NamedPath> = args
        .config
        .iter()
        .map(|p| NamedPath::new("--config", p))
        .collect();
    let started = Instant::now();
    let quiet = args.quiet;
    let (n, rig_shown, scen_shown) = write_files(
        &args,
        Outputs {
            rig_text: s.rig.to_toml_string()?,
            scenario_text,
            inputs,
            write_log: |log: &OutputFile| write_log(&s, seed, log, quiet),
        },
    )?;
    if !args.quiet {
        super::summary::say_err!(
            "wrote {n} rows of {name} ({} s at {} Hz, seed {seed}) to {} in {:.2} s; rig: {}; \
             scenario: {}",
            s.duration,
            s.rate,
            args.output.as_deref().unwrap_or(Path::new("-")).display(),
            started.elapsed().as_secs_f64(),
            rig_shown,
            scen_shown
        );
    }
    Ok(())
}

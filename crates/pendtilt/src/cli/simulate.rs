//! `pendtilt simulate`: run a scenario and write the sensor log, the rig TOML and the
//! resolved scenario beside it.
//!
//! Settings are applied in this order, each overriding the one before: the named scenario
//! (`--scenario`), the scenario TOML (`--config`), the rig (`--rig`), the individual flags,
//! `--set KEY=VALUE` assignments, and last `--no-noise`, `--ideal-sensors`, `--no-vibration`.

use std::io::BufWriter;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{bail, Context};
use indicatif::ProgressBar;

use super::help;
use crate::io::output::{NamedPath, OutputFile};
pub(super) use crate::sim::planar::output::Outputs;
use crate::sim::planar::overrides::Overrides;
use crate::sim::planar::{self, output, Scenario, Simulator};

/// Seed used when neither `--seed` nor the scenario TOML gives one.
pub const DEFAULT_SEED: u64 = 1;

/// Options of `pendtilt simulate`.
#[derive(Debug, Clone, Default, clap::Args)]
pub struct Args {
    /// Base scenario: still, sigmoid, step, sine, chirp or scooter (MODEL.md section 6), or
    /// a 3-D one: still3d, scooter3d, ship3d, ride3d (MODEL.md 7.8), or ride3d's variants
    /// ride3d_yawbias and ride3d_slip. No default: give it or --config.
    #[arg(long, value_name = "NAME")]
    pub scenario: Option<String>,
    /// Scenario TOML overriding the base key by key (`pendtilt simulate --print-scenario`
    /// shows every key). Default: none, the named scenario as it is.
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
    /// Seed of every random part (same seed, same bytes). Default: the TOML's `seed`, else 1.
    #[arg(long, value_name = "N")]
    pub seed: Option<u64>,
    /// Length of the run (s). Default: the scenario's.
    #[arg(long, value_name = "S", help = help::duration())]
    pub duration: Option<f64>,
    /// Sample rate in Hz. Default: the scenario's.
    #[arg(long, value_name = "HZ", help = help::rate())]
    pub rate: Option<f64>,
    /// Rig, motion, vibration and sensor settings.
    #[command(flatten)]
    pub settings: Box<Settings>,
    /// The log to write (CSV of MODEL.md section 5); `-` for standard output (the rig file
    /// then only with --rig-out). No default: required unless --print-scenario.
    #[arg(
        short,
        long,
        visible_alias = "out",
        value_name = "LOG.csv",
        required_unless_present = "print_scenario"
    )]
    pub output: Option<PathBuf>,
    /// Where to write the rig TOML (default: beside the log, `LOG.rig.toml`).
    #[arg(long, value_name = "FILE")]
    pub rig_out: Option<PathBuf>,
    /// Print the resolved scenario as TOML and exit.
    #[arg(long)]
    pub print_scenario: bool,
    /// No progress bar and no summary.
    #[arg(short, long)]
    pub quiet: bool,
}

/// The options that change one part of the scenario (boxed in `Args`: they are many).
#[derive(Debug, Clone, Default, clap::Args)]
pub struct Settings {
    /// RK4 steps per sample. Default: the scenario's.
    #[arg(long, value_name = "N", help = help::substeps())]
    pub substeps: Option<u32>,
    /// Switch off every random sensor error (white noise, gyro bias walk, potentiometer
    /// noise); biases, quantisation and saturation stay. Vibration is not sensor noise: see
    /// --no-vibration.
    #[arg(long)]
    pub no_noise: bool,
    /// Ideal sensors: no noise, bias, quantisation or saturation.
    #[arg(long)]
    pub ideal_sensors: bool,
    /// No floor vibration (harmonics, broadband, angular).
    #[arg(long)]
    pub no_vibration: bool,
    /// Take the pendulum from the `[pendulum]` table of a rig TOML (physical form).
    /// Default: none, the scenario's pendulum.
    #[arg(long, value_name = "FILE")]
    pub rig: Option<PathBuf>,
    /// Pendulum mass m_p (kg). Default: the scenario's.
    #[arg(long, value_name = "KG", help = help::pendulum("Pendulum mass m_p (kg)", |p| p.mass))]
    pub mass: Option<f64>,
    /// Pivot-to-CG distance l_p (m). Default: the scenario's.
    #[arg(long, value_name = "M", help = help::pendulum("Pivot-to-CG distance l_p (m)", |p| p.length))]
    pub length: Option<f64>,
    /// Inertia about the pivot I_p (kg m^2). Default: the scenario's.
    #[arg(long, value_name = "KG_M2", help = help::pendulum("Inertia about the pivot I_p (kg m^2)", |p| p.inertia))]
    pub inertia: Option<f64>,
    /// Pivot friction C (N m s/rad). Default: the scenario's.
    #[arg(long, value_name = "NMS", help = help::pendulum("Pivot friction C (N m s/rad)", |p| p.damping))]
    pub damping: Option<f64>,
    /// Distance l12 from the body's pivot P1 to the pendulum pivot P2 (m). Default: the scenario's.
    #[arg(long, value_name = "M", help = help::pendulum("Distance l12 from the body's pivot P1 to the pendulum pivot P2 (m)", |p| p.pivot_offset))]
    pub pivot_offset: Option<f64>,
    /// Size of the body motion (rad) (amplitude, or the angle of `still`).
    #[arg(long, value_name = "RAD", allow_negative_numbers = true, help = help::amplitude())]
    pub amplitude: Option<f64>,
    /// Frequency of the `sine` motion (Hz).
    #[arg(long, value_name = "HZ", help = help::frequency())]
    pub frequency: Option<f64>,
    /// Engine fundamental (Hz): every vibration harmonic keeps its ratio to the first.
    #[arg(long, value_name = "HZ", help = help::engine_hz())]
    pub engine_hz: Option<f64>,
    /// Multiply every vibration amplitude (harmonic, broadband, angular) by this.
    /// Default 1 (the scenario's vibration as it is).
    #[arg(long, value_name = "X")]
    pub vibration_scale: Option<f64>,
    /// Accelerometer position relative to P2 in body axes (m), e.g. `--accel-mount 0.02,-0.1`.
    #[arg(
        long,
        value_name = "X,Y",
        value_delimiter = ',',
        allow_negative_numbers = true,
        help = help::accel_mount()
    )]
    pub accel_mount: Option<Vec<f64>>,
    /// Encoder resolution (bits per turn); 0 = no quantisation.
    #[arg(long, value_name = "BITS", help = help::encoder_bits())]
    pub encoder_bits: Option<u32>,
    /// Set any scenario key, TOML syntax: `--set vibration.broadband.rms=[1.0,2.0]`
    /// (repeatable). Default: none.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
}

/// The scenario and seed the options describe (see the module docs for the order): the
/// named scenario or the file, then the rig, the overrides, `--set`, the sensor switches.
pub fn resolve(args: &Args) -> anyhow::Result<(Scenario, u64)> {
    let o = &args.settings;
    let (mut s, file_seed) = match (&args.config, &args.scenario) {
        (Some(path), name) => planar::load_config(path, name.as_deref())?,
        (None, Some(name)) => (Scenario::named(name)?, None),
        (None, None) => bail!(
            "give --scenario NAME (one of {}) or --config FILE",
            planar::SCENARIO_NAMES.join(", ")
        ),
    };
    if let Some(path) = &o.rig {
        s.pendulum = planar::load_rig(path)?;
    }
    overrides(args).apply(&mut s)?;
    s.validate()?;
    super::simulate::at_least_one_row(s.duration, s.rate, s.rows())?;
    Ok((s, args.seed.or(file_seed).unwrap_or(DEFAULT_SEED)))
}

/// The changes to the scenario the options give.
fn overrides(args: &Args) -> Overrides {
    let o = &args.settings;
    Overrides {
        mass: o.mass,
        length: o.length,
        inertia: o.inertia,
        damping: o.damping,
        pivot_offset: o.pivot_offset,
        duration: args.duration,
        rate: args.rate,
        substeps: o.substeps,
        amplitude: o.amplitude,
        frequency: o.frequency,
        engine_hz: o.engine_hz,
        vibration_scale: o.vibration_scale,
        accel_mount: o.accel_mount.clone(),
        encoder_bits: o.encoder_bits,
        set: o.set.clone(),
        no_noise: o.no_noise,
        ideal_sensors: o.ideal_sensors,
        no_vibration: o.no_vibration,
    }
}

/// The resolved pendulum's doubtful lengths ([`crate::config::doubt_length`], the check
/// every rig file gets), each worded for where it was last set: `--set`, `--length` or
/// `--pivot-offset`, `--rig` or `--config` (the order they are applied in, reversed).
pub fn length_doubts(args: &Args, s: &Scenario) -> anyhow::Result<Vec<String>> {
    let o = &args.settings;
    let mut out = Vec::new();
    for d in s.rig()?.length_doubts() {
        let (flag, given) = match d.key.as_str() {
            "pendulum.length" => ("--length", o.length),
            _ => ("--pivot-offset", o.pivot_offset),
        };
        let set = last_set(args, &d.key);
        out.push(match (set, given, &o.rig, &args.config) {
            (Some(a), ..) => {
                d.on_command_line(&format!("--set {a}"), &format!("--set {}={}", d.key, d.fix))
            }
            (None, Some(v), ..) => {
                d.on_command_line(&format!("{flag} {v}"), &format!("{flag} {}", d.fix))
            }
            (None, None, Some(rig), _) => format!("{}: {}", rig.display(), d.in_file("rig file")),
            (None, None, None, Some(c)) => {
                format!("{}: {}", c.display(), d.in_file("scenario file"))
            }
            (None, None, None, None) => d.in_file("scenario"),
        });
    }
    Ok(out)
}

/// The last `--set` of `key` (the one that took effect), as given.
fn last_set<'a>(args: &'a Args, key: &str) -> Option<&'a String> {
    (args.settings.set.iter().rev()).find(|a| a.split('=').next().map(str::trim) == Some(key))
}

/// The sensors' full scales and gravity in another unit (a gyro's in deg/s, an
/// accelerometer's in g or mg, gravity in g: [`crate::config::doubt_gyro_full_scale`], the
/// checks every rig file gets), each worded for where it was set: `--set` or `--config`.
/// A gyro of `full_scale = 500`, meant as deg/s, simulated a gyro that never clips,
/// without a word.
pub fn unit_doubts(args: &Args, s: &Scenario) -> Vec<String> {
    let doubts = [
        (
            "sensors.gyro.full_scale",
            s.sensors.gyro.full_scale,
            crate::config::doubt_gyro_full_scale as fn(&str, f64, &str) -> Option<String>,
        ),
        (
            "sensors.accel.full_scale",
            s.sensors.accel.full_scale,
            crate::config::doubt_accel_full_scale,
        ),
        (
            "pendulum.gravity",
            s.pendulum.gravity,
            |k: &str, g: f64, _: &str| crate::config::doubt_gravity(k, g),
        ),
    ];
    let mut out = Vec::new();
    for (key, value, doubt) in doubts {
        let set = last_set(args, key);
        let d = match (set, &args.config) {
            (Some(a), _) => doubt(key, value, "--set value").map(|d| format!("--set {a}: {d}")),
            (None, Some(c)) => {
                doubt(key, value, "scenario file").map(|d| format!("{}: {d}", c.display()))
            }
            (None, None) => doubt(key, value, "scenario"),
        };
        out.extend(d);
    }
    out
}

/// A progress bar on standard error for `total` rows (hidden when quiet or not a terminal).
pub(super) fn progress_bar(total: u64, quiet: bool) -> ProgressBar {
    super::options::bar(
        total,
        "simulating {bar:40} {percent:>3}% {human_pos}/{human_len} rows, eta {eta}",
        quiet,
    )
}

/// A run of no row would write a header-only log that no command reads: refused with
/// the shortest duration that gives one (`--duration 0` wrote one, exit 0).
pub(super) fn at_least_one_row(duration: f64, rate: f64, rows: u64) -> anyhow::Result<()> {
    anyhow::ensure!(
        rows > 0,
        "a duration of {duration} s at {rate} Hz gives no row, and a log needs at least one: \
         give --duration {} or more",
        1.0 / rate
    );
    Ok(())
}

/// A log above this many bytes is announced before it is written ([`size_warning`]).
const LARGE_LOG: f64 = 1e9;

/// The warning for a log of `rows` rows at about `bytes_per_row` (a noisy ride's) into
/// `target`, when it is above [`LARGE_LOG`]: its size, and whether the file system has
/// room (`--rate 1e9` started a 100 GB file without a word and ran until the disk was full).
/// None for standard output or a device, which keep nothing.
pub(super) fn size_warning(target: &Path, rows: u64, bytes_per_row: f64) -> Option<String> {
    let bytes = rows as f64 * bytes_per_row;
    let regular = !crate::io::output::is_stdout(target)
        && std::fs::metadata(target).map_or(true, |m| m.is_file());
    if bytes <= LARGE_LOG || !regular {
        return None;
    }
    let dir = crate::io::output::absolute(target)
        .parent()
        .map_or_else(|| PathBuf::from("."), Path::to_path_buf);
    let room = match crate::io::output::free_bytes(&dir) {
        Some(free) if (free as f64) < bytes => format!(
            "; the file system holding it has {:.1} GB free: it may not fit",
            free as f64 / 1e9
        ),
        _ => String::new(),
    };
    Some(format!(
        "warning: {}: {rows} rows of about {bytes_per_row:.0} bytes are about {:.1} GB{room}; \
         a shorter --duration or a lower --rate writes less (Ctrl-C stops the run and \
         removes the partial file)",
        target.display(),
        bytes / 1e9
    ))
}

/// Simulates into the (uncommitted) log; returns the number of rows.
fn write_outputs(
    scenario: &Scenario,
    seed: u64,
    log: &OutputFile,
    quiet: bool,
) -> anyhow::Result<u64> {
    let sim = Simulator::new(scenario, seed)?;
    // 104 bytes a row on the noisy scooter ride.
    if let Some(w) = size_warning(log.target(), sim.total_rows(), 104.0) {
        if !quiet {
            eprintln!("{w}");
        }
    }
    let bar = progress_bar(sim.total_rows(), quiet);
    let n = output::write_log(
        sim,
        BufWriter::with_capacity(1 << 20, log.writer()?),
        |done, _| bar.set_position(done),
    )
    .with_context(|| format!("cannot write the log {}", log.target().display()))?;
    bar.finish_and_clear();
    Ok(n)
}

/// Writes the log, the rig file and the scenario file ([`output::write_files`]). Returns
/// the rows written and the rig and scenario paths shown in the summary.
pub(super) fn write_files<F>(
    args: &Args,
    out: Outputs<'_, F>,
) -> anyhow::Result<(u64, String, String)>
where
    F: FnOnce(&OutputFile) -> anyhow::Result<u64>,
{
    let Some(log) = args.output.clone() else {
        bail!("give -o LOG.csv");
    };
    let (n, rig_path, scen_path) = output::write_files(&log, args.rig_out.as_deref(), out)?;
    let shown = |p: &Option<PathBuf>, none: &str| {
        p.as_ref()
            .map_or(none.to_string(), |p| p.display().to_string())
    };
    Ok((
        n,
        shown(
            &rig_path,
            "none (no file beside standard output or a device: give --rig-out FILE)",
        ),
        shown(&scen_path, "none"),
    ))
}

/// The error for a scenario name that is neither planar nor 3-D, listing both.
fn unknown_scenario(name: &str) -> anyhow::Error {
    anyhow::anyhow!(
        "unknown scenario '{name}' (planar: {}; 3-D: {})",
        planar::SCENARIO_NAMES.join(", "),
        crate::sim::SCENARIO3D_NAMES.join(", ")
    )
}

/// Runs `pendtilt simulate`: refuses an output that is an input (`--config`, `--rig`) or
/// another output, and renames the log, rig and scenario files into place only when all
/// were written. A 3-D scenario (by name, or a `--config` file written for one) goes to
/// [`super::simulate3d`].
pub fn run(args: Args) -> anyhow::Result<()> {
    if let Some(name) = &args.scenario {
        if crate::sim::SCENARIO3D_NAMES.contains(&name.as_str()) {
            return super::simulate3d::run(args);
        }
        if args.config.is_none() && !planar::SCENARIO_NAMES.contains(&name.as_str()) {
            return Err(unknown_scenario(name));
        }
    }
    if let Some(path) = &args.config {
        if super::simulate3d::is_3d_config(path) {
            return super::simulate3d::run(args);
        }
    }
    let (scenario, seed) = resolve(&args)?;
    if !args.quiet {
        for d in length_doubts(&args, &scenario)? {
            eprintln!("warning: {d}");
        }
        for d in unit_doubts(&args, &scenario) {
            eprintln!("warning: {d}");
        }
    }
    // Every key is written below, so the base only has to exist.
    let base = args.scenario.clone().unwrap_or_else(|| "still".into());
    let scenario_text = format!(
        "# Resolved scenario written by `pendtilt simulate`; rerun with\n\
         # pendtilt simulate --config THIS_FILE -o NEW.csv (another log name: the scenario file\n# beside NEW.csv must not be THIS_FILE)\nscenario = \"{base}\"\nseed = {seed}\n{}",
        scenario.to_toml()
    );
    if args.print_scenario {
        print!("{scenario_text}");
        return Ok(());
    }
    let mut inputs = Vec::new();
    if let Some(p) = &args.config {
        inputs.push(NamedPath::new("--config", p));
    }
    if let Some(p) = &args.settings.rig {
        inputs.push(NamedPath::new("--rig", p));
    }
    let started = Instant::now();
    let quiet = args.quiet;
    let (n, rig_shown, scen_shown) = write_files(
        &args,
        Outputs {
            rig_text: scenario.rig()?.to_toml_string(),
            scenario_text,
            inputs,
            write_log: |log: &OutputFile| write_outputs(&scenario, seed, log, quiet),
        },
    )?;
    if !args.quiet {
        super::summary::say_err!(
            "wrote {n} rows ({} s at {} Hz, seed {seed}) to {} in {:.2} s; rig: {}; scenario: {}",
            scenario.duration,
            scenario.rate,
            args.output
                .as_deref()
                .unwrap_or(std::path::Path::new("-"))
                .display(),
            started.elapsed().as_secs_f64(),
            rig_shown,
            scen_shown
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_log_above_a_gigabyte_is_announced_with_its_size_and_the_room() {
        // `--rate 1e9` began a 100 GB file without a word.
        let dir = tempfile::tempdir().unwrap();
        let log = dir.path().join("big.csv");
        assert_eq!(size_warning(&log, 1_000_000, 104.0), None);
        let w = size_warning(&log, 2_000_000_000, 104.0).unwrap();
        assert!(
            w.contains("big.csv: 2000000000 rows of about 104 bytes are about 208.0 GB")
                && w.contains("Ctrl-C stops the run and removes the partial file"),
            "{w}"
        );
        let w = size_warning(&log, 1_000_000_000_000_000, 104.0).unwrap();
        assert!(w.contains("GB free: it may not fit"), "{w}");
        // Standard output and a device keep nothing.
        assert_eq!(size_warning(Path::new("-"), 2_000_000_000, 104.0), None);
        assert_eq!(
            size_warning(Path::new("/dev/null"), 2_000_000_000, 104.0),
            None
        );
    }
}

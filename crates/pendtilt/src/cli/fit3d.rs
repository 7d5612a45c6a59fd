//! `pendtilt fit LOG3D -o RIG`: the Cardan pendulum's parameters from a 3-D log
//! ([`crate::fit::cardan`]), written as a 3-D rig file that `pendtilt estimate LOG3D
//! --params RIG` reads as it is.
use anyhow::{ensure, Context};

use super::fit::Args;
use crate::bank::spatial::rig::Rig3dConfig;
use crate::fit::cardan::steps::{mass_length, mounting_warning, read_log, settings, Fit3dOptions};
use crate::fit::cardan::{
    self, fit_cardan, Fit3dReport, Fit3dSettings, Implausible3d, NAMES, NP, UNITS,
};
use crate::fit::plausibility::LogSpan;
use crate::fit::{Algorithm, Cost, Iteration, Method, Target};
use crate::io::output::{self, NamedPath};

/// Runs the 3-D fit: refuses an output that is an input, fits, and writes the rig file
/// all at once (an earlier file stays as it was when the fit fails or is implausible).
pub fn run(args: &Args) -> anyhow::Result<()> {
    let mut inputs = vec![NamedPath::new("LOG", &args.log)];
    if let Some(p) = &args.params {
        inputs.push(NamedPath::new("--params", p));
    }
    output::check_distinct(&inputs, &[NamedPath::new("-o", &args.output)])?;
    let text = fit(args).with_context(|| output::not_written(&args.output))?;
    output::write_atomic("-o", &args.output, text.as_bytes())?;
    if !args.quiet {
        super::summary::say_err!("wrote {}", args.output.display());
    }
    Ok(())
}

/// The planar fit's options that a 3-D fit cannot honour, refused by name.
fn refuse_planar_options(args: &Args) -> anyhow::Result<()> {
    let planar = [
        ("--method newton", args.method == Some(Method::Newton)),
        ("--algorithm", args.algorithm != Algorithm::Alg2),
        ("--a", args.a.is_some()),
        ("--b", args.b.is_some()),
        ("--cost inverse", args.cost == Cost::Inverse),
        ("--accel-drive", args.accel_drive),
        ("--no-accel-drive", args.no_accel_drive),
        ("--mean-square", args.mean_square),
        ("--unmatched", args.unmatched),
    ];
    let given: Vec<&str> = planar.iter().filter(|g| g.1).map(|g| g.0).collect();
    ensure!(
        given.is_empty(),
        "{}: for planar logs only; {} is a 3-D log, whose fit is the output error of the \
         Cardan pendulum (MODEL.md 7.3) by Levenberg-Marquardt, always driven by the \
         accelerometer",
        given.join(", "),
        args.log.display()
    );
    for (name, v) in [
        ("--mass", args.mass),
        ("--length", args.length),
        ("--accel-noise", args.accel_noise),
        ("--gyro-noise", args.gyro_noise),
    ] {
        if let Some(v) = v {
            let ok = v.is_finite()
                && if name.ends_with("noise") {
                    v >= 0.0
                } else {
                    v > 0.0
                };
            ensure!(ok, "{name} {v}: must be a finite number > 0 (noise: >= 0)");
        }
    }
    Ok(())
}

/// The start rig: `--params` (a 3-D rig file) or MODEL.md 7.6's.
fn start_rig(args: &Args) -> anyhow::Result<Rig3dConfig> {
    match &args.params {
        Some(p) => Rig3dConfig::load(p).map_err(anyhow::Error::msg),
        None => Ok(Rig3dConfig::default()),
    }
}

/// The 3-D fit's options these arguments give.
fn options(args: &Args) -> Fit3dOptions {
    Fit3dOptions {
        target: args.target,
        skip: args.skip,
        smoothing_hz: args.smoothing_hz,
        no_encoder_offset: args.no_encoder_offset,
        max_iterations: args.max_iterations,
        accel_noise: args.accel_noise,
        gyro_noise: args.gyro_noise,
    }
}

/// Reads, fits, prints, checks; returns the rig file's text.
fn fit(args: &Args) -> anyhow::Result<String> {
    refuse_planar_options(args)?;
    let rig = start_rig(args)?;
    let mass_length = mass_length(args.mass, args.length, &rig)?;
    let name = args.log.display().to_string();
    let (log, speed) = read_log(&args.log, &name, &args.columns)?;
    if !args.quiet {
        eprintln!("{name}: read {} rows of a 3-D log", log.t.len());
    }
    if let Some(w) = mounting_warning(args.params.as_deref(), &rig, speed) {
        eprintln!("{w}");
    }
    // The fit is driven by the specific force: a wrong unit is said before it runs.
    let unit = crate::units::AccelMagnitude::of_vectors(&log.accel)
        .finding("ax, ay, az", args.columns.accel_unit);
    if let Some(f) = unit {
        eprintln!("warning: {}: {}", args.log.display(), f.message);
    }
    ensure!(
        args.target != Target::Truth || log.has_truth(),
        "{} has no finite `roll` and `pitch` in every row, which --target truth (the default) \
         fits against; without them, --target gyro drives the simulated pendulum with the \
         log's own gyro and accelerometer",
        args.log.display()
    );
    let (settings, noise) = settings(&options(args), &log);
    let start = rig.pendulum3d.params();
    let quiet = args.quiet;
    if !quiet {
        print_header(args, &start, &noise);
    }
    let show = |it: &Iteration| {
        if !quiet {
            let p: Vec<String> = it.params.iter().map(|v| format!("{v:>12.5e}")).collect();
            eprintln!(
                "{:>4} {} {:>11.4e} {:>9.2e} {:>5}",
                it.n,
                p.join(" "),
                it.cost,
                it.step,
                it.evaluations
            );
        }
    };
    let span = LogSpan::of(log.t.iter().copied());
    let hint = match span {
        Some(s) if s.median_step >= 0.05 => format!(
            " (the log's median time step is {:.3} s: if its time column is in ms, give \
             --time-unit ms)",
            s.median_step
        ),
        _ => String::new(),
    };
    let report = fit_cardan(&log, &start, rig.mounting.accel_at, &settings, show)
        .map_err(|e| anyhow::anyhow!("{e}{hint}"))?;
    let implausible = span.map_or_else(Vec::new, |s| cardan::check(&report.fitted, &s));
    let on_stdout = output::is_stdout(&args.output);
    print_result(&report, &implausible, on_stdout);
    check_result(args, &implausible, &hint)?;
    let header = vec![
        format!(
            "fitted by `pendtilt fit` from {} ({:?} target, output error, RMS residual {:.4e} rad)",
            args.log.display(),
            report.target,
            report.cost
        ),
        format!(
            "encoder offsets found: phi_x {:+.4e} rad, phi_y {:+.4e} rad (not a rig key)",
            report.params[5], report.params[6]
        ),
    ];
    cardan::rig::rig_toml(&report.fitted, mass_length, &rig, &header).map_err(anyhow::Error::msg)
}

/// What is fitted, what is held, and the iteration table's header (stderr).
fn print_header(
    args: &Args,
    start: &pendtilt_core::spatial::cardan::CardanParams<f64>,
    noise: &str,
) {
    let drive = match args.target {
        Target::Truth => {
            "the true roll and pitch, the gyro's yaw rate and the accelerometer's fast part"
        }
        Target::Gyro => "the log's gyro and accelerometer",
    };
    eprintln!(
        "fitting the Cardan pendulum (MODEL.md 7.3) by Levenberg-Marquardt: output error, \
         phi_x, phi_y measured - simulated (rad), the pendulum driven by {drive}"
    );
    eprintln!(
        "held at the start rig's values: b_z = {:.4e} s^2, b_ring = {:.4e} s^2 (only b_x + \
         b_ring shows), c_x = {:.4e}, c_y = {:.4e} s^2 (only yaw motion shows them), gravity \
         = {} m/s^2 (the normalisation)",
        start.b_z, start.b_ring, start.c[0], start.c[1], start.gravity
    );
    eprintln!("{noise}");
    let names: Vec<String> = NAMES.iter().map(|n| format!("{n:>12}")).collect();
    eprintln!(
        "{:>4} {} {:>11} {:>9} {:>5}",
        "iter",
        names.join(" "),
        "rms",
        "lambda",
        "sims"
    );
}

/// The verdict, each parameter with its start and result, the pendulum per axis.
fn print_result(r: &Fit3dReport, implausible: &[Implausible3d], on_stdout: bool) {
    let say = |text: String| super::summary::print(on_stdout, &text);
    let verdict = if implausible.is_empty() {
        format!("{:?}", r.stop)
    } else {
        format!("IMPLAUSIBLE (the optimiser stopped: {:?})", r.stop)
    };
    say(format!(
        "{verdict} after {} iterations ({} simulations of the log, {:.1} s): RMS residual \
         {:.4e} -> {:.4e} rad (phi_x {:.4e}, phi_y {:.4e}) over {} rows",
        r.iterations.len() - 1,
        r.evaluations,
        r.elapsed.as_secs_f64(),
        r.start_cost,
        r.cost,
        r.cost_per_axis[0],
        r.cost_per_axis[1],
        r.rows
    ));
    say(format!(
        "  {:<22} {:>13} {:>13}",
        "parameter", "start", "fitted"
    ));
    for j in 0..NP {
        let name = format!("{} [{}]", NAMES[j], UNITS[j]);
        let result = if r.active[j] {
            format!("{:>13.6e}", r.params[j])
        } else {
            format!("{:>13}", "held")
        };
        say(format!("  {name:<22} {:>13.6e} {result}", r.start[j]));
    }
    if !r.active[4] {
        say(format!(
            "  c_z held: a 1 cm pivot offset moves the encoders by only {:.2e} rad RMS in this \
             log (fitted from {:.0e})",
            r.offset_sensitivity,
            Fit3dSettings::default().min_offset_sensitivity
        ));
    }
    let (f, z) = (r.natural_frequencies_hz(), r.damping_ratios());
    for (i, axis) in ["outer (x)", "inner (y)"].iter().enumerate() {
        say(format!(
            "  {axis}: natural frequency {:.4} Hz, damping ratio {:.4}",
            f[i], z[i]
        ));
    }
    say(format!(
        "  b_x = {:.6e} s^2 (b_x + b_ring less the held b_ring)",
        r.fitted.b_x
    ));
}

/// Refuses an implausible fit unless `--accept-implausible` (then it warns).
fn check_result(args: &Args, implausible: &[Implausible3d], hint: &str) -> anyhow::Result<()> {
    if implausible.is_empty() {
        return Ok(());
    }
    let why: Vec<String> = implausible.iter().map(|i| format!("  - {i}")).collect();
    ensure!(
        args.accept_implausible,
        "the fitted Cardan pendulum is implausible for this log:\n{}\n{} not written; check \
         the log's units (time in s, angles in rad or --deg) and that it moves the pendulum, \
         or pass --accept-implausible to write it anyway{hint}",
        why.join("\n"),
        args.output.display()
    );
    eprintln!(
        "warning: the fitted Cardan pendulum is implausible for this log (written anyway, \
         --accept-implausible):\n{}",
        why.join("\n")
    );
    Ok(())
}

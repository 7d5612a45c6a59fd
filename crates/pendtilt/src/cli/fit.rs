//! `pendtilt fit LOG.csv --target truth|gyro --method newton|lm [--algorithm alg1|alg2|alg3]
//! -o RIG.toml`: fits the pendulum's parameters to a log (paper section IV-B, C) and writes a
//! rig file that `pendtilt estimate` reads as it is.
use std::path::PathBuf;

use anyhow::Context;

use crate::config::RigConfig;
use crate::fit::steps::{check_result, check_smoothing, fitted_rig, time_hint, FitLog, FitOptions};
use crate::fit::{self, Algorithm, Cost, Iteration, Method, Target};
use crate::io::output::{self, NamedPath};
use pendtilt_core::PendulumParams;

/// Options of `pendtilt fit`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The sensor log (CSV, MODEL.md section 5).
    pub log: PathBuf,
    /// Cost: `truth` = Eq (23) against the `theta` column; `gyro` = Eq (29) against the gyro.
    #[arg(long, value_enum, default_value = "truth")]
    pub target: Target,
    /// Optimiser: `newton` = the paper's Eqs (24)-(28); `lm` = Levenberg-Marquardt.
    /// Default: newton on a planar log; a 3-D log is fitted by lm only.
    #[arg(long, value_enum)]
    pub method: Option<Method>,
    /// Cost. `auto` (default) = `output` where it applies (truth target, alg1/alg2), else
    /// `inverse`. `output` = the pendulum simulated from the true angle against the
    /// measured phi: stays within 5 % of a, b under vibration and noise. `inverse` = the
    /// paper's Eq (23)/(29), the inverted estimate against the target: BIASED under
    /// vibration (b 29 % low on the 60 s scooter ride); the only cost for `--target gyro`
    /// and alg3.
    #[arg(long, value_enum, default_value = "auto")]
    pub cost: Cost,
    /// Output cost: cutoff of the zero-phase smoothing of the true angle (Hz).
    #[arg(long, default_value_t = 20.0)]
    pub smoothing_hz: f64,
    /// Output cost: always drive the simulated pendulum with the accelerometer's specific
    /// force (`ax`, `ay`, at the pivot) so that floor vibration is an input, not a
    /// disturbance. Default: on when the log's accelerometer vibrates (high-frequency RMS
    /// above 0.5 m/s^2), off otherwise.
    #[arg(long, conflicts_with = "no_accel_drive")]
    pub accel_drive: bool,
    /// Output cost: never drive the simulated pendulum with the accelerometer.
    #[arg(long)]
    pub no_accel_drive: bool,
    /// Write the rig file even when the fitted pendulum is implausible (damping ratio
    /// above 2, natural frequency outside the log's band); it is still reported.
    #[arg(long)]
    pub accept_implausible: bool,
    /// Which parameters: alg1/alg2 fit a, b; alg3 fits K, L, M, N.
    #[arg(long, value_enum, default_value = "alg2")]
    pub algorithm: Algorithm,
    /// Where to write the fitted rig file (TOML).
    #[arg(long, short = 'o', visible_alias = "out")]
    pub output: PathBuf,
    /// Rig file with the start values (and the differentiator settings). Default: the
    /// MODEL.md rig.
    #[arg(long, short = 'p')]
    pub params: Option<PathBuf>,
    /// Start a (s) (overrides the rig file).
    #[arg(long, allow_negative_numbers = true, help = super::help::fit_start('a'))]
    pub a: Option<f64>,
    /// Start b (s^2) (overrides the rig file).
    #[arg(long, allow_negative_numbers = true, help = super::help::fit_start('b'))]
    pub b: Option<f64>,
    /// Newton's step factor h (Eq 24).
    #[arg(long, default_value_t = 1.0)]
    pub h: f64,
    /// Newton's finite difference dp (Eqs 25-28), absolute.
    #[arg(long, default_value_t = 1e-6)]
    pub dp: f64,
    /// Iteration limit.
    #[arg(long, default_value_t = 100)]
    pub max_iterations: usize,
    /// Newton: stop when the cost changes by less than this fraction.
    #[arg(long, default_value_t = 1e-10)]
    pub ftol: f64,
    /// Newton: stop when every parameter changes by less than this fraction.
    #[arg(long, default_value_t = 1e-8)]
    pub xtol: f64,
    /// Newton minimises the mean square instead of the paper's RMS (same minimiser).
    #[arg(long)]
    pub mean_square: bool,
    /// Seconds at the start left out while the differentiators settle (the output cost
    /// leaves out at least 1 s while the simulated pendulum forgets its start).
    #[arg(long, default_value_t = 0.5)]
    pub skip: f64,
    /// Compare with the raw target (the paper's cost as printed) instead of the target
    /// through the same low-pass as phi.
    #[arg(long)]
    pub unmatched: bool,
    /// How the log's columns are named and in which units.
    #[command(flatten)]
    pub columns: crate::cli::options::LogColumns,
    /// 3-D logs: the pendulum's mass m (kg), to write the physical `[pendulum3d]` form.
    /// Default: none, the normalised form (or the start rig's mass with --length).
    #[arg(long)]
    pub mass: Option<f64>,
    /// 3-D logs: the pendulum's length l, pivot to centre of mass (m), to write the
    /// physical form. Default: none, the normalised form (or the start rig's length with
    /// --mass).
    #[arg(long)]
    pub length: Option<f64>,
    /// 3-D logs: the accelerometer's white-noise density (m/s^2/sqrt(Hz)), whose effect on
    /// the simulated pendulum the cost takes out. Default: measured over the log's
    /// initial rest, else no correction.
    #[arg(long)]
    pub accel_noise: Option<f64>,
    /// 3-D logs, `--target gyro`: the gyro's white-noise density (rad/s/sqrt(Hz)), as
    /// --accel-noise. Default: measured over the log's initial rest, else no correction.
    #[arg(long)]
    pub gyro_noise: Option<f64>,
    /// 3-D logs: do not fit the constant encoder offsets. Default: fitted (and reported;
    /// the rig file has no key for them).
    #[arg(long)]
    pub no_encoder_offset: bool,
    /// Print nothing but errors.
    #[arg(long, short = 'q')]
    pub quiet: bool,
}

impl Args {
    /// The optimiser of a planar fit (Newton unless --method says otherwise).
    fn planar_method(&self) -> Method {
        self.method.unwrap_or(Method::Newton)
    }

    /// The planar fit's options these arguments give.
    fn options(&self) -> FitOptions {
        FitOptions {
            algorithm: self.algorithm,
            target: self.target,
            method: self.planar_method(),
            cost: self.cost,
            start_given: self.a.is_some() || self.b.is_some(),
            mean_square: self.mean_square,
            skip: self.skip,
            unmatched: self.unmatched,
            h: self.h,
            dp: self.dp,
            max_iterations: self.max_iterations,
            ftol: self.ftol,
            xtol: self.xtol,
            smoothing_hz: self.smoothing_hz,
            accel_drive: self.accel_drive,
            no_accel_drive: self.no_accel_drive,
        }
    }
}

/// Runs `pendtilt fit`: refuses an output that is an input, fits, and writes the rig file
/// all at once (an earlier file stays as it was when the fit fails).
pub fn run(args: Args) -> anyhow::Result<()> {
    // A map onto planar columns reads one axis of a 3-D log as planar: the planar path.
    let map = &args.columns.map;
    let spatial = super::estimate3d::is_3d_log(&args.log, map) && map.planar_only().is_empty();
    if spatial || !map.spatial_only().is_empty() {
        return super::fit3d::run(&args);
    }
    super::estimate3d::refuse_3d_options(
        &[
            ("--mass", args.mass.is_some()),
            ("--length", args.length.is_some()),
            ("--accel-noise", args.accel_noise.is_some()),
            ("--gyro-noise", args.gyro_noise.is_some()),
            ("--no-encoder-offset", args.no_encoder_offset),
        ],
        &args.log,
    )?;
    let mut inputs = vec![NamedPath::new("LOG", &args.log)];
    if let Some(p) = &args.params {
        inputs.push(NamedPath::new("--params", p));
    }
    output::check_distinct(&inputs, &[NamedPath::new("-o", &args.output)])?;
    let rig = fit_rig(&args).with_context(|| output::not_written(&args.output))?;
    output::write_atomic("-o", &args.output, rig.to_toml_string().as_bytes())?;
    if !args.quiet {
        super::summary::say_err!("wrote {}", args.output.display());
    }
    Ok(())
}

/// Reads the log, fits, prints the iterations and the result, and returns the fitted rig:
/// the command's steps, in order.
fn fit_rig(args: &Args) -> anyhow::Result<RigConfig> {
    check_options(args)?;
    let rig = match &args.params {
        Some(p) => super::options::load_rig(p, args.quiet)?,
        None => RigConfig::default(),
    };
    let start = PendulumParams {
        a: args.a.unwrap_or(rig.params().a),
        b: args.b.unwrap_or(rig.params().b),
        ..rig.params()
    };
    let log = read_log(args, &rig)?;
    // Said before any work, with the way out (it used to come after the iteration header).
    anyhow::ensure!(
        args.target != Target::Truth || log.has_theta,
        "{} has no `theta` column (the true angle), which --target truth (the default) fits \
         against; without a true angle, --target gyro fits from the gyro and the pendulum \
         (Eq 29)",
        args.log.display()
    );
    let settings = args.options().settings(&rig, start);
    let cost = args.cost.resolve(args.target, args.algorithm);
    anyhow::ensure!(
        !(args.accel_drive || args.no_accel_drive) || cost == Cost::Output,
        "--accel-drive and --no-accel-drive apply to the output cost only (this fit runs {})",
        cost.describe()
    );
    let span = fit::plausibility::LogSpan::of(log.stamps.iter().copied());
    let truth_opt = log.has_theta.then_some(&log.truth[..]);
    let hint = time_hint(span);
    if let (Cost::Output, Some(s)) = (cost, span) {
        check_smoothing(args.smoothing_hz, &s)?;
    }
    let with_hint = |e: fit::FitError| anyhow::anyhow!("{e}{hint}");
    let problem = match cost {
        Cost::Output => None,
        _ => Some(fit::prepare(&log.samples, truth_opt, &settings).map_err(with_hint)?),
    };
    let quiet = args.quiet;
    if !quiet {
        print_fit_header(args, problem.as_ref());
    }
    let show = |it: &Iteration| {
        if !quiet {
            let p: Vec<String> = it.params.iter().map(|v| format!("{v:>13.6e}")).collect();
            eprintln!(
                "{:>4} {} {:>12.5e} {:>10.3e} {:>10.3e} {:>5}",
                it.n,
                p.join(" "),
                it.cost,
                it.gradient_norm,
                it.step,
                it.evaluations
            );
        }
    };
    let report = match &problem {
        Some(problem) => fit::fit(problem, &settings, show),
        None => fit::fit_output_log(&log.samples, truth_opt, &settings, show),
    }
    .map_err(with_hint)?;
    if !quiet && report.cost_kind == Cost::Output {
        eprintln!("{}", accel_note(&report));
    }
    let fitted = report.pendulum_params();
    // alg3's K, L are gains that may take up the differentiator's delay, not a pendulum.
    let implausible = match (args.algorithm, span) {
        (Algorithm::Alg3, _) | (_, None) => Vec::new(),
        (_, Some(span)) => fit::plausibility::check(&fitted, &span),
    };
    print_result(
        &report,
        &fitted,
        &implausible,
        crate::io::output::is_stdout(&args.output),
    );
    check(args, &report, &fitted, &implausible)?;
    fitted_rig(args.algorithm, rig, &report, fitted, problem.as_ref())
}

/// Reads the whole log (what it finds said on stderr unless `--quiet`).
fn read_log(args: &Args, rig: &RigConfig) -> anyhow::Result<FitLog> {
    FitLog::read(&args.log, args.columns.reader_options(rig), |m| {
        if !args.quiet {
            eprintln!("{m}");
        }
    })
}

/// [`check_result`] with the command's options, its warning on stderr.
fn check(
    args: &Args,
    report: &fit::FitReport,
    fitted: &PendulumParams<f64>,
    implausible: &[fit::plausibility::Implausible],
) -> anyhow::Result<()> {
    let warn = |w: &str| eprintln!("{w}");
    check_result(
        args.accept_implausible,
        &args.output,
        report,
        fitted,
        implausible,
        warn,
    )
}

/// The numeric options no fit can run with, refused with the option's name and the valid
/// range before the log is read (`--xtol nan` was blamed on "Newton h and dp", `--skip -1`
/// and a negative tolerance were taken as they were).
fn check_options(args: &Args) -> anyhow::Result<()> {
    let finite = |v: f64| v.is_finite();
    for (name, v, ok, range) in [
        (
            "--h",
            args.h,
            finite(args.h) && args.h > 0.0,
            "a finite number > 0",
        ),
        (
            "--dp",
            args.dp,
            finite(args.dp) && args.dp > 0.0,
            "a finite number > 0",
        ),
        (
            "--ftol",
            args.ftol,
            finite(args.ftol) && args.ftol >= 0.0,
            "a finite fraction >= 0",
        ),
        (
            "--xtol",
            args.xtol,
            finite(args.xtol) && args.xtol >= 0.0,
            "a finite fraction >= 0",
        ),
        (
            "--skip",
            args.skip,
            finite(args.skip) && args.skip >= 0.0,
            "a finite number of seconds >= 0",
        ),
        (
            "--smoothing-hz",
            args.smoothing_hz,
            finite(args.smoothing_hz) && args.smoothing_hz > 0.0,
            "a finite frequency > 0 [Hz], below the log's Nyquist frequency",
        ),
    ] {
        anyhow::ensure!(ok, "{name} {v}: must be {range}");
    }
    Ok(())
}

/// What is fitted, on which cost, and the iteration table's header (stderr).
fn print_fit_header(args: &Args, problem: Option<&fit::Problem>) {
    let unit = match args.target {
        Target::Truth => "rad",
        Target::Gyro => "rad/s",
    };
    {
        match problem {
            Some(problem) => eprintln!(
                "fitting {} of {:?} by {:?} on {} samples (the paper's inverse cost, Eq {} in \
                 {unit}, differentiator cutoff {:.3} Hz; biased under vibration)",
                args.algorithm.names().join(", "),
                args.algorithm,
                args.planar_method(),
                problem.len(),
                if args.target == Target::Truth { 23 } else { 29 },
                problem.cutoff_hz(),
            ),
            None => eprintln!(
                "fitting {} of {:?} by {:?} (output error: RMS of phi measured - phi simulated \
                 from the true angle, in rad; truth smoothed at {:.3} Hz)",
                args.algorithm.names().join(", "),
                args.algorithm,
                args.planar_method(),
                args.smoothing_hz,
            ),
        }
        let names: Vec<String> = args
            .algorithm
            .names()
            .iter()
            .map(|n| format!("{n:>13}"))
            .collect();
        eprintln!(
            "{:>4} {} {:>12} {:>10} {:>10} {:>5}",
            "iter",
            names.join(" "),
            "cost",
            "|grad|",
            if args.planar_method() == Method::Newton {
                "step"
            } else {
                "lambda"
            },
            "evals"
        );
    }
}

/// The verdict, the parameters and the pendulum they make (stdout).
fn print_result(
    report: &fit::FitReport,
    fitted: &pendtilt_core::PendulumParams<f64>,
    implausible: &[fit::plausibility::Implausible],
    data_on_stdout: bool,
) {
    let say = |text: String| super::summary::print(data_on_stdout, &text);
    let verdict = if implausible.is_empty() {
        format!("{:?}", report.stop)
    } else {
        format!("IMPLAUSIBLE (the optimiser stopped: {:?})", report.stop)
    };
    say(format!(
        "{verdict} after {} iterations ({} passes over the log, {:.1} ms): cost {:.4e} -> {:.4e} {}",
        report.iterations.len() - 1,
        report.evaluations,
        report.elapsed.as_secs_f64() * 1e3,
        report.start_cost,
        report.cost,
        report.cost_unit()
    ));
    for (n, v) in report.names.iter().zip(&report.params) {
        say(format!("  {n} = {v:.6e}"));
    }
    if fitted.b > 0.0 && fitted.a.is_finite() {
        say(format!(
            "  natural frequency {:.4} Hz ({:.3} rad/s), damping ratio {:.4}",
            fitted.natural_frequency_hz(),
            fitted.natural_frequency(),
            fitted.damping_ratio()
        ));
    }
}

/// One line on how the output cost ran: with or without the accelerometer, and why.
fn accel_note(report: &fit::FitReport) -> String {
    let vib = report.vibration_rms.map_or_else(
        || "no usable ax, ay".to_string(),
        |v| format!("accelerometer high-frequency RMS {v:.2} m/s^2"),
    );
    if report.accel_drive {
        format!("output cost driven by the accelerometer ({vib}; --no-accel-drive to switch off)")
    } else {
        format!(
            "output cost driven by gravity alone ({vib}, threshold {} m/s^2; --accel-drive to \
             use it)",
            fit::output::VIBRATION_RMS
        )
    }
}

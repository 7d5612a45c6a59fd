//! `pendtilt reproduce -o DIR`: the paper's experiment and figures on built-in simulated
//! data (see [`crate::experiment`]), with progress bars and the claims table on stdout.
use std::cell::RefCell;
use std::path::PathBuf;
use std::time::{Duration, Instant};

use anyhow::Context;
use indicatif::{ProgressBar, ProgressStyle};

use crate::experiment::{self, Progress, ReproduceConfig};
use crate::io::output::{self, OutputDir};
use crate::report::claims::Claim;

/// Options of `pendtilt reproduce`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Directory to write into (created): index.html, report.md, claims.json, scooter/,
    /// sigmoid/, and the 3-D scenarios still3d/, scooter3d/, ship3d/, ride3d/.
    #[arg(long, short = 'o', visible_alias = "out")]
    pub output: PathBuf,
    /// Length of the scooter test ride (s).
    #[arg(long, default_value_t = 60.0)]
    pub duration: f64,
    /// Length of the separate calibration ride (s).
    #[arg(long, default_value_t = 30.0)]
    pub calibration: f64,
    /// Seed of the test ride (the calibration ride uses seed + 1, the sigmoid seed + 2; the
    /// 3-D scenarios seed).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// No progress bars.
    #[arg(long, short = 'q')]
    pub quiet: bool,
}

/// Progress bars on standard error (hidden when it is not a terminal, or with `--quiet`).
pub struct Bars {
    bar: RefCell<Option<ProgressBar>>,
    quiet: bool,
}

impl Bars {
    /// Bars, or nothing at all with `quiet`.
    pub fn new(quiet: bool) -> Self {
        Self {
            bar: RefCell::new(None),
            quiet,
        }
    }

    /// Ends the current bar.
    pub fn finish(&self) {
        if let Some(b) = self.bar.borrow_mut().take() {
            b.finish_and_clear();
        }
    }
}

impl Progress for Bars {
    fn stage(&self, what: &str, total: u64) {
        self.finish();
        if self.quiet {
            return;
        }
        let bar = if total == 0 {
            let b = ProgressBar::new_spinner();
            b.enable_steady_tick(Duration::from_millis(120));
            b
        } else {
            let b = ProgressBar::new(total);
            if let Ok(style) = ProgressStyle::with_template(
                "{msg:48} [{bar:30}] {percent:>3}% {elapsed_precise} eta {eta}",
            ) {
                b.set_style(style.progress_chars("=> "));
            }
            b
        };
        bar.set_message(what.to_string());
        *self.bar.borrow_mut() = Some(bar);
    }

    fn advance(&self, n: u64) {
        if let Some(b) = self.bar.borrow().as_ref() {
            b.inc(n);
        }
    }

    fn message(&self, text: &str) {
        if self.quiet || text.is_empty() {
            return;
        }
        // A hidden bar (standard error not a terminal) prints nothing: say it plainly.
        match self.bar.borrow().as_ref() {
            Some(b) if !b.is_hidden() => b.println(text),
            _ => eprintln!("{text}"),
        }
    }
}

/// The claims as a plain-text table for the terminal.
pub fn claims_text(claims: &[Claim]) -> String {
    let mut s = String::new();
    for c in claims {
        s.push_str(&format!(
            "[{}] {}\n      {}\n",
            match c.verdict() {
                "yes" => "holds",
                "no" => "FAILS",
                _ => "n/a",
            },
            c.claim,
            c.measured
        ));
    }
    s
}

/// Runs `pendtilt reproduce`.
pub fn run(args: Args) -> anyhow::Result<()> {
    anyhow::ensure!(
        args.duration.is_finite() && args.duration >= 5.0,
        "--duration must be at least 5 s, got {}",
        args.duration
    );
    anyhow::ensure!(
        args.calibration.is_finite() && args.calibration >= 5.0,
        "--calibration must be at least 5 s, got {}",
        args.calibration
    );
    let started = Instant::now();
    let mut cfg = ReproduceConfig::with_durations(args.duration, args.calibration);
    cfg.scooter_seed = args.seed;
    cfg.calibration_seed = args.seed.wrapping_add(1);
    cfg.sigmoid_seed = args.seed.wrapping_add(2);
    for r in &mut cfg.spatial {
        r.seed = args.seed;
    }
    let bars = Bars::new(args.quiet);
    // Written into a staging directory beside --out, moved in only when complete.
    let out = OutputDir::create("-o", &args.output)?;
    let outcome = experiment::reproduce(&cfg, out.staging(), &bars);
    bars.finish();
    let outcome = outcome.with_context(|| output::not_written(&args.output))?;
    let (index, markdown, json) = (
        out.final_path(&outcome.index),
        out.final_path(&outcome.markdown),
        out.final_path(&outcome.json),
    );
    out.commit(&[])?;
    super::summary::say!("Claims ({} metrics):", outcome.claims_view);
    print!("{}", claims_text(&outcome.claims));
    super::summary::print(false, "");
    let t = &outcome.timings;
    super::summary::say!(
        "simulate {:.1} s, fit {:.1} s, estimate {:.1} s, report {:.1} s; total {:.1} s",
        t.simulate.as_secs_f64(),
        t.fit.as_secs_f64(),
        t.estimate.as_secs_f64(),
        t.report.as_secs_f64(),
        started.elapsed().as_secs_f64()
    );
    super::summary::say!("wrote {}", index.display());
    super::summary::say!("      {}", markdown.display());
    super::summary::say!("      {}", json.display());
    Ok(())
}

//! Step 3 of the examples: Algorithm 3 with its gains fitted live, with no true angle.
//!
//! Algorithm 3 (the paper's Eq 30) is Algorithm 2 with free gains K, L, M, N in place of
//! the rig's a and b. Its supervisor re-fits them while it runs by making the estimate's
//! rate agree with the gyro (Eq 29): a rig whose parameters are wrong, or drift, corrects
//! itself. Here the estimator starts from a pendulum described 50 % wrong.
//!
//! Run: `cargo run -p pendtilt-core --release --example supervised_alg3`
mod common;

use pendtilt_core::prelude::*;

fn main() {
    let rows = common::ride(30.0);

    // The true rig, and a wrong description of it: a and b 1.5 times too large.
    let truth = PendulumParams::<f64>::default();
    let wrong = PendulumParams {
        a: 1.5 * truth.a,
        b: 1.5 * truth.b,
        c: 0.0,
    };
    let mut settings = SupervisedAlg3Settings {
        alg3: Alg3Settings::from_params(wrong),
        ..SupervisedAlg3Settings::default()
    };
    // The paper's Newton's method on the last 1000 samples, every 0.25 s, minimising the
    // mean square of Eq (29) (nearly quadratic in the gains, so Newton converges fast).
    // `Method::Rls` is the cheap alternative: one recursive least-squares update a sample.
    settings.supervisor.method = Method::Newton;
    settings.supervisor.objective = Objective::MeanSquare;
    settings.supervisor.refit_interval = 250;
    // The window buffer's capacity (1024 samples) is a type parameter: no allocation.
    let mut supervised = SupervisedAlg3::<f64>::new(settings).expect("valid settings");
    // The same estimator with the wrong gains kept fixed, for comparison.
    let mut fixed = Alg3::<f64>::new(Alg3Settings::from_params(wrong));

    let start = supervised.gains();
    let mut gate = StepGate::<f64>::new();
    let (mut live, mut stuck) = (Vec::new(), Vec::new());
    for r in &rows {
        let s = Sample {
            dt: gate.step(r.t),
            phi: r.phi,
            gyro: r.gyro,
            ax: r.ax,
            ay: r.ay,
        };
        // `update_supervised` also says what the supervisor did (warming up, refit);
        // `update` (the `Estimator` trait) returns the estimate alone.
        live.push(supervised.update_supervised(&s).estimate.theta);
        stuck.push(fixed.update(&s).theta);
    }

    let g = supervised.gains();
    println!("gains relative to the true rig (K = a, L = b, M = -b on a clean rig):");
    println!(
        "  start : K/a {:.3}  L/b {:.3}  M/-b {:.3}",
        start.k / truth.a,
        start.l / truth.b,
        -start.m / truth.b
    );
    println!(
        "  end   : K/a {:.3}  L/b {:.3}  M/-b {:.3}  ({} refits)",
        g.k / truth.a,
        g.l / truth.b,
        -g.m / truth.b,
        supervised.refits()
    );
    // K (the damping term) is found; L and M move towards b and -b, but slowly on a
    // motion this gentle (phi'' is small), and that is enough for the estimate.
    // Errors over the last 10 s, once the gains have settled.
    let skip = rows.len() - 10_000;
    let live_err = common::rms_deg(&rows, &live, skip);
    let stuck_err = common::rms_deg(&rows, &stuck, skip);
    println!("RMS tilt error over the last 10 s:");
    println!("  wrong gains, fixed      : {stuck_err:6.3} deg");
    println!("  wrong gains, supervised : {live_err:6.3} deg");
    assert!(live_err < stuck_err);
}

//! Claims rows come from the metrics: holds, measured numbers and reasons.
use pendtilt::report::claims::{ClaimSpec, Expect, MetricKind};
use pendtilt::report::markdown::{claims_markdown, metrics_markdown};
use pendtilt::report::metrics::{compute_metrics, AngleUnit, Metrics, MetricsConfig};

fn metrics(name: &str, offset: f64) -> Metrics {
    let cfg = MetricsConfig {
        input_unit: AngleUnit::Deg,
        ..MetricsConfig::default()
    };
    let truth = vec![0.0; 20];
    let est = vec![offset; 20];
    compute_metrics(name, &est, &truth, 100.0, &cfg).unwrap()
}

#[test]
fn a_claim_holds_when_the_numbers_say_so() {
    let run = [metrics("alg1", 0.8), metrics("alg2", 0.2)];
    let c = ClaimSpec::new("Alg 2 beats Alg 1")
        .expect("alg2", MetricKind::Rms, Expect::Lower, "alg1")
        .because("it uses the gyro", "unexpected")
        .evaluate(&run);
    assert!(c.holds);
    assert_eq!(
        c.measured,
        "RMS error: alg2 0.200 deg vs alg1 0.800 deg (-75%)"
    );
    assert!(c.why.contains("lower") && c.why.ends_with("it uses the gyro"));

    let c = ClaimSpec::new("Alg 1 beats Alg 2")
        .expect("alg1", MetricKind::Rms, Expect::Lower, "alg2")
        .because("", "alg1 ignores theta''")
        .evaluate(&run);
    assert!(!c.holds);
    assert!(c.why.contains("is not lower") && c.why.ends_with("alg1 ignores theta''"));
}

#[test]
fn every_comparison_must_hold() {
    let run = [metrics("alg2", 0.5), metrics("alg3", 0.1)];
    // alg3: lower RMS (true) and more |bias| (false): the claim fails on the second
    let c = ClaimSpec::new("Alg 3 is better and more biased")
        .expect("alg3", MetricKind::Rms, Expect::Lower, "alg2")
        .expect("alg3", MetricKind::AbsBias, Expect::Higher, "alg2")
        .evaluate(&run);
    assert!(!c.holds);
    assert!(c.measured.contains("RMS error") && c.measured.contains("|bias|"));
}

#[test]
fn missing_estimators_and_unmeasured_metrics_do_not_hold() {
    let run = [metrics("alg1", 0.3), metrics("alg2", 0.1)];
    let c = ClaimSpec::new("ekf beats alg1")
        .expect("ekf", MetricKind::Rms, Expect::Lower, "alg1")
        .evaluate(&run);
    assert!(!c.holds);
    assert!(c.why.contains("ekf was not in the run"));
    // constant series: no lag can be measured
    let c = ClaimSpec::new("alg2 has less delay")
        .expect("alg2", MetricKind::LagMs, Expect::Lower, "alg1")
        .evaluate(&run);
    assert!(!c.holds);
    assert!(c.why.contains("could not be measured"), "{}", c.why);
    assert!(!ClaimSpec::new("empty").evaluate(&run).holds);
}

#[test]
fn markdown_tables_are_well_formed() {
    let run = [metrics("alg1", 0.3), metrics("alg2", 0.1)];
    let md = metrics_markdown(&run);
    // every table line has the same number of unescaped cell separators
    let table: Vec<&str> = md.lines().take_while(|l| l.starts_with('|')).collect();
    assert_eq!(table.len(), 4);
    let pipes = |l: &str| l.replace("\\|", "").matches('|').count();
    assert!(table.iter().all(|l| pipes(l) == pipes(table[0])), "{md}");
    let c = ClaimSpec::new("a | b")
        .expect("alg2", MetricKind::Rms, Expect::Lower, "alg1")
        .evaluate(&run);
    let cm = claims_markdown(&[c]);
    let rows: Vec<&str> = cm.lines().collect();
    assert_eq!(pipes(rows[0]), 5);
    assert_eq!(pipes(rows[2]), 5, "{cm}");
    assert!(rows[2].contains("| yes |"));
}

/// Claim 4 says what was run: with no K, L, M, N given it is "n/a" (Algorithm 3 then is
/// Algorithm 2), never a failure, and its wording says why; with fitted gains it is judged
/// and labelled as fitted.
#[test]
fn claim_4_is_labelled_by_the_gains_that_were_run() {
    use pendtilt::experiment::claims::{paper_claims, Alg3Gains, DifferentiatorInfo};
    let run = [
        metrics("accel", 2.0),
        metrics("pendulum", 1.0),
        metrics("alg1", 0.5),
        metrics("alg2", 0.4),
        metrics("alg3", 0.4),
        metrics("kf_accel", 1.0),
        metrics("kf_alg2", 0.3),
    ];
    let info = DifferentiatorInfo {
        cutoff_hz: 2.84,
        delay_ms: 147.0,
        natural_hz: 2.19,
    };
    let none = paper_claims(&run, false, &info, Alg3Gains::Eq21Equivalent);
    let c = none[3].evaluate(&run);
    assert!(c.claim.starts_with("4.") && c.claim.contains("no K, L, M, N given"));
    assert_eq!((c.applicable, c.holds, c.verdict()), (false, false, "n/a"));
    assert!(
        c.why.starts_with("Not applicable: no fitted K, L, M, N"),
        "{}",
        c.why
    );
    assert!(claims_markdown(&[c]).contains("| n/a |"));
    let fitted = paper_claims(&run, false, &info, Alg3Gains::Fitted)[3].evaluate(&run);
    assert!(fitted.claim.contains("fitted in this run") && fitted.applicable);
    assert_eq!(fitted.verdict(), "no");
    // the other claims are judged as before
    assert_eq!(none[0].evaluate(&run).verdict(), "yes");
}

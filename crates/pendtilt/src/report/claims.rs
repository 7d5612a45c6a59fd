//! Claims checked against measured metrics: "alg2 beats alg1", computed from the run.
//!
//! A [`ClaimSpec`] states a claim as one or more comparisons of a metric between two named
//! estimators; [`ClaimSpec::evaluate`] looks the numbers up in the run's [`Metrics`] and
//! returns a [`Claim`] row (claim, measured numbers, holds yes/no, why). Nothing in a row is
//! written by hand except the claim's wording and, optionally, the caller's explanation.
use serde::Serialize;

use super::metrics::Metrics;

/// A metric that claims can compare.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum MetricKind {
    /// RMS error \[deg\].
    Rms,
    /// Largest absolute error \[deg\].
    MaxAbs,
    /// |bias| \[deg\].
    AbsBias,
    /// Error standard deviation \[deg\].
    Std,
    /// Lag \[ms\].
    LagMs,
    /// Overshoot \[%\].
    OvershootPct,
    /// Settling time \[s\].
    SettlingS,
    /// Share within the tolerance band \[%\].
    WithinTolerancePct,
}

impl MetricKind {
    /// Short label with unit, as in the tables.
    pub fn label(self) -> &'static str {
        match self {
            MetricKind::Rms => "RMS error",
            MetricKind::MaxAbs => "max |error|",
            MetricKind::AbsBias => "|bias|",
            MetricKind::Std => "error std",
            MetricKind::LagMs => "lag",
            MetricKind::OvershootPct => "overshoot",
            MetricKind::SettlingS => "settling time",
            MetricKind::WithinTolerancePct => "share within tolerance",
        }
    }

    /// Unit of the value.
    pub fn unit(self) -> &'static str {
        match self {
            MetricKind::Rms | MetricKind::MaxAbs | MetricKind::AbsBias | MetricKind::Std => "deg",
            MetricKind::LagMs => "ms",
            MetricKind::OvershootPct | MetricKind::WithinTolerancePct => "%",
            MetricKind::SettlingS => "s",
        }
    }

    /// The value in a metrics row (`None` when it was not measured).
    pub fn value(self, m: &Metrics) -> Option<f64> {
        match self {
            MetricKind::Rms => Some(m.rms_deg),
            MetricKind::MaxAbs => Some(m.max_abs_deg),
            MetricKind::AbsBias => Some(m.bias_deg.abs()),
            MetricKind::Std => Some(m.std_deg),
            MetricKind::LagMs => m.lag_ms,
            MetricKind::OvershootPct => m.overshoot_pct,
            MetricKind::SettlingS => m.settling_time_s,
            MetricKind::WithinTolerancePct => Some(m.within_tolerance_pct),
        }
    }
}

/// Which way a comparison is expected to go.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Expect {
    /// The subject's value is strictly lower than the reference's.
    Lower,
    /// The subject's value is strictly higher.
    Higher,
}

/// One comparison: `subject`'s `metric` is `expect` than `reference`'s.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Comparison {
    /// Estimator the claim is about.
    pub subject: String,
    /// Metric compared.
    pub metric: MetricKind,
    /// Expected direction.
    pub expect: Expect,
    /// Estimator compared against.
    pub reference: String,
}

/// A claim to check: wording, comparisons (all must hold), optional explanations.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ClaimSpec {
    /// The claim in words ("Alg 2 beats Alg 1").
    pub claim: String,
    /// Comparisons that must all hold.
    pub comparisons: Vec<Comparison>,
    /// Added to the "why" column when the claim holds.
    pub why_holds: Option<String>,
    /// Added to the "why" column when it does not.
    pub why_fails: Option<String>,
    /// Why the claim does not apply to what was run (then it is shown as "n/a", never as
    /// holding or failing), if it does not.
    pub not_applicable: Option<String>,
}

/// A row of the claims table, computed by [`ClaimSpec::evaluate`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Claim {
    /// The claim in words.
    pub claim: String,
    /// The measured numbers behind it.
    pub measured: String,
    /// Whether every comparison holds (false when not applicable).
    pub holds: bool,
    /// Whether the claim applies to what was run ([`ClaimSpec::not_applicable`]).
    pub applicable: bool,
    /// Why it holds or not: the deciding numbers, then the caller's explanation if any.
    pub why: String,
}

impl ClaimSpec {
    /// A claim with no comparison yet (add them with [`ClaimSpec::expect`]).
    pub fn new(claim: &str) -> Self {
        Self {
            claim: claim.to_string(),
            comparisons: Vec::new(),
            why_holds: None,
            why_fails: None,
            not_applicable: None,
        }
    }

    /// Marks the claim as not applicable to what was run, with the reason.
    pub fn not_applicable(mut self, reason: &str) -> Self {
        self.not_applicable = Some(reason.to_string());
        self
    }

    /// Adds a comparison: `subject`'s `metric` is `expect` than `reference`'s.
    pub fn expect(
        mut self,
        subject: &str,
        metric: MetricKind,
        expect: Expect,
        reference: &str,
    ) -> Self {
        self.comparisons.push(Comparison {
            subject: subject.to_string(),
            metric,
            expect,
            reference: reference.to_string(),
        });
        self
    }

    /// Explanations appended to "why" when the claim holds and when it does not.
    pub fn because(mut self, holds: &str, fails: &str) -> Self {
        self.why_holds = Some(holds.to_string());
        self.why_fails = Some(fails.to_string());
        self
    }

    /// Checks the claim against a run's metrics.
    ///
    /// A comparison whose estimator is absent or whose metric was not measured does not
    /// hold, and "why" says which; a claim with no comparison does not hold either.
    pub fn evaluate(&self, metrics: &[Metrics]) -> Claim {
        let mut measured = Vec::new();
        let mut reasons = Vec::new();
        let mut holds = !self.comparisons.is_empty();
        if self.comparisons.is_empty() {
            reasons.push("no comparison given".to_string());
        }
        for c in &self.comparisons {
            match c.check(metrics) {
                Ok((m, ok, reason)) => {
                    measured.push(m);
                    holds &= ok;
                    reasons.push(reason);
                }
                Err(reason) => {
                    holds = false;
                    reasons.push(reason);
                }
            }
        }
        let extra = if holds {
            &self.why_holds
        } else {
            &self.why_fails
        };
        let mut why = reasons.join("; ");
        if let Some(x) = extra.as_deref().filter(|x| !x.trim().is_empty()) {
            why = format!("{why}. {x}");
        }
        if let Some(r) = &self.not_applicable {
            why = format!("Not applicable: {r}. (Measured anyway: {why})");
        }
        Claim {
            claim: self.claim.clone(),
            measured: if measured.is_empty() {
                "-".to_string()
            } else {
                measured.join("; ")
            },
            holds: holds && self.not_applicable.is_none(),
            applicable: self.not_applicable.is_none(),
            why,
        }
    }
}

impl Comparison {
    /// This comparison on a run's metrics: what was measured, whether it holds, and why;
    /// `Err` with the reason when an estimator or its metric is missing.
    fn check(&self, metrics: &[Metrics]) -> Result<(String, bool, String), String> {
        let c = self;
        let find = |name: &str| metrics.iter().find(|m| m.name == name);
        let label = c.metric.label();
        let unit = c.metric.unit();
        let (s, r) = (find(&c.subject), find(&c.reference));
        let (Some(s), Some(r)) = (s, r) else {
            let missing = if s.is_none() {
                &c.subject
            } else {
                &c.reference
            };
            return Err(format!("{missing} was not in the run"));
        };
        let (Some(vs), Some(vr)) = (c.metric.value(s), c.metric.value(r)) else {
            let who = if c.metric.value(s).is_none() { s } else { r };
            let detail = who
                .notes
                .iter()
                .find(|n| n.contains(label.split(' ').next().unwrap_or(label)))
                .map(|n| format!(" ({n})"))
                .unwrap_or_default();
            return Err(format!(
                "{label} of {} could not be measured{detail}",
                who.name
            ));
        };
        let rel = if vr != 0.0 {
            format!(" ({:+.0}%)", (vs - vr) / vr.abs() * 100.0)
        } else {
            String::new()
        };
        let measured = format!(
            "{label}: {} {} {unit} vs {} {} {unit}{rel}",
            c.subject,
            fmt_sig(vs),
            c.reference,
            fmt_sig(vr)
        );
        let (ok, word) = match c.expect {
            Expect::Lower => (vs < vr, "lower"),
            Expect::Higher => (vs > vr, "higher"),
        };
        let not = if ok { "" } else { "not " };
        let reason = format!(
            "{}'s {label} is {not}{word} than {}'s",
            c.subject, c.reference
        );
        Ok((measured, ok, reason))
    }
}

impl Claim {
    /// "yes", "no" or "n/a" (not applicable).
    pub fn verdict(&self) -> &'static str {
        match (self.applicable, self.holds) {
            (false, _) => "n/a",
            (true, true) => "yes",
            (true, false) => "no",
        }
    }
}

/// A number with about three significant digits, for tables and sentences.
pub fn fmt_sig(v: f64) -> String {
    if !v.is_finite() {
        return format!("{v}");
    }
    let a = v.abs();
    let decimals = if a == 0.0 || a >= 100.0 {
        1
    } else if a >= 10.0 {
        2
    } else if a >= 0.1 {
        3
    } else {
        4
    };
    format!("{v:.decimals$}")
}

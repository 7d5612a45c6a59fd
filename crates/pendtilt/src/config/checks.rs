//! The rules a rig's values must meet beyond their types: the physically possible, the
//! finite, one cutoff. [`super::RigConfig::validate`] and the file reader apply them; the
//! reader names the offending key's position.
use super::tables::window_problem;
use super::{PendulumConfig, RigConfig};
use pendtilt_core::estimators::theta_dd::ThetaDdSource;
use pendtilt_core::filters::diff::Cutoff;
use pendtilt_core::kalman::KalmanSettings;

/// A rule broken: (dotted key, value, why).
pub(super) type Issue = (String, f64, String);

/// Every rule `cfg` breaks, in the file's table order.
pub(super) fn issues(cfg: &RigConfig) -> Vec<Issue> {
    let mut issues = Vec::new();
    check_pendulum(&cfg.pendulum, &mut issues);
    check_kalman(&cfg.kalman, &mut issues);
    check_estimators(cfg, &mut issues);
    check_ekf(cfg, &mut issues);
    issues
}

fn require(issues: &mut Vec<Issue>, key: &str, value: f64, ok: bool, why: &str) {
    if !value.is_finite() {
        issues.push((
            key.to_string(),
            value,
            "must be a finite number".to_string(),
        ));
    } else if !ok {
        issues.push((key.to_string(), value, why.to_string()));
    }
}

fn positive(issues: &mut Vec<Issue>, key: &str, value: Option<f64>, why: &str) {
    if let Some(v) = value {
        require(issues, key, v, v > 0.0, why);
    }
}

fn check_pendulum(p: &PendulumConfig, issues: &mut Vec<Issue>) {
    match p {
        PendulumConfig::Physical(p) => {
            require(
                issues,
                "pendulum.mass",
                p.mass,
                p.mass > 0.0,
                "mass must be > 0 [kg]",
            );
            require(
                issues,
                "pendulum.length",
                p.length,
                p.length > 0.0,
                "length (pivot to centre of gravity) must be > 0 [m]",
            );
            require(
                issues,
                "pendulum.inertia",
                p.inertia,
                p.inertia > 0.0,
                "inertia about the pivot must be > 0 [kg m^2]",
            );
            require(
                issues,
                "pendulum.damping",
                p.damping,
                p.damping >= 0.0,
                "damping (viscous friction) must be >= 0 [N m s/rad]",
            );
            require(issues, "pendulum.pivot_offset", p.pivot_offset, true, "");
            require(
                issues,
                "pendulum.gravity",
                p.gravity,
                p.gravity > 0.0,
                "gravity must be > 0 [m/s^2]",
            );
            let point = p.mass * p.length * p.length;
            if issues.is_empty() && p.inertia < point * (1.0 - 1e-12) {
                // Six significant digits, written plainly (0.00015, not 0.00015000000000000001).
                let shown = super::shown(super::plain(point));
                issues.push((
                    "pendulum.inertia".to_string(),
                    p.inertia,
                    format!(
                        "inertia about the pivot must be >= mass * length^2 = {shown} kg m^2 \
                         (a point mass at the centre of gravity)"
                    ),
                ));
            }
        }
        PendulumConfig::Normalised(p) => {
            require(
                issues,
                "pendulum.a",
                p.a,
                p.a >= 0.0,
                "a = C / (m_p g l_p) must be >= 0 [s]",
            );
            require(
                issues,
                "pendulum.b",
                p.b,
                p.b > 0.0,
                "b = I_p / (m_p g l_p) must be > 0 [s^2]",
            );
            require(issues, "pendulum.c", p.c, true, "");
        }
    }
}

fn check_kalman(k: &KalmanSettings<f64>, issues: &mut Vec<Issue>) {
    let nonneg = "a noise density must be >= 0";
    require(
        issues,
        "kalman.q_angle",
        k.q_angle,
        k.q_angle >= 0.0,
        nonneg,
    );
    require(issues, "kalman.q_bias", k.q_bias, k.q_bias >= 0.0, nonneg);
    let pos = "a measurement variance must be > 0";
    require(issues, "kalman.r_accel", k.r_accel, k.r_accel > 0.0, pos);
    require(
        issues,
        "kalman.r_pendulum",
        k.r_pendulum,
        k.r_pendulum > 0.0,
        pos,
    );
    if let Some(r) = k.r_accel_fused {
        require(issues, "kalman.r_accel_fused", r, r > 0.0, pos);
    }
    let var = "an initial variance must be >= 0";
    require(
        issues,
        "kalman.p0_angle",
        k.p0_angle,
        k.p0_angle >= 0.0,
        var,
    );
    require(issues, "kalman.p0_bias", k.p0_bias, k.p0_bias >= 0.0, var);
}

fn check_estimators(e: &RigConfig, issues: &mut Vec<Issue>) {
    match e.differentiator.cutoff {
        Cutoff::Hz(f) => positive(
            issues,
            "differentiator.cutoff_hz",
            Some(f),
            "the cutoff must be > 0 [Hz]",
        ),
        Cutoff::TimesNatural(k) => positive(
            issues,
            "differentiator.cutoff_times_natural",
            Some(k),
            "the cutoff must be > 0 (a multiple of f_n)",
        ),
    }
    positive(
        issues,
        "alg1.cutoff_times_natural",
        e.alg1.cutoff_times_natural,
        "the cutoff must be > 0 (a multiple of f_n; leave it out for [differentiator]'s)",
    );
    positive(
        issues,
        "accel.prefilter_hz",
        e.accel.prefilter_hz,
        "the prefilter cutoff must be > 0 [Hz] (leave it out to turn it off)",
    );
    positive(
        issues,
        "accel.full_scale",
        e.accel.full_scale,
        "the full scale must be > 0 [m/s^2] (leave it out when unknown)",
    );
    positive(
        issues,
        "gyro.full_scale",
        e.gyro.full_scale,
        "the full scale must be > 0 [rad/s] (leave it out when unknown)",
    );
    for (key, source) in [
        ("alg2.window", e.alg2.front_end.theta_dd),
        ("alg3.window", e.alg3.front_end.theta_dd),
    ] {
        if let ThetaDdSource::Window { span } = source {
            if let Some(why) = window_problem(span) {
                issues.push((key.into(), span, why.into()));
            }
        }
    }
    let g = e.alg3.gains;
    for (key, v) in [
        ("alg3.k", g.k),
        ("alg3.l", g.l),
        ("alg3.m", g.m),
        ("alg3.n", g.n),
    ] {
        if !v.is_finite() {
            issues.push((key.into(), v, "must be a finite number".into()));
        }
    }
}

fn check_ekf(cfg: &RigConfig, issues: &mut Vec<Issue>) {
    for (key, v) in cfg.ekf.values() {
        require(issues, key, v, v >= 0.0, "a noise figure must be >= 0");
    }
    if let Some(bits) = cfg.ekf.encoder_bits {
        let b = f64::from(bits);
        require(
            issues,
            "ekf.encoder_bits",
            b,
            bits <= 52,
            "an encoder has at most 52 bits per turn (0: not quantised)",
        );
    }
}

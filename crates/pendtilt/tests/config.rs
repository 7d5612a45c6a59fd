//! The rig file: defaults, round trips, and every error naming file, line, key and why.
use pendtilt::config::{ConfigErrorKind, PendulumConfig, RigConfig};
use pendtilt::core::kalman::KalmanSettings;
use pendtilt::core::{PendulumParams, PhysicalParams};

fn err(text: &str) -> pendtilt::config::ConfigError {
    match RigConfig::from_toml_str(text, "rig.toml") {
        Ok(cfg) => panic!("expected an error for {text:?}, got {cfg:?}"),
        Err(e) => e,
    }
}

#[test]
fn empty_file_gives_documented_defaults() {
    let cfg = RigConfig::from_toml_str("", "rig.toml").unwrap();
    assert_eq!(cfg.physical(), Some(PhysicalParams::default()));
    assert_eq!(cfg.params(), PendulumParams::default());
    let k = cfg.kalman;
    assert_eq!(
        (
            k.q_angle,
            k.q_bias,
            k.r_accel,
            k.r_pendulum,
            k.p0_angle,
            k.p0_bias
        ),
        (0.001, 0.003, 0.03, 0.001, 0.01, 0.01)
    );
    assert_eq!(k, KalmanSettings::default());
}

#[test]
fn physical_form_reads_every_key_and_defaults_the_rest() {
    let cfg = RigConfig::from_toml_str(
        "[pendulum]\nmass = 0.1\nlength = 0.04\ninertia = 2e-4\ndamping = 0\n",
        "rig.toml",
    )
    .unwrap();
    let p = cfg.physical().unwrap();
    assert_eq!(p.mass, 0.1);
    assert_eq!(p.length, 0.04);
    assert_eq!(p.inertia, 2e-4);
    assert_eq!(p.damping, 0.0);
    assert_eq!(p.pivot_offset, 0.0);
    assert_eq!(p.gravity, 9.80665);
    let n = cfg.params();
    assert!((n.b - 2e-4 / (0.1 * 9.80665 * 0.04)).abs() < 1e-15);
    assert_eq!(n.a, 0.0);
}

#[test]
fn integers_are_accepted_for_floats() {
    let cfg = RigConfig::from_toml_str("[pendulum]\ngravity = 10\n", "rig.toml").unwrap();
    assert_eq!(cfg.physical().unwrap().gravity, 10.0);
}

#[test]
fn normalised_form_reads_a_b_c() {
    let cfg = RigConfig::from_toml_str(
        "[pendulum]\na = 0.05\nb = 0.006\nc = 0.001\n\n[kalman]\nr_accel = 0.5\n",
        "rig.toml",
    )
    .unwrap();
    assert_eq!(cfg.physical(), None);
    assert_eq!(
        cfg.params(),
        PendulumParams {
            a: 0.05,
            b: 0.006,
            c: 0.001
        }
    );
    assert_eq!(cfg.kalman.r_accel, 0.5);
    assert_eq!(cfg.kalman.q_angle, 0.001);
}

#[test]
fn physical_round_trip() {
    let p = PhysicalParams {
        mass: 0.123_456_789,
        length: 0.0371,
        inertia: 1.9e-4,
        damping: 2.5e-3,
        pivot_offset: -0.12,
        gravity: 9.81,
    };
    let mut cfg = RigConfig::from_physical(p).unwrap();
    cfg.kalman.q_bias = 1.0 / 3.0;
    let text = cfg.to_toml_string();
    let back = RigConfig::from_toml_str(&text, "written.toml").unwrap();
    assert_eq!(back, cfg, "text was:\n{text}");
    assert!(text.contains("[pendulum]") && text.contains("[kalman]"));
    assert!(
        !text
            .lines()
            .any(|l| l.starts_with("a ") || l.starts_with("b ")),
        "physical form only:\n{text}"
    );
}

#[test]
fn normalised_round_trip_and_save_load() {
    let p = PendulumParams {
        a: 0.043_643_1,
        b: 5.302_5e-3,
        c: 0.0,
    };
    let cfg = RigConfig::from_params(p).unwrap();
    assert!(matches!(cfg.pendulum, PendulumConfig::Normalised(_)));
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("fit.toml");
    cfg.save(&path).unwrap();
    let back = RigConfig::load(&path).unwrap();
    assert_eq!(back, cfg);
    assert_eq!(back.params(), p);
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(!text.contains("mass"), "normalised form only:\n{text}");
}

#[test]
fn unknown_key_names_file_line_column_key_and_allowed_keys() {
    let e = err("[pendulum]\nmass = 0.05\nmasss = 0.1\n");
    assert_eq!(e.location.file, "rig.toml");
    assert_eq!(e.location.line, Some(3));
    assert_eq!(e.location.column, Some(1));
    assert_eq!(e.location.key.as_deref(), Some("pendulum.masss"));
    assert!(matches!(*e.kind, ConfigErrorKind::UnknownKey { .. }));
    let msg = e.to_string();
    assert!(
        msg.starts_with("rig.toml:3:1: pendulum.masss: unknown key"),
        "{msg}"
    );
    assert!(msg.contains("mass") && msg.contains("inertia"), "{msg}");
}

#[test]
fn unknown_kalman_key_and_unknown_table() {
    let e = err("[kalman]\n  q_angel = 0.1\n");
    assert_eq!(e.location.key.as_deref(), Some("kalman.q_angel"));
    assert_eq!((e.location.line, e.location.column), (Some(2), Some(3)));
    assert!(e.to_string().contains("q_angle"), "{e}");

    let e = err("[pendulum]\nmass = 1\n[kalmann]\nq_angle = 1\n");
    assert_eq!(e.location.key.as_deref(), Some("kalmann"));
    assert_eq!(e.location.line, Some(3));
    assert!(matches!(*e.kind, ConfigErrorKind::UnknownKey { .. }));
    assert!(e.to_string().contains("[kalman]"), "{e}");
}

#[test]
fn wrong_type_names_key_and_position() {
    let e = err("[pendulum]\nmass = \"heavy\"\n");
    assert_eq!(e.location.key.as_deref(), Some("pendulum.mass"));
    assert_eq!((e.location.line, e.location.column), (Some(2), Some(8)));
    assert!(matches!(*e.kind, ConfigErrorKind::WrongType(_)));
    let msg = e.to_string();
    assert!(
        msg.starts_with("rig.toml:2:8: pendulum.mass: wrong type"),
        "{msg}"
    );
    assert!(msg.contains("heavy"), "{msg}");

    let e = err("pendulum = 3\n");
    assert_eq!(e.location.key.as_deref(), Some("pendulum"));
    assert!(e.to_string().contains("must be a table"), "{e}");

    let e = err("[kalman]\nr_accel = [1, 2]\n");
    assert_eq!(e.location.key.as_deref(), Some("kalman.r_accel"));
    assert_eq!(e.location.line, Some(2));
}

#[test]
fn syntax_error_has_line_and_column() {
    let e = err("[pendulum]\nmass = = 1\n");
    assert!(matches!(*e.kind, ConfigErrorKind::Syntax(_)));
    assert_eq!(e.location.line, Some(2));
    assert!(e.location.column.is_some());
    assert!(e.to_string().starts_with("rig.toml:2:"), "{e}");
}

fn impossible(text: &str, key: &str, line: Option<usize>, why: &str) {
    let e = err(text);
    assert_eq!(e.location.key.as_deref(), Some(key), "{e}");
    assert_eq!(e.location.line, line, "{e}");
    assert!(matches!(*e.kind, ConfigErrorKind::Impossible { .. }), "{e}");
    let msg = e.to_string();
    assert!(msg.starts_with("rig.toml"), "{msg}");
    assert!(msg.contains(key), "{msg}");
    assert!(msg.contains(why), "expected `{why}` in {msg}");
}

#[test]
fn physically_impossible_values_are_named() {
    impossible(
        "[pendulum]\nmass = -0.05\n",
        "pendulum.mass",
        Some(2),
        "must be > 0",
    );
    impossible(
        "[pendulum]\nmass = 0\n",
        "pendulum.mass",
        Some(2),
        "must be > 0",
    );
    impossible(
        "[pendulum]\nlength = 0.0\n",
        "pendulum.length",
        Some(2),
        "must be > 0",
    );
    impossible(
        "[pendulum]\ninertia = -1e-4\n",
        "pendulum.inertia",
        Some(2),
        "> 0",
    );
    impossible(
        "[pendulum]\ndamping = -1e-3\n",
        "pendulum.damping",
        Some(2),
        ">= 0",
    );
    impossible(
        "[pendulum]\ngravity = 0\n",
        "pendulum.gravity",
        Some(2),
        "> 0",
    );
    impossible(
        "[pendulum]\nmass = nan\n",
        "pendulum.mass",
        Some(2),
        "finite",
    );
    impossible(
        "[pendulum]\ndamping = inf\n",
        "pendulum.damping",
        Some(2),
        "finite",
    );
    impossible("[pendulum]\nb = 0\n", "pendulum.b", Some(2), "> 0");
    // Quoted compactly, not as 301 digits.
    impossible(
        "[pendulum]\nmass = -1e300\n",
        "pendulum.mass",
        Some(2),
        "impossible value -1e300: mass must be > 0",
    );
    impossible(
        "[pendulum]\nmass = 1e300\nlength = 0.05\ninertia = 0.00013\ndamping = 0.00107\n",
        "pendulum.inertia",
        Some(4),
        "impossible value 0.00013: inertia about the pivot must be >= mass * length^2 = 2.5e297 kg m^2",
    );
    impossible("[pendulum]\na = -0.1\n", "pendulum.a", Some(2), ">= 0");
    impossible("[kalman]\nr_accel = 0\n", "kalman.r_accel", Some(2), "> 0");
    impossible("[kalman]\nq_bias = -1\n", "kalman.q_bias", Some(2), ">= 0");
    impossible(
        "[kalman]\np0_angle = -1\n",
        "kalman.p0_angle",
        Some(2),
        ">= 0",
    );
}

#[test]
fn inertia_below_point_mass_is_impossible() {
    // 1 kg at 0.5 m needs I >= 0.25 kg m^2.
    impossible(
        "[pendulum]\nmass = 1\nlength = 0.5\ninertia = 0.2\n",
        "pendulum.inertia",
        Some(4),
        "mass * length^2 = 0.25 kg m^2",
    );
    // The same with the inertia defaulted: no line, and the message says it is the default.
    impossible(
        "[pendulum]\nmass = 1\nlength = 0.5\n",
        "pendulum.inertia",
        None,
        "default",
    );
    // Exactly a point mass is allowed.
    assert!(
        RigConfig::from_toml_str("[pendulum]\nmass = 1\nlength = 0.5\ninertia = 0.25\n", "r")
            .is_ok()
    );
}

#[test]
fn mixed_forms_are_an_error() {
    let e = err("[pendulum]\nmass = 0.05\nb = 0.005\n");
    assert!(matches!(
        *e.kind,
        ConfigErrorKind::MixedPendulumForms { .. }
    ));
    assert_eq!(e.location.line, Some(3));
    let msg = e.to_string();
    assert!(msg.contains("mass") && msg.contains("b"), "{msg}");
}

#[test]
fn constructors_reject_impossible_values() {
    let p = PhysicalParams {
        mass: -1.0,
        ..PhysicalParams::default()
    };
    let e = RigConfig::from_physical(p).unwrap_err();
    assert_eq!(e.location.key.as_deref(), Some("pendulum.mass"));
    let e = RigConfig::from_params(PendulumParams {
        a: 0.1,
        b: f64::NAN,
        c: 0.0,
    })
    .unwrap_err();
    assert_eq!(e.location.key.as_deref(), Some("pendulum.b"));
    assert!(e.to_string().contains("finite"), "{e}");
}

#[test]
fn missing_file_names_it() {
    let e = RigConfig::load("/nonexistent/dir/rig.toml").unwrap_err();
    assert!(matches!(*e.kind, ConfigErrorKind::Io(_)));
    assert!(
        e.to_string()
            .starts_with("/nonexistent/dir/rig.toml: cannot read"),
        "{e}"
    );
}

#[test]
fn estimator_tables_default_to_the_core_defaults() {
    use pendtilt::core::estimators::{
        accel::AccelSettings, alg1::Alg1Settings, alg2::Alg2Settings, alg3::Alg3Settings,
    };
    use pendtilt::core::kalman::KalmanSettings;
    let cfg = RigConfig::from_toml_str("", "rig.toml").unwrap();
    let p = PendulumParams::default();
    assert_eq!(cfg.accel_settings(), AccelSettings::default());
    assert_eq!(cfg.alg1_settings(), Alg1Settings::from_params(p));
    assert_eq!(cfg.alg2_settings(), Alg2Settings::from_params(p));
    assert_eq!(cfg.alg3_settings(), Alg3Settings::from_params(p));
    assert_eq!(cfg.kalman_settings(), KalmanSettings::default());
}

#[test]
fn estimator_tables_map_onto_core_settings() {
    use pendtilt::core::estimators::theta_dd::ThetaDdSource;
    use pendtilt::core::estimators::PhiSource;
    use pendtilt::core::filters::diff::{Cutoff, Response};
    let text = "[pendulum]\na = 0.04\nb = 0.005\n\
        [differentiator]\nresponse = \"bessel\"\ncutoff_hz = 3\n\
        [accel]\nprefilter_hz = 5.0\nfull_scale = 78.5\n\
        [gyro]\nfull_scale = 8.7\n\
        [alg1]\nphi = \"filtered\"\n\
        [alg2]\ntheta_dd = \"window\"\nwindow = 0.03\npivot_offset = true\n\
        [alg3]\nk = 0.1\nn = 0.002\n\
        [kalman]\nr_pendulum = 0.002\n";
    let cfg = RigConfig::from_toml_str(text, "rig.toml").unwrap();
    let d = cfg.diff_settings();
    assert_eq!(d.response, Response::Bessel);
    assert_eq!(d.cutoff, Cutoff::Hz(3.0));
    let a = cfg.accel_settings();
    assert_eq!((a.prefilter_hz, a.full_scale), (Some(5.0), Some(78.5)));
    assert_eq!(cfg.alg1_settings().front_end.phi, PhiSource::Filtered);
    assert_eq!(cfg.alg1_settings().front_end.differentiator, d);
    let s2 = cfg.alg2_settings();
    assert_eq!(s2.front_end.theta_dd, ThetaDdSource::Window { span: 0.03 });
    assert!(s2.pivot_offset);
    assert_eq!(s2.front_end.params.a, 0.04);
    let g = cfg.alg3_settings().gains;
    // K and N given; L and M from b.
    assert_eq!((g.k, g.l, g.m, g.n), (0.1, 0.005, -0.005, 0.002));
    assert_eq!(
        cfg.alg3_settings().front_end.theta_dd,
        ThetaDdSource::Matched
    );
    assert_eq!(cfg.kalman_settings().r_pendulum, 0.002);
    // The gyro's full scale reaches every estimator that reads the gyro.
    assert_eq!(s2.front_end.gyro.full_scale, Some(8.7));
    assert_eq!(cfg.alg3_settings().front_end.gyro.full_scale, Some(8.7));
    assert_eq!(cfg.kalman_settings().gyro.full_scale, Some(8.7));
    // And the whole file round-trips.
    let back = RigConfig::from_toml_str(&cfg.to_toml_string(), "again.toml").unwrap();
    assert_eq!(back, cfg, "{}", cfg.to_toml_string());
}

#[test]
fn alg1_may_have_its_own_cutoff() {
    use pendtilt::core::filters::diff::{Cutoff, Response};
    let text = "[pendulum]\na = 0.04\nb = 0.005\n\
        [differentiator]\nresponse = \"bessel\"\ncutoff_hz = 3\n\
        [alg1]\ncutoff_times_natural = 0.8\n";
    let cfg = RigConfig::from_toml_str(text, "rig.toml").unwrap();
    let d1 = cfg.alg1_settings().front_end.differentiator;
    // Its own cutoff, the shared response; everyone else keeps [differentiator]'s.
    assert_eq!(d1.cutoff, Cutoff::TimesNatural(0.8));
    assert_eq!(d1.response, Response::Bessel);
    assert_eq!(
        cfg.alg2_settings().front_end.differentiator.cutoff,
        Cutoff::Hz(3.0)
    );
    assert_eq!(
        cfg.alg3_settings().front_end.differentiator.cutoff,
        Cutoff::Hz(3.0)
    );
    let back = RigConfig::from_toml_str(&cfg.to_toml_string(), "again.toml").unwrap();
    assert_eq!(back, cfg, "{}", cfg.to_toml_string());
    impossible(
        "[alg1]\ncutoff_times_natural = -1\n",
        "alg1.cutoff_times_natural",
        Some(2),
        "> 0",
    );
}

#[test]
fn fitted_alg3_gains_round_trip() {
    use pendtilt::core::estimators::equations::Alg3Gains;
    let mut cfg = RigConfig::from_params(PendulumParams {
        a: 0.05,
        b: 0.006,
        c: 0.0,
    })
    .unwrap();
    let g = Alg3Gains {
        k: 0.051,
        l: 0.0061,
        m: -0.0058,
        n: 1.0e-3,
    };
    cfg.alg3.gains = g;
    let text = cfg.to_toml_string();
    let back = RigConfig::from_toml_str(&text, "fit.toml").unwrap();
    assert_eq!(back.alg3_settings().gains, g, "{text}");
    assert!(
        text.contains("[alg3]") && text.contains("k = 0.051"),
        "{text}"
    );
    assert_eq!(back.alg3_gains(), g);
    let other = RigConfig {
        alg3: pendtilt::core::estimators::alg3::Alg3Settings {
            gains: g,
            ..Default::default()
        },
        ..RigConfig::default()
    };
    assert_eq!(other.alg3_gains(), g);
    assert_eq!(
        other.alg3_settings().front_end.theta_dd,
        pendtilt::core::estimators::theta_dd::ThetaDdSource::Matched
    );
}

#[test]
fn estimator_table_errors_name_the_key() {
    let e = err("[differentiator]\nresponse = \"chebyshev\"\n");
    assert!(matches!(*e.kind, ConfigErrorKind::BadChoice(_)), "{e}");
    assert_eq!(e.location.key.as_deref(), Some("differentiator.response"));
    assert_eq!(e.location.line, Some(2));
    assert!(e.to_string().contains("bessel"), "{e}");

    let e = err("[alg2]\nwindow_s = 0.1\n");
    assert!(matches!(*e.kind, ConfigErrorKind::UnknownKey { .. }), "{e}");
    assert_eq!(e.location.key.as_deref(), Some("alg2.window_s"));
    assert!(e.to_string().contains("window"), "{e}");

    let e = err("[alg2]\npivot_offset = 1\n");
    assert!(matches!(*e.kind, ConfigErrorKind::WrongType(_)), "{e}");
    assert_eq!(e.location.key.as_deref(), Some("alg2.pivot_offset"));

    impossible(
        "[differentiator]\ncutoff_hz = 0\n",
        "differentiator.cutoff_hz",
        Some(2),
        "> 0",
    );
    impossible(
        "[differentiator]\ncutoff_hz = 3\ncutoff_times_natural = 2\n",
        "differentiator.cutoff_times_natural",
        Some(3),
        "not both",
    );
    impossible("[alg3]\nwindow = -0.01\n", "alg3.window", Some(2), "> 0");
    impossible("[alg3]\nm = nan\n", "alg3.m", Some(2), "finite");
    impossible(
        "[accel]\nprefilter_hz = -5\n",
        "accel.prefilter_hz",
        Some(2),
        "> 0",
    );
    impossible(
        "[gyro]\n\nfull_scale = 0\n",
        "gyro.full_scale",
        Some(3),
        "> 0 [rad/s]",
    );
    let e = err("[gyro]\nrange = 8.7\n");
    assert!(matches!(*e.kind, ConfigErrorKind::UnknownKey { .. }), "{e}");
    assert!(e.to_string().contains("full_scale"), "{e}");
}

mod never_panics {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(1000))]

        #[test]
        fn arbitrary_toml_like_text(
            body in "(\\[(pendulum|kalman|alg3)\\]\n)?([a-z_0-9]{1,8} = [-0-9.e\"a-z\\[\\]]{0,8}\n){0,6}"
        ) {
            if let Ok(cfg) = RigConfig::from_toml_str(&body, "fuzz.toml") {
                // Whatever loads also writes and reloads to the same value.
                let back = RigConfig::from_toml_str(&cfg.to_toml_string(), "again.toml");
                prop_assert_eq!(back.ok(), Some(cfg));
            }
        }
    }
}

#[test]
fn save_error_names_the_path() {
    let e = RigConfig::default()
        .save("/nonexistent/dir/rig.toml")
        .unwrap_err();
    assert!(e.to_string().contains("/nonexistent/dir/rig.toml"), "{e}");
}

#[test]
fn dotted_keys_at_top_level_are_read_and_located() {
    let cfg =
        RigConfig::from_toml_str("pendulum.mass = 0.04\nkalman.r_accel = 0.5\n", "r").unwrap();
    assert_eq!(cfg.physical().unwrap().mass, 0.04);
    assert_eq!(cfg.kalman.r_accel, 0.5);
    let e = err("pendulum.mass = -1\n");
    assert_eq!(e.location.key.as_deref(), Some("pendulum.mass"));
    assert_eq!(e.location.line, Some(1));
}

#[test]
fn the_tables_are_listed_once_and_every_use_agrees() {
    // The unknown-table error, reading and writing all come from RigConfig's fields.
    let e = err("[kalmann]\n");
    let ConfigErrorKind::UnknownKey { allowed, .. } = &*e.kind else {
        panic!("{e}");
    };
    let listed: Vec<&str> = allowed
        .split(", ")
        .map(|t| t.trim_start_matches('[').trim_end_matches(']'))
        .collect();
    // (Not a copy of the list: adding a table needs no change here.)
    assert!(listed.starts_with(&["pendulum", "kalman"]) && listed.contains(&"alg3"));
    let written: Vec<String> = RigConfig::default()
        .to_toml_string()
        .lines()
        .filter_map(|l| l.strip_prefix('[').and_then(|l| l.strip_suffix(']')))
        .map(str::to_string)
        .collect();
    assert_eq!(
        written, listed,
        "the written file has every table, in order"
    );
    for table in listed {
        let cfg = RigConfig::from_toml_str(&format!("[{table}]\n"), "rig.toml").unwrap();
        assert_eq!(cfg, RigConfig::default(), "[{table}] empty is the defaults");
    }
}

#[test]
fn alg3_gains_left_out_follow_the_files_pendulum() {
    use pendtilt::core::estimators::equations::Alg3Gains;
    // L and M from this file's b (not the default pendulum's), N = 0.
    let cfg = RigConfig::from_toml_str("[alg3]\nk = 0.1\n[pendulum]\na = 0.04\nb = 0.007\n", "r")
        .unwrap();
    assert_eq!(
        cfg.alg3_gains(),
        Alg3Gains {
            k: 0.1,
            l: 0.007,
            m: -0.007,
            n: 0.0
        }
    );
    assert!(!cfg.alg3_gains_are_eq21());
    // None given: the Eq (21) equivalent, and none written back.
    let cfg = RigConfig::from_toml_str("[pendulum]\na = 0.04\nb = 0.007\n", "r").unwrap();
    assert!(cfg.alg3_gains_are_eq21());
    let text = cfg.to_toml_string();
    assert!(!text.contains("\nk = "), "{text}");
    // A matched theta'' keeps no window, and writes the default one.
    let cfg = RigConfig::from_toml_str("[alg2]\nwindow = 0.05\n", "r").unwrap();
    assert!(cfg.to_toml_string().contains("window = 0.02 "));
}

#[test]
fn lengths_that_look_like_millimetres_are_doubted_with_the_fix() {
    let doubts = |text: &str| RigConfig::from_toml_str(text, "rig.toml").unwrap().doubts();
    assert!(doubts("").is_empty());
    assert!(doubts("[pendulum]\npivot_offset = 1.5\n").is_empty());
    assert!(doubts("[pendulum]\npivot_offset = -0.3\nlength = 0.2\ninertia = 0.01\n").is_empty());
    let d = doubts("[pendulum]\npivot_offset = -120\n");
    assert_eq!(d.len(), 1, "{d:?}");
    assert!(d[0].starts_with("pendulum.pivot_offset: a pivot offset l12 of -120 m is beyond 2 m"));
    assert!(
        d[0].contains("write pendulum.pivot_offset = -0.12"),
        "{d:?}"
    );
    // A length in mm with an inertia to match (else the inertia rule refuses it).
    let d = doubts("[pendulum]\nlength = 50\ninertia = 130\n");
    assert!(
        d[0].contains("pendulum.length: a pendulum length l_p of 50 m"),
        "{d:?}"
    );
    assert!(d[0].contains("write pendulum.length = 0.05"), "{d:?}");
    // The normalised form: c = l12 / g.
    let d = doubts("[pendulum]\na = 0.0436\nb = 0.0053\nc = 5.1\n");
    assert!(
        d[0].contains("pendulum.c: c = l12 / g = 5.1 s^2, a pivot offset l12 of 50.014 m"),
        "{d:?}"
    );
    assert!(d[0].contains("write pendulum.c = 0.0051"), "{d:?}");
}

#[test]
fn full_scales_that_look_like_deg_per_s_g_or_mg_are_doubted_with_the_fix() {
    let doubts = |text: &str| RigConfig::from_toml_str(text, "rig.toml").unwrap().doubts();
    // Ranges in the rig's own units: nothing (4000 deg/s = 69.8 rad/s; 2 g .. 200 g).
    for ok in [
        "[gyro]\nfull_scale = 8.73\n",
        "[gyro]\nfull_scale = 69.8\n",
        "[gyro]\nfull_scale = 0.3\n",
        "[accel]\nfull_scale = 19.7\n",
        "[accel]\nfull_scale = 156.9\n",
        "[accel]\nfull_scale = 1961\n",
    ] {
        assert!(doubts(ok).is_empty(), "{ok}: {:?}", doubts(ok));
    }
    // 500 deg/s read as rad/s: 500 deg/s is 8.72665 rad/s.
    let d = doubts("[gyro]\nfull_scale = 500\n");
    assert_eq!(d.len(), 1, "{d:?}");
    assert!(
        d[0].starts_with("gyro.full_scale: 500 rad/s is above 69.8 rad/s (4000 deg/s)"),
        "{d:?}"
    );
    assert!(d[0].contains("write gyro.full_scale = 8.72665"), "{d:?}");
    // The smallest range in deg/s, 125, is caught too.
    assert_eq!(doubts("[gyro]\nfull_scale = 125\n").len(), 1);
    // 16 g written as 16: 16 g is 156.9 m/s^2.
    let d = doubts("[accel]\nfull_scale = 16\n");
    assert_eq!(d.len(), 1, "{d:?}");
    assert!(d[0].contains("written in g? 16 g is 156.9 m/s^2"), "{d:?}");
    assert!(d[0].contains("write accel.full_scale = 156.906"), "{d:?}");
    // 8000 mg: 8 g.
    let d = doubts("[accel]\nfull_scale = 8000\n");
    assert!(
        d[0].contains("written in mg? 8000 mg is 78.5 m/s^2"),
        "{d:?}"
    );
    assert!(d[0].contains("write accel.full_scale = 78.4532"), "{d:?}");
    // Both at once, with a length in millimetres: three doubts.
    let d = doubts(
        "[pendulum]\npivot_offset = 50\n[gyro]\nfull_scale = 2000\n[accel]\nfull_scale = 4\n",
    );
    assert_eq!(d.len(), 3, "{d:?}");
}

#[test]
fn a_gravity_off_the_earths_is_doubted_with_the_fix() {
    // `gravity = 1` (in g) left alg2 7.8 deg RMS off instead of 0.86, without a word.
    let doubts = |text: &str| RigConfig::from_toml_str(text, "rig.toml").unwrap().doubts();
    for ok in [
        "",
        "[pendulum]\ngravity = 9.78\n",
        "[pendulum]\ngravity = 9.832\n",
    ] {
        assert!(doubts(ok).is_empty(), "{ok}: {:?}", doubts(ok));
    }
    let d = doubts("[pendulum]\ngravity = 1.0\n");
    assert_eq!(d.len(), 1, "{d:?}");
    assert!(
        d[0].starts_with(
            "pendulum.gravity: 1 m/s^2 is not the Earth's gravity (9.78 to 9.83 m/s^2)"
        ) && d[0].contains("written in g? write pendulum.gravity = 9.80665"),
        "{d:?}"
    );
    let d = doubts("[pendulum]\ngravity = 980.665\n");
    assert!(
        d[0].contains("written in cm/s^2? write pendulum.gravity = 9.80665"),
        "{d:?}"
    );
    let d = doubts("[pendulum]\ngravity = 32.174\n");
    assert!(
        d[0].contains("written in ft/s^2? write pendulum.gravity = 9.80664"),
        "{d:?}"
    );
}

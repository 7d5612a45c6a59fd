//! Estimator families: which panel of the small-multiple figures a series belongs to, so
//! that no panel carries more than a handful of lines.

/// A family of estimators, in the order the panels are drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Family {
    /// The accelerometer's tilt (Eq 1) and the raw pendulum reading.
    Raw,
    /// The paper's Algorithms 1-3 (Eqs 20, 21, 30) and their variants (`alg2_*`).
    Paper,
    /// The Kalman filters (`kf_*`).
    Kalman,
    /// The model-based filters (EKF, UKF on the pendulum dynamics).
    ModelBased,
    /// Other attitude filters (Madgwick, Mahony, complementary).
    Peers,
    /// Anything else.
    Other,
}

impl Family {
    /// The family of a series name.
    pub fn of(name: &str) -> Family {
        match name {
            "accel" | "pendulum" => Family::Raw,
            "ekf" | "ukf" => Family::ModelBased,
            "madgwick" | "mahony" | "complementary" => Family::Peers,
            n if n.starts_with("kf_") => Family::Kalman,
            n if n.starts_with("alg") => Family::Paper,
            _ => Family::Other,
        }
    }

    /// The panel title.
    pub fn label(self) -> &'static str {
        match self {
            Family::Raw => "raw: accelerometer (Eq 1) and pendulum",
            Family::Paper => "the paper's algorithms (Eqs 20, 21, 30) and variants",
            Family::Kalman => "Kalman filters",
            Family::ModelBased => "model-based (EKF, UKF)",
            Family::Peers => "peers (Madgwick, Mahony, complementary)",
            Family::Other => "other",
        }
    }
}

/// `names` grouped by family, families in panel order, names in their given order.
pub fn group<'a>(names: impl IntoIterator<Item = &'a str>) -> Vec<(Family, Vec<&'a str>)> {
    let mut out: Vec<(Family, Vec<&'a str>)> = Vec::new();
    for n in names {
        let f = Family::of(n);
        match out.iter_mut().find(|(g, _)| *g == f) {
            Some((_, v)) => v.push(n),
            None => out.push((f, vec![n])),
        }
    }
    out.sort_by_key(|(f, _)| *f);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The 17 outputs of `reproduce` fall into five panels, none with more than six lines.
    #[test]
    fn the_bank_splits_into_five_small_panels() {
        let names: Vec<&str> = crate::bank::REGISTRY.iter().map(|e| e.name).collect();
        let g = group(names.iter().copied());
        let fams: Vec<Family> = g.iter().map(|(f, _)| *f).collect();
        assert_eq!(
            fams,
            [
                Family::Raw,
                Family::Paper,
                Family::Kalman,
                Family::ModelBased,
                Family::Peers
            ]
        );
        assert_eq!(g.iter().map(|(_, v)| v.len()).sum::<usize>(), 17);
        assert!(g.iter().all(|(_, v)| v.len() <= 6));
        assert_eq!(g[1].1, ["alg1", "alg2", "alg2_offset", "alg2_dc", "alg3"]);
        assert_eq!(Family::of("my_filter"), Family::Other);
    }
}

//! The catalogue of estimators: one row per estimator, planar and 3-D, with its name (the
//! prefix of its output columns), its model, its family, its colour in every figure, the
//! sensors it reads and one line on what it is.
//!
//! Everything that names estimators reads this table: the two registries (which add how
//! each one is built), `--help`, the report's panels and palette, the peers' columns and
//! the hint that tells a 3-D name given for a planar log. Adding an estimator is a row
//! here and an entry in its registry (`bank/planar/registry.rs` or `bank/spatial/mod.rs`), then the
//! golden outputs' re-bless.
use crate::sensors::Inputs;

/// Which model an estimator runs on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Model {
    /// A planar log (MODEL.md section 5): one tilt angle.
    Planar,
    /// A 3-D log (MODEL.md 7.6): roll and pitch.
    Spatial,
}

/// A family of estimators: which panel of the small-multiple figures a series belongs to,
/// so that no panel carries more than a handful of lines, and which estimators are the
/// peers a pendulum estimator is compared with.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Family {
    /// The accelerometer's tilt (Eq 1) and the raw pendulum reading.
    Raw,
    /// The paper's Algorithms 1-3 (Eqs 20, 21, 30) and their variants (`alg2_*`).
    Paper,
    /// The Kalman filters (`kf_*`).
    Kalman,
    /// The model-based filters (EKF, UKF on the pendulum dynamics, and the same filter on
    /// the accelerometer).
    ModelBased,
    /// Other attitude filters (Madgwick, Mahony, complementary, VQF, Fusion): the peers.
    Peers,
    /// Anything else.
    Other,
}

impl Family {
    /// The family of a series name: its catalogue row's, or for a name the catalogue does
    /// not hold, `kf_*` Kalman, `alg*` Paper, else Other.
    pub fn of(name: &str) -> Family {
        match listing(name) {
            Some(l) => l.family,
            None if name.starts_with("kf_") => Family::Kalman,
            None if name.starts_with("alg") => Family::Paper,
            None => Family::Other,
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

/// One estimator.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Listing {
    /// Its name: the prefix of its output columns (MODEL.md sections 5 and 7.6).
    pub name: &'static str,
    /// The model it runs on.
    pub model: Model,
    /// Its family.
    pub family: Family,
    /// Its colour in every figure (RGB).
    pub colour: [u8; 3],
    /// The sensors it reads: a log without one of them skips it (planar), a long gap of
    /// one restarts it and an implausible reading flags it (3-D). ekf3d and ukf3d read
    /// the accelerometer too, but only as an optional, gated measurement: its gaps do not
    /// restart them.
    pub reads: Inputs,
    /// One line on what it is, for `--help` and reports.
    pub about: &'static str,
}

const fn row(
    name: &'static str,
    model: Model,
    family: Family,
    colour: [u8; 3],
    reads: Inputs,
    about: &'static str,
) -> Listing {
    Listing {
        name,
        model,
        family,
        colour,
        reads,
        about,
    }
}

use Family::{Kalman, ModelBased, Paper, Peers, Raw};
use Model::{Planar, Spatial};

/// Every estimator, planar then 3-D, each in output column order.
///
/// Colours: the accelerometer grey and the Kalman filter fed by it orange; the pendulum
/// family blue/green/red; other filters in their own hues; the 3-D estimators each their
/// own (a hash could give two of them one colour).
pub static CATALOGUE: &[Listing] = &[
    row(
        "accel",
        Planar,
        Raw,
        [150, 150, 150],
        Inputs::ACCEL,
        "accelerometer, Eq (1)",
    ),
    row(
        "pendulum",
        Planar,
        Raw,
        [140, 86, 75],
        Inputs::PHI,
        "raw pendulum angle",
    ),
    row(
        "alg1",
        Planar,
        Paper,
        [31, 119, 180],
        Inputs::PHI,
        "Algorithm 1, Eq (20)",
    ),
    row(
        "alg2",
        Planar,
        Paper,
        [44, 160, 44],
        Inputs::PHI_GYRO,
        "Algorithm 2, Eqs (21)-(22)",
    ),
    // alg2's variants: a lighter alg2, and a hue of their own
    row(
        "alg2_offset",
        Planar,
        Paper,
        [152, 223, 138],
        Inputs::PHI_GYRO,
        "Algorithm 2 with the pivot-offset term (not in the paper)",
    ),
    row(
        "alg2_dc",
        Planar,
        Paper,
        [90, 60, 160],
        Inputs::PHI_GYRO,
        "Algorithm 2 with the differentiator's delay removed by the gyro (not in the paper)",
    ),
    row(
        "alg3",
        Planar,
        Paper,
        [214, 39, 40],
        Inputs::PHI_GYRO,
        "Algorithm 3's Eq (30) with the configured K, L, M, N",
    ),
    row(
        "kf_accel",
        Planar,
        Kalman,
        [255, 127, 14],
        Inputs::IMU,
        "Kalman filter fed by the accelerometer (the classic filter)",
    ),
    row(
        "kf_alg1",
        Planar,
        Kalman,
        [23, 190, 207],
        Inputs::PHI_GYRO,
        "Kalman filter fed by Algorithm 1",
    ),
    row(
        "kf_alg2",
        Planar,
        Kalman,
        [148, 103, 189],
        Inputs::PHI_GYRO,
        "Kalman filter fed by Algorithm 2",
    ),
    row(
        "kf_alg3",
        Planar,
        Kalman,
        [227, 119, 194],
        Inputs::PHI_GYRO,
        "Kalman filter fed by Algorithm 3",
    ),
    // not the fallback's amber, which sat beside kf_accel's orange in one panel
    row(
        "kf_fused",
        Planar,
        Kalman,
        [0, 128, 128],
        Inputs::ALL,
        "Kalman filter fed by the accelerometer and Algorithm 2 in turn",
    ),
    row(
        "ekf",
        Planar,
        ModelBased,
        [188, 189, 34],
        Inputs::PHI_GYRO,
        "EKF on the pendulum's own dynamics with l12 (the paper's future work)",
    ),
    row(
        "ukf",
        Planar,
        ModelBased,
        [0, 90, 50],
        Inputs::PHI_GYRO,
        "UKF on the same model",
    ),
    row(
        "madgwick",
        Planar,
        Peers,
        [120, 0, 120],
        Inputs::IMU,
        "Madgwick (ahrs crate), planar use, gain from a search on the scooter ride",
    ),
    row(
        "mahony",
        Planar,
        Peers,
        [0, 60, 140],
        Inputs::IMU,
        "Mahony (ahrs crate), planar use, gains from a search on the scooter ride",
    ),
    row(
        "complementary",
        Planar,
        Peers,
        [160, 90, 0],
        Inputs::IMU,
        "complementary filter of gyro and accelerometer",
    ),
    row(
        "pendulum3d",
        Spatial,
        Raw,
        [160, 100, 60],
        Inputs::PHI,
        "raw encoder angles: roll = phi_x, pitch = phi_y",
    ),
    row(
        "accel3d",
        Spatial,
        Raw,
        [130, 130, 130],
        Inputs::ACCEL,
        "roll and pitch of the accelerometer",
    ),
    row(
        "inv3d",
        Spatial,
        Paper,
        [50, 170, 80],
        Inputs::PHI_GYRO,
        "Algorithm 2 in three dimensions",
    ),
    row(
        "ekf3d",
        Spatial,
        ModelBased,
        [200, 30, 30],
        Inputs::PHI_GYRO,
        "quaternion EKF with the pendulum's equations of motion",
    ),
    row(
        "ukf3d",
        Spatial,
        ModelBased,
        [20, 170, 190],
        Inputs::PHI_GYRO,
        "the same model on the UKF",
    ),
    row(
        "imu3d",
        Spatial,
        ModelBased,
        [204, 121, 167],
        Inputs::IMU,
        "ekf3d's filter with the accelerometer in place of the encoders (the ablation)",
    ),
    row(
        "vqf",
        Spatial,
        Peers,
        [240, 140, 0],
        Inputs::IMU,
        "VQF 6D (peer, vqf-rs)",
    ),
    row(
        "madgwick3d",
        Spatial,
        Peers,
        [130, 20, 140],
        Inputs::IMU,
        "Madgwick IMU filter (peer, ahrs)",
    ),
    row(
        "mahony3d",
        Spatial,
        Peers,
        [40, 90, 200],
        Inputs::IMU,
        "Mahony IMU filter (peer, ahrs)",
    ),
    row(
        "fusion3d",
        Spatial,
        Peers,
        [0, 158, 115],
        Inputs::IMU,
        "Fusion-style complementary filter with acceleration rejection (peer)",
    ),
];

/// The catalogue's row for `name`, if it holds one.
pub fn listing(name: &str) -> Option<&'static Listing> {
    CATALOGUE.iter().find(|l| l.name == name)
}

/// The catalogue's row for `name`. Panics on a name it does not hold: for the
/// registries, whose names a test checks against the catalogue.
pub(crate) fn expect(name: &str) -> &'static Listing {
    listing(name).unwrap_or_else(|| panic!("`{name}` is not in the catalogue"))
}

/// The names of one model's estimators, in output column order.
pub fn names(model: Model) -> impl Iterator<Item = &'static str> {
    CATALOGUE
        .iter()
        .filter(move |l| l.model == model)
        .map(|l| l.name)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each registry builds exactly its model's estimators, in the catalogue's order.
    #[test]
    fn the_registries_build_the_catalogue_in_its_order() {
        let planar: Vec<&str> = crate::bank::planar::REGISTRY
            .iter()
            .map(|e| e.name)
            .collect();
        let spatial: Vec<&str> = crate::bank::spatial::REGISTRY3D
            .iter()
            .map(|e| e.name)
            .collect();
        assert_eq!(planar, names(Model::Planar).collect::<Vec<_>>());
        assert_eq!(spatial, names(Model::Spatial).collect::<Vec<_>>());
    }

    /// Names are unique, and no two estimators of one figure share a colour.
    #[test]
    fn names_and_colours_are_unique() {
        for (i, a) in CATALOGUE.iter().enumerate() {
            for b in &CATALOGUE[i + 1..] {
                assert_ne!(a.name, b.name);
                if a.model == b.model {
                    assert_ne!(a.colour, b.colour, "{} and {}", a.name, b.name);
                }
            }
        }
    }

    /// An estimator reads at least one sensor; the peers read the IMU and not the
    /// pendulum.
    #[test]
    fn every_estimator_reads_a_sensor_and_the_peers_the_imu_alone() {
        for l in CATALOGUE {
            assert!(!l.reads.is_empty(), "{}", l.name);
            if l.family == Family::Peers {
                assert_eq!(l.reads, Inputs::IMU, "{}", l.name);
            }
        }
    }

    #[test]
    fn families_of_names_outside_the_catalogue_follow_their_prefix() {
        assert_eq!(Family::of("ekf3d"), Family::ModelBased);
        assert_eq!(Family::of("vqf"), Family::Peers);
        assert_eq!(Family::of("kf_custom"), Family::Kalman);
        assert_eq!(Family::of("alg9"), Family::Paper);
        assert_eq!(Family::of("theta"), Family::Other);
    }
}

//! The estimators built by name one at a time, from normalised or physical parameters
//! and the peers' settings, every other setting at its default: what the peers' gain
//! searches and the benches use.
use super::{build_alone, BankSettings, BoxedEstimator};
use crate::peers::PeerSettings;
use pendtilt_core::{PendulumParams, PhysicalParams};

/// Builds the estimator of column `name` (one of [`crate::peers::COLUMNS`], or any other stand-alone
/// entry of [`REGISTRY`](super::REGISTRY), the one name-to-constructor table) for normalised
/// parameters `params` under gravity `gravity`, every other setting at its default;
/// `None` for an unknown name.
pub fn build(
    name: &str,
    params: &PendulumParams<f64>,
    gravity: f64,
    peer: &PeerSettings,
) -> Option<BoxedEstimator> {
    let settings = BankSettings {
        gravity: Some(gravity),
        peers: *peer,
        ..BankSettings::from_params(*params)
    };
    build_alone(name, &settings)
}

/// [`build`] from the rig's physical parameters.
pub fn build_physical(
    name: &str,
    rig: &PhysicalParams<f64>,
    peer: &PeerSettings,
) -> Option<BoxedEstimator> {
    build(name, &rig.normalised(), rig.gravity, peer)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::peers::COLUMNS;

    #[test]
    fn every_column_builds_and_unknown_names_do_not() {
        let rig = PhysicalParams::<f64>::default();
        for name in COLUMNS {
            let mut e = build_physical(name, &rig, &PeerSettings::default()).unwrap();
            let s = pendtilt_core::Sample {
                dt: 0.0,
                phi: 0.1,
                gyro: 0.0,
                ax: 9.81 * 0.1f64.sin(),
                ay: 9.81 * 0.1f64.cos(),
            };
            let est = e.update(&s);
            assert!((est.theta - 0.1).abs() < 1e-9, "{name}: {}", est.theta);
        }
        assert!(build_physical("alg9", &rig, &PeerSettings::default()).is_none());
    }
}

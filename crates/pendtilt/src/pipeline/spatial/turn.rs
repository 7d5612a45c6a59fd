//! The gyro's unit from a vehicle's turns (the yaw rate against the lateral force).
use crate::units::{Fit, Pair, Smooth};

/// The gyro's unit from a vehicle's turns: in a turn the lateral specific force is the
/// speed times the yaw rate, `a_y ~ v gyro_z` (MODEL.md 7.7: `a_O = v' d + v d'`, FLU), up to
/// the roll's share of gravity. Both low-passed at [`TURN_HZ`]; on ride3d (60 s, seed 1)
/// with the gyro in deg/s the fit of `v gyro_z` on `a_y` gives 54.4 (0.95 x 57.3) at
/// r = 0.96. The encoders cannot tell there:
/// a car's turns swing its pendulum outward, so d(phi)/dt is not the gyro (a gyro in deg/s
/// on ride3d was found only by the slip warning, which blamed the speed first).
pub(super) struct TurnCheck {
    /// `a_y` and `v gyro_z`, low-passed.
    lp: [Smooth; 2],
    /// Time since the filters started \[s\] (pairs are taken after [`TURN_SETTLE`]).
    since: f64,
    pair: Pair,
}

/// The low-pass of [`TurnCheck`] \[Hz\]: the turns, not the vibration or the road.
pub(super) const TURN_HZ: f64 = 0.5;
/// The filters' settling time before pairs are taken \[s\].
const TURN_SETTLE: f64 = 2.0;
/// The least standard deviation of the low-passed lateral specific force for the turn
/// check \[m/s^2\]: ride3d's is 1.18; a ship's (0.07 of v gyro_z) has no turns to tell.
const TURN_MIN_LATERAL: f64 = 0.3;

impl TurnCheck {
    pub(super) fn new() -> Self {
        Self {
            lp: [Smooth::new(TURN_HZ); 2],
            since: 0.0,
            pair: Default::default(),
        }
    }

    /// One row: `gyro_z` \[as read, times the --deg factor\], `a_y` \[m/s^2\], `speed`.
    pub(super) fn add(&mut self, dt: f64, gyro_z: f64, a_y: f64, speed: Option<f64>) {
        let Some(v) = speed else {
            return;
        };
        let (x, y) = (a_y, v * gyro_z);
        if !(x.is_finite() && y.is_finite() && dt > 0.0 && dt < 0.1) {
            return;
        }
        let (x, y) = (self.lp[0].update(x, dt), self.lp[1].update(y, dt));
        self.since += dt;
        if self.since >= TURN_SETTLE {
            self.pair.add(x, y);
        }
    }

    /// The factor of `v gyro_z` on `a_y` (1 in rad/s, 57.3 in deg/s), when the log turned.
    /// The noise is in `a_y` (the roll's share of gravity, the vibration left): the factor
    /// of the regression of `a_y` on `v gyro_z`, not the other way (ride3d, seeds 1-4, deg/s:
    /// 50.0, 41.2, 43.1, 48.2 the other way, against 57.3).
    pub(super) fn fit(&self) -> Option<Fit> {
        self.pair.fit_noisy_x_above(TURN_MIN_LATERAL)
    }
}

//! Operations on the filter's covariance: decorrelating and loosening states, the rate
//! noise of a held gyro, and the bound on the unobserved heading.
use crate::engine::{Cov, GaussianFilter};
use crate::spatial::ekf::state::{State, A, B, N, ROT};
use crate::Real;
use nalgebra::Vector3;

/// Bound on the variance of the heading error \[rad^2\]: rotations about the world's
/// vertical are observed by no sensor, so without a bound their variance grows for ever
/// (gyro noise and the z bias's walk: about 1e3 rad^2 after two hours), and next to the
/// encoders' 1e-8 rad^2 that leaves f32 with no precision (0.36 deg from f64 after two
/// hours). When it passes twice the bound it is scaled back to it (the correlations kept).
/// Small, because a large heading error makes both filters' linearisation (the rotation
/// errors compose, they do not add) cost roll and pitch: ukf3d's sigma points spread it by
/// sqrt(10). Measured (`spatial_scenarios`): at 0.1 rad^2 ukf3d was 1.12 deg RMS on the
/// noise-free still3d and ekf3d 0.31 deg on scooter3d at its defaults; at 1e-3, 0.018 and
/// 0.23; at 1e-5, 0.0027 (ekf3d's 0.0025) and 0.18; below that little changes.
pub(super) const HEADING_VARIANCE: f64 = 1e-5;

/// Zeroes the covariances between the states `apart` picks and all others.
pub(super) fn uncorrelate<T: Real>(p: &mut Cov<T, N>, apart: impl Fn(usize) -> bool) {
    for i in 0..N {
        for j in 0..N {
            if i != j && (apart(i) || apart(j)) {
                p[(i, j)] = T::zero();
            }
        }
    }
}

/// Roll and pitch made uncorrelated with the rest and their standard deviation raised to
/// at least `sd` \[rad\] (a re-acquisition, a reset onto the guard's reference).
pub(super) fn loosen_roll_pitch<T: Real>(p: &mut Cov<T, N>, sd: T) {
    uncorrelate(p, |i| i == ROT || i == ROT + 1);
    for i in [ROT, ROT + 1] {
        p[(i, i)] = p[(i, i)].max(sd * sd);
    }
}

/// `q` with `share[k]` more variance of the rotation about body axis `k` over the step (a
/// held or clipped gyro's rate error): it turns the attitude one way and the joint angles
/// the other (as the gyro's own noise does, see `CardanProcess::q`).
pub(super) fn add_rate_noise<T: Real>(mut q: Cov<T, N>, share: &Vector3<T>) -> Cov<T, N> {
    for k in 0..3 {
        q[(ROT + k, ROT + k)] += share[k];
    }
    for (k, joint) in [(0, A), (1, B)] {
        q[(joint, joint)] += share[k];
        q[(ROT + k, joint)] -= share[k];
        q[(joint, ROT + k)] -= share[k];
    }
    q
}

/// Scales the covariance along the unobserved heading back to [`HEADING_VARIANCE`] once it
/// passes twice that. The rotation error is in body axes, so a turn about the world's
/// vertical is one about `u`, the up direction in body axes.
pub(super) fn bound_heading<T: Real, F: GaussianFilter<T, State<T>, N>>(f: &mut F) {
    let u = f.state().up();
    let p = f.covariance().fixed_view::<3, 3>(ROT, ROT).into_owned();
    let var = u.dot(&(p * u));
    let cap = T::lit(HEADING_VARIANCE);
    if var > cap + cap && var.is_finite() {
        let k = T::one() - (cap / var).sqrt();
        let mut t = Cov::<T, N>::identity();
        let shrink = nalgebra::Matrix3::<T>::identity() - u * u.transpose() * k;
        t.fixed_view_mut::<3, 3>(ROT, ROT).copy_from(&shrink);
        f.transform(&t);
    }
}

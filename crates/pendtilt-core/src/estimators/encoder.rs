//! The encoder reading as the pendulum estimators take it: range check, wrap-around
//! unwrapping, and the wrap back of an estimate into (-pi, pi].
use crate::Real;

pub use crate::model::PHI_LIMIT;

/// True when `phi` is a usable encoder reading.
#[inline]
pub(crate) fn is_reading<T: Real>(phi: T) -> bool {
    phi.is_finite() && phi.abs() < T::lit(PHI_LIMIT)
}

/// Keeps consecutive encoder readings within half a turn of each other, so an encoder
/// that wraps at ±pi (or reports [0, 2 pi)) gives a continuous angle.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Unwrapper<T> {
    offset: T,
    prev: Option<T>,
}

impl<T: Real> Unwrapper<T> {
    pub fn new() -> Self {
        Self {
            offset: T::zero(),
            prev: None,
        }
    }

    /// The continuous angle for reading `phi`, and whether a wrap was removed.
    #[inline]
    pub fn unwrap(&mut self, phi: T) -> (T, bool) {
        let mut phi = phi + self.offset;
        let mut wrapped = false;
        if let Some(p) = self.prev {
            let jump = phi - p;
            if jump.abs() > T::pi() {
                let turns = (jump / T::two_pi()).round() * T::two_pi();
                self.offset -= turns;
                phi -= turns;
                wrapped = true;
            }
        }
        self.prev = Some(phi);
        (phi, wrapped)
    }
}

/// `x` wrapped into (-pi, pi] (unchanged when already there).
#[inline]
pub(crate) fn wrap_angle<T: Real>(x: T) -> T {
    if x.abs() > T::pi() {
        x.sin().atan2(x.cos())
    } else {
        x
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unwraps_across_the_seam_and_wraps_back() {
        let mut u = Unwrapper::<f64>::new();
        assert_eq!(u.unwrap(3.1), (3.1, false));
        let (p, w) = u.unwrap(-3.1); // crossed +pi: continuous at 2 pi - 3.1
        assert!(w && (p - (2.0 * core::f64::consts::PI - 3.1)).abs() < 1e-12);
        assert!((wrap_angle(p) + 3.1).abs() < 1e-12);
        assert!(!is_reading(f64::NAN) && !is_reading(2e4) && is_reading(-1.0));
    }
}

//! Per-sample diagnostics shared by every estimator.

bitflags::bitflags! {
    /// What happened while an estimate was computed. An empty set means a normal sample.
    ///
    /// Flags are sticky only for the sample they are returned with; every `update`
    /// returns a fresh set.
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
    pub struct Flags: u16 {
        /// The estimator has not seen enough samples for its filters or windows to be valid
        /// (for example the first sample, or the Eq (22) gyro window still filling).
        const INITIALISING = 1 << 0;
        /// The argument of asin left [-1, 1] and was clamped (Eqs 20, 21, 30): the
        /// parameters or the data are inconsistent with the pendulum model.
        const ASIN_CLAMPED = 1 << 1;
        /// A required input was missing or not finite: the output holds (or, for a
        /// filter, predicts) instead of using it.
        const SAMPLE_MISSING = 1 << 2;
        /// The time step was not positive or not finite: the sample was not integrated.
        const BAD_TIME_STEP = 1 << 3;
        /// A sensor was at its full-scale limit.
        const SATURATED = 1 << 4;
        /// A Kalman measurement was not used (missing, or flagged by its source).
        const MEASUREMENT_SKIPPED = 1 << 5;
        /// The encoder angle jumped by about a full turn and was unwrapped.
        const ENCODER_WRAPPED = 1 << 6;
        /// A reading of the row was implausible (beyond its sensor's full scale or
        /// physically impossible) and was read as missing before any estimator saw it.
        const IMPLAUSIBLE = 1 << 7;
        /// The wheel-speed reading disagreed with the accelerometer (wheel spin or lock):
        /// it was not used for this sample, the speed was carried by the accelerometer
        /// (ekf3d, ukf3d).
        const SLIP = 1 << 8;
        /// The pendulum left the range where its model holds (near the Cardan joint's lock,
        /// or a run of readings the model could not explain): its reading was not used and
        /// the attitude was carried by the gyro (ekf3d, ukf3d).
        const PENDULUM_UNUSED = 1 << 9;
        /// The attitude was reset to the gyro and accelerometer's inclination reference:
        /// the two had parted by more than the guard (ekf3d, ukf3d).
        const RESET = 1 << 10;
        /// The input line could not be read (a malformed line of a live stream: a cell
        /// that is no number, a wrong number of fields): no estimator saw it, and its
        /// output row holds NaN so that the rows still match the input's.
        const BAD_LINE = 1 << 11;
    }
}

impl Flags {
    /// Short names of the set flags, `|`-separated, for CSV output (empty when none).
    pub fn names(self) -> FlagNames {
        FlagNames(self)
    }
}

/// Display adapter returned by [`Flags::names`]: `asin_clamped|initialising`.
#[derive(Debug, Clone, Copy)]
pub struct FlagNames(Flags);

impl core::fmt::Display for FlagNames {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        const NAMES: [(Flags, &str); 12] = [
            (Flags::INITIALISING, "initialising"),
            (Flags::ASIN_CLAMPED, "asin_clamped"),
            (Flags::SAMPLE_MISSING, "sample_missing"),
            (Flags::BAD_TIME_STEP, "bad_time_step"),
            (Flags::SATURATED, "saturated"),
            (Flags::MEASUREMENT_SKIPPED, "measurement_skipped"),
            (Flags::ENCODER_WRAPPED, "encoder_wrapped"),
            (Flags::IMPLAUSIBLE, "implausible"),
            (Flags::SLIP, "slip"),
            (Flags::PENDULUM_UNUSED, "pendulum_unused"),
            (Flags::RESET, "reset"),
            (Flags::BAD_LINE, "bad_line"),
        ];
        let mut first = true;
        for (flag, name) in NAMES {
            if self.0.contains(flag) {
                if !first {
                    f.write_str("|")?;
                }
                f.write_str(name)?;
                first = false;
            }
        }
        Ok(())
    }
}

//! The 3-D peers: the IMU filters a user would run instead of a
//! pendulum, on the same spatial samples, as [`SpatialEstimator`]s: VQF (the `vqf-rs`
//! port of Laidig and Seel's reference implementation, 6D: gyro + accelerometer),
//! Madgwick's and Mahony's filters (the `ahrs` crate's IMU updates), and a Fusion-style
//! complementary filter ([`super::fusion`]).
//!
//! Common to all (one wrapper, [`Imu6`]): a sample whose time step is refused is held
//! and flagged; the filter starts on the first sample with a usable accelerometer reading,
//! at its roll and pitch (Madgwick and Mahony; VQF starts itself, built on the next sample
//! for the step to it, [`ImuFilter::BUILT_WITH_STEP`]); after a restart
//! ([`pendtilt_core::Estimator::resume`], a long gap) at the mean accelerometer direction over
//! [`RESTART_AVERAGE`], keeping what the filter says a gap cannot change (VQF's bias;
//! Mahony's steady offset from the accelerometer, [`Imu6::with_restart_offset`]); a
//! missing gyro reading is bridged, axis by axis, by the gyro's recent mean (as the planar
//! peers do, see [`super::ahrs_planar::MISSING_RATE_TAU`]), and the attitude held through
//! the gap is corrected once the gyro is back ([`Imu6::with_gap_bridge`]: Mahony at kp,
//! VQF at 1 / tau_acc, fusion3d at its gain; Madgwick, which forgets an angle error within
//! ms, takes none); a missing accelerometer reading skips the correction (flagged; VQF
//! takes a reading with only some axes missing with those from their recent mean,
//! [`ImuFilter::bridges_accel`]); a gyro reading at or beyond the rig's full scale
//! ([`Imu6::with_gyro_full_scale`]) is flagged `saturated` (and still used: the filters
//! have no other rate). Roll and pitch are those of the filter's up direction in body
//! axes.
use nalgebra_ahrs::{UnitQuaternion, Vector3};
use pendtilt_core::spatial::SpatialEstimator;

use super::ahrs_planar::PlanarAhrs;
use super::fusion::{Fusion, FusionSettings};

mod imu6;
pub use imu6::{Imu6, MakeFilter};

/// An IMU filter the wrapper [`Imu6`] drives.
pub trait ImuFilter {
    /// What it is built from (its gains or settings).
    type Params: Copy + core::fmt::Debug;
    /// One gyro + accelerometer step of `dt`; `accel` is `None` when missing. Returns
    /// `false` if the filter skipped the correction.
    fn step(&mut self, gyro: [f64; 3], accel: Option<[f64; 3]>, dt: f64) -> bool;
    /// The world's up direction in body axes.
    fn up(&self) -> [f64; 3];
    /// Takes over from `old`, the filter that ran before a restart after a long gap, what
    /// a gap cannot change. Default: nothing (the filter starts afresh).
    fn keep_from(&mut self, _old: &Self) {}
    /// How long \[s\] the wrapper averages the accelerometer (carried by the gyro) before it starts
    /// the filter after a restart ([`Estimator::resume`](pendtilt_core::Estimator::resume)),
    /// instead of starting it at one reading. Default [`RESTART_AVERAGE`].
    fn restart_average(&self) -> f64 {
        RESTART_AVERAGE
    }
    /// Whether a reading with some accelerometer axes missing should reach the filter with
    /// those axes from their recent mean rather than be skipped. Default: skipped.
    fn bridges_accel(&self) -> bool {
        false
    }
    /// Whether the filter is built for the log's sample time and takes its first reading
    /// itself (VQF: its low-pass, rest detection and bias estimation coefficients follow
    /// from the sample time, fixed when it is built). The wrapper then holds the first
    /// usable sample, builds the filter on the next with the step between them, and feeds
    /// it both. Default: no (built on the first usable sample, at its roll and pitch, the
    /// published Madgwick and Mahony start).
    const BUILT_WITH_STEP: bool = false;
}

/// Default of [`ImuFilter::restart_average`] \[s\]: after a long gap Madgwick, Mahony and
/// the Fusion-style filter start at the mean accelerometer direction over this long rather
/// than at one reading, which on a vibrating body is degrees off (up to 24 deg on the
/// scooter3d ride, accel3d's error there) and which they then forget only at their gain.
/// A first start is unchanged (the published filters' start).
pub const RESTART_AVERAGE: f64 = 1.0;

fn up_of(q: &UnitQuaternion<f64>) -> [f64; 3] {
    let u = q.inverse_transform_vector(&Vector3::z());
    [u[0], u[1], u[2]]
}

/// Madgwick's and Mahony's filters of the `ahrs` crate, through the planar wrapper's
/// trait (the sample period and the attitude).
impl<F: PlanarAhrs> ImuFilter for F {
    type Params = [f64; 2];
    fn step(&mut self, gyro: [f64; 3], accel: Option<[f64; 3]>, dt: f64) -> bool {
        self.set_period(dt);
        let g = Vector3::from(gyro);
        match accel {
            Some(a) => self.update_imu(&g, &Vector3::from(a)).is_ok(),
            None => {
                self.update_gyro(&g);
                false
            }
        }
    }
    fn up(&self) -> [f64; 3] {
        up_of(&self.attitude())
    }
}

impl ImuFilter for vqf_rs::VQF {
    type Params = [f64; 2];
    fn step(&mut self, gyro: [f64; 3], accel: Option<[f64; 3]>, dt: f64) -> bool {
        self.update_gyr_with_ts(gyro, dt);
        match accel {
            Some(a) => {
                self.update_acc(a);
                true
            }
            None => false,
        }
    }
    /// VQF's gyro bias estimate (and its uncertainty) survives a gap: VQF learns it over
    /// minutes at rest or in motion, and losing it left the restarted VQF 1.02 deg from the
    /// fault-free run 2 s to 12 s after a 10 s gap (scooter3d).
    fn keep_from(&mut self, old: &Self) {
        let (bias, sigma) = old.bias_estimate();
        self.set_bias_estimate(bias, Some(sigma));
    }
    /// Yes: VQF low-passes the accelerometer per reading (tau_acc), so skipped readings
    /// leave out their share of the vibration, which the low-pass forgets only at tau_acc
    /// (one missing ax axis for 100 ms left it 0.066 deg off the fault-free run 2 s later,
    /// back after 3.48 s, on the ride of tests/faults3d/; bridged: 0).
    fn bridges_accel(&self) -> bool {
        true
    }
    /// None: VQF averages its first `tau_acc` of readings itself.
    fn restart_average(&self) -> f64 {
        0.0
    }
    /// Yes: built for 1 ms before the step was known, VQF ran BROAD's 3.5 ms samples with
    /// 3.5 times its time constants (tau_acc 10.5 s instead of 3 s) and scored 0.72 instead
    /// of the reference's 0.43 deg RMS on trial 02; built for the step, it follows the
    /// reference within 1e-10 deg.
    const BUILT_WITH_STEP: bool = true;
    fn up(&self) -> [f64; 3] {
        // VQF's quaternion turns body (sensor) vectors into world (earth) vectors.
        let q = self.quat_6d();
        vqf_rs::Quaternion(q.0, -q.1, -q.2, -q.3).rotate([0.0, 0.0, 1.0])
    }
}

/// A clip of the gyro at least this long \[s\] restarts a peer when it ends
/// ([`Imu6::update_clipped`]): 50 ms, as ekf3d's re-acquisition after a hold, so that the
/// vibration's peaks clipped a few ms at a time restart nothing (tests/faults3d/, `gyro
/// range`: restarting after every clip of 3 ms or more took Mahony 6.71 s instead of 1.45 s
/// back to its fault-free run; 50 ms and 300 ms gave the same as no restart there). After
/// 2 s clipped at 0.1 rad/s (`gyro clipped`): VQF 0.557 deg RMS from the truth instead of
/// 0.920, Mahony back within 0.05 deg of its fault-free run after 3.80 s instead of 9.97 s.
pub const CLIP_RESTART_AFTER: f64 = 0.05;

/// Madgwick's gain (`beta` [rad/s]) in 3-D: the planar search's value until the 3-D search
/// (the fair tuning) replaces it.
pub const MADGWICK3D_BETA: f64 = super::ahrs_planar::MADGWICK_BETA;
/// Mahony's gains (`kp` [1/s], `ki` [1/s^2]) in 3-D, likewise.
pub const MAHONY3D_GAINS: [f64; 2] = super::ahrs_planar::MAHONY_GAINS;
/// VQF's accelerometer time constant `tau_acc` \[s\]: the authors' default, 3 s.
pub const VQF_TAU_ACC: f64 = 3.0;
/// Madgwick's gain at the `ahrs` Python package's default (`gain_imu`, 0.033 rad/s), the
/// reference filter's (tools/broad_reference.py), for checking the port against it.
pub const AHRS_PY_MADGWICK_BETA: f64 = 0.033;
/// Mahony's gains at the `ahrs` Python package's defaults (`k_P` 1 /s, `k_I` 0.3 /s^2).
pub const AHRS_PY_MAHONY_GAINS: [f64; 2] = [1.0, 0.3];

/// Madgwick's IMU filter (column `madgwick3d`), gain `beta`.
pub fn madgwick3d(beta: f64) -> Imu6<ahrs::Madgwick<f64>> {
    Imu6::new(
        |r, p, dt, g: &[f64; 2]| {
            ahrs::Madgwick::new_with_quat(dt, g[0], UnitQuaternion::from_euler_angles(r, p, 0.0))
        },
        [beta, 0.0],
    )
}

/// Mahony's IMU filter (column `mahony3d`), gains `kp`, `ki`; after a restart in its own
/// steady state relative to the accelerometer ([`Imu6::with_restart_offset`]).
pub fn mahony3d(kp: f64, ki: f64) -> Imu6<ahrs::Mahony<f64>> {
    Imu6::new(
        |r, p, dt, g: &[f64; 2]| {
            ahrs::Mahony::new_with_quat(
                dt,
                g[0],
                g[1],
                UnitQuaternion::from_euler_angles(r, p, 0.0),
            )
        },
        [kp, ki],
    )
    .with_restart_offset(kp)
    .with_gap_bridge(kp)
}

/// VQF, 6D with its rest and motion bias estimation (column `vqf`), `tau_acc` \[s\]; its
/// other parameters at the authors' defaults. It starts itself (from the identity, its
/// accelerometer low-pass aligning within a few `tau_acc`), so roll and pitch are not
/// imposed; its sample time is the log's first step.
pub fn vqf(tau_acc: f64) -> Imu6<vqf_rs::VQF> {
    Imu6::new(
        |_, _, dt, g: &[f64; 2]| {
            let params = vqf_rs::Params {
                tau_acc: g[0],
                ..Default::default()
            };
            vqf_rs::VQF::new(dt, None, None, Some(params))
        },
        [tau_acc, 0.0],
    )
    .with_gap_bridge(1.0 / tau_acc)
}

/// The Fusion-style complementary filter (column `fusion3d`, [`super::fusion`]) with
/// `settings`; it starts at the first accelerometer reading's roll and pitch, then runs
/// its start-up ramp.
pub fn fusion3d(settings: FusionSettings) -> Imu6<Fusion> {
    Imu6::new(|r, p, _, s| Fusion::new(*s, r, p), settings).with_gap_bridge(settings.gain)
}

/// Every 3-D peer with its default gains, by column name.
pub fn peers() -> Vec<(&'static str, Box<dyn SpatialEstimator<f64>>)> {
    vec![
        ("vqf", Box::new(vqf(VQF_TAU_ACC))),
        ("madgwick3d", Box::new(madgwick3d(MADGWICK3D_BETA))),
        (
            "mahony3d",
            Box::new(mahony3d(MAHONY3D_GAINS[0], MAHONY3D_GAINS[1])),
        ),
        ("fusion3d", Box::new(fusion3d(FusionSettings::default()))),
    ]
}

#[cfg(test)]
mod tests {
    use super::imu6::{cross, norm};
    use super::*;
    use pendtilt_core::spatial::attitude::{inclination_error, up_from_roll_pitch};
    use pendtilt_core::spatial::{Attitude, SpatialSample};
    use pendtilt_core::{Estimator, Flags};

    /// After a restart Mahony starts at the accelerometer's mean over RESTART_AVERAGE, not
    /// at one reading: on a still tilt with +-3 m/s^2 of vibration across the vertical
    /// (alternating each sample, 17 deg of apparent tilt in one reading) it starts within
    /// 0.1 deg of the tilt, flagged initialising until then.
    #[test]
    fn after_a_restart_mahony_starts_at_the_mean_accelerometer_direction() {
        let (roll, pitch): (f64, f64) = (0.3, -0.2);
        let f = up_from_roll_pitch(roll, pitch).map(|v| v * 9.81);
        let mut e = mahony3d(MAHONY3D_GAINS[0], MAHONY3D_GAINS[1]);
        let sample = |k: usize| {
            SpatialSample::new(if k == 0 { 0.0 } else { 1e-3 }, [f64::NAN; 2], [0.0; 3], {
                // Across the vertical: (up x x) / |up x x| = (0, u_z, -u_y) / |..|.
                let n = (f[1] * f[1] + f[2] * f[2]).sqrt();
                let v = if k % 2 == 0 { 3.0 } else { -3.0 };
                [f[0], f[1] + v * f[2] / n, f[2] - v * f[1] / n]
            })
        };
        for k in 0..100 {
            e.update(&sample(k));
        }
        Estimator::resume(&mut e);
        let mut first = None;
        for k in 100..1200 {
            let a = e.update(&sample(k));
            if !a.flags.contains(Flags::INITIALISING) && first.is_none() {
                first = Some((k, a));
            }
        }
        let (k, a) = first.unwrap();
        // 1 s of 1 ms steps after the first reading.
        assert!((1100..=1102).contains(&k), "{k}");
        let err = (a.roll - roll).abs().max((a.pitch - pitch).abs());
        assert!(err < 0.1f64.to_radians(), "{a:?}");
    }

    /// Mahony (ki = 0) with a gyro bias stands off the accelerometer's tilt by the bias
    /// across the up direction over kp (0.01 rad/s cos(0.2) / 0.45 /s = 1.25 deg) on a still
    /// body; after a restart it starts there again, not at the accelerometer's tilt, from
    /// which it would take several time constants to get back. (Within 0.35 deg: the
    /// accelerometer's mean, carried by the biased gyro, lags by the bias over half the
    /// 1 s window, 0.29 deg.)
    #[test]
    fn after_a_restart_mahony_starts_in_its_own_steady_state() {
        let (roll, pitch): (f64, f64) = (0.3, -0.2);
        let f = up_from_roll_pitch(roll, pitch).map(|v| v * 9.81);
        let sample = |k: usize| {
            SpatialSample::new(
                if k == 0 { 0.0 } else { 1e-3 },
                [f64::NAN; 2],
                [0.01, 0.0, 0.0],
                f,
            )
        };
        let mut e = mahony3d(MAHONY3D_GAINS[0], MAHONY3D_GAINS[1]);
        let mut before = Attitude::unknown();
        for k in 0..30_000 {
            before = e.update(&sample(k));
        }
        let off = |a: &Attitude<f64>| inclination_error(a.roll, a.pitch, roll, pitch).to_degrees();
        // The bias across the up direction (body x is pitch away from the horizontal).
        let steady = 0.01 * pitch.cos() / MAHONY3D_GAINS[0];
        assert!(
            (off(&before) - steady.to_degrees()).abs() < 0.01,
            "{before:?}"
        );
        Estimator::resume(&mut e);
        let mut after = None;
        for k in 30_000..32_000 {
            let a = e.update(&sample(k));
            if !a.flags.contains(Flags::INITIALISING) && after.is_none() {
                after = Some(a);
            }
        }
        let after = after.unwrap();
        let moved = inclination_error(after.roll, after.pitch, before.roll, before.pitch);
        assert!(moved.to_degrees() < 0.35, "{after:?} {before:?}");
        // Without the fit it starts near the accelerometer's tilt (its mean lagging by the
        // bias over half the averaging window, 0.29 deg), about a degree away.
        let mut plain = mahony3d(MAHONY3D_GAINS[0], MAHONY3D_GAINS[1]).with_restart_offset(0.0);
        for k in 0..30_000 {
            plain.update(&sample(k));
        }
        Estimator::resume(&mut plain);
        let mut first = None;
        for k in 30_000..32_000 {
            let a = plain.update(&sample(k));
            if !a.flags.contains(Flags::INITIALISING) && first.is_none() {
                first = Some(a);
            }
        }
        let first = first.unwrap();
        let moved = inclination_error(first.roll, first.pitch, before.roll, before.pitch);
        assert!(moved.to_degrees() > 0.9, "{first:?}");
    }

    /// VQF takes a reading with a missing axis with that axis from its recent mean: on a
    /// still tilt with a 2 Hz, 3 m/s^2 sway on ay (ax constant), 100 ms without ax leave it
    /// on the fault-free run (within 1e-9 deg), where 100 ms without the whole reading
    /// (skipped) leave its 3 s low-pass without that share of the sway, which it forgets
    /// only at tau_acc: more than 0.01 deg off 1 s later.
    #[test]
    fn vqf_bridges_a_missing_accelerometer_axis() {
        let (roll, pitch): (f64, f64) = (0.3, -0.2);
        let g = up_from_roll_pitch(roll, pitch).map(|v| v * 9.81);
        let sample = |k: usize, missing: &[usize]| {
            let t = k as f64 * 1e-3;
            let mut accel = g;
            accel[1] += 3.0 * (core::f64::consts::TAU * 2.0 * t).sin();
            if (5000..5100).contains(&k) {
                for &i in missing {
                    accel[i] = f64::NAN;
                }
            }
            SpatialSample::new(
                if k == 0 { 0.0 } else { 1e-3 },
                [f64::NAN; 2],
                [0.0; 3],
                accel,
            )
        };
        let run = |missing: &[usize]| {
            let mut e = vqf(VQF_TAU_ACC);
            (0..6100)
                .map(|k| e.update(&sample(k, missing)))
                .last()
                .unwrap()
        };
        let clean = run(&[]);
        let off = |a: Attitude<f64>| {
            inclination_error(a.roll, a.pitch, clean.roll, clean.pitch).to_degrees()
        };
        assert!(off(run(&[0])) < 1e-9, "{}", off(run(&[0])));
        assert!(off(run(&[0, 1, 2])) > 0.01, "{}", off(run(&[0, 1, 2])));
    }

    /// VQF is built for the log's step, known only at the second sample, and takes the
    /// first sample too: on a 100 Hz log (tilting at 0.5 rad/s about x, then still) it
    /// gives what `vqf-rs` built for 10 ms and fed every sample gives, within 1e-9 deg at
    /// every sample after the first (built for 1 ms, as before the step was waited for, its
    /// 3 s accelerometer low-pass ran as 30 s: up to 0.11 deg off).
    #[test]
    fn vqf_is_built_for_the_logs_step() {
        let up_of_vqf = |v: &vqf_rs::VQF| {
            let q = v.quat_6d();
            vqf_rs::Quaternion(q.0, -q.1, -q.2, -q.3).rotate([0.0, 0.0, 1.0])
        };
        let angle = |a: [f64; 3], b: [f64; 3]| {
            norm(cross(a, b)).atan2(a.iter().zip(b).map(|(x, y)| x * y).sum())
        };
        let mut wrapped = vqf(VQF_TAU_ACC);
        let mut plain = vqf_rs::VQF::new(0.01, None, None, None);
        let mut worst: f64 = 0.0;
        for k in 0..1000 {
            let t = k as f64 * 0.01;
            let w = if t < 2.0 { 0.5 } else { 0.0 };
            let roll = 0.5 * t.min(2.0);
            let gyro = [w, 0.0, 0.0];
            let accel = up_from_roll_pitch(roll, 0.1).map(|v| v * 9.81);
            let a = wrapped.update(&SpatialSample::new(
                if k == 0 { 0.0 } else { 0.01 },
                [f64::NAN; 2],
                gyro,
                accel,
            ));
            plain.update(gyro, accel, None);
            if k > 0 {
                worst = worst.max(angle(
                    up_from_roll_pitch(a.roll, a.pitch),
                    up_of_vqf(&plain),
                ));
            }
        }
        assert!(worst.to_degrees() < 1e-9, "{} deg", worst.to_degrees());
    }

    /// A gyro clipped at the rig's full scale (0.1 rad/s) while the body rolls at 0.5 rad/s
    /// hides 0.4 rad of the roll per second of clip. After a 1 s clip Mahony restarts from
    /// the accelerometer's mean and reads the new tilt within 0.1 deg 1.5 s after the clip,
    /// where without the restart it still carries more than 5 deg of the hidden 23 deg
    /// (forgotten at kp = 0.45 /s). A 20 ms clip (shorter than CLIP_RESTART_AFTER, 8 mrad
    /// hidden) restarts nothing.
    #[test]
    fn a_long_gyro_clip_restarts_a_peer_when_it_ends() {
        let run = |clip_s: f64, restart: bool| {
            let mut e =
                mahony3d(MAHONY3D_GAINS[0], MAHONY3D_GAINS[1]).with_gyro_full_scale(Some(0.1));
            let (mut roll, mut restarted, mut last) = (0.0, false, Attitude::unknown());
            for k in 0..=3500 {
                let t = k as f64 * 1e-3;
                let w: f64 = if (1.0..1.0 + clip_s).contains(&t) {
                    0.5
                } else {
                    0.0
                };
                roll += w * 1e-3;
                let s = SpatialSample::new(
                    if k == 0 { 0.0 } else { 1e-3 },
                    [f64::NAN; 2],
                    [w.min(0.1), 0.0, 0.0],
                    up_from_roll_pitch(roll, 0.0).map(|v| v * 9.81),
                );
                last = if restart {
                    e.update(&s)
                } else {
                    e.advance(&s, w >= 0.1)
                };
                restarted |= t > 1.5 && last.flags.contains(Flags::INITIALISING);
            }
            let off = inclination_error(last.roll, last.pitch, roll, 0.0).to_degrees();
            (off, restarted)
        };
        let (off, restarted) = run(1.0, true);
        let (kept, restarted_plain) = run(1.0, false);
        println!("1.5 s after a 1 s clip: {off:.4} deg restarted, {kept:.2} deg not");
        assert!(restarted && off < 0.1, "{off} deg, restarted {restarted}");
        assert!(!restarted_plain && kept > 5.0, "{kept} deg");
        let (_, restarted) = run(0.02, true);
        assert!(!restarted);
    }

    /// The body rolls at a rate ramping at 0.5 rad/s^2; 100 ms of gyro readings are
    /// missing from 1 s. The hold integrates the mean before the gap and falls behind by
    /// (tau + L / 2) 0.5 rad/s^2 L = 0.21 deg; the bridge hands Mahony what the ramp turned
    /// beyond that once [`BRIDGE_WINDOW`] (0.42 s) of readings have followed, so 0.5 s after
    /// the gap it is within 0.01 deg of the run without the gap, where the hold alone is
    /// still 0.1 deg or more off (forgotten at kp = 0.45 /s only).
    #[test]
    fn mahony_takes_the_bridge_over_a_gap_in_the_gyro() {
        let run = |gap: bool, bridge: bool| {
            let mut e = mahony3d(MAHONY3D_GAINS[0], MAHONY3D_GAINS[1]);
            if !bridge {
                e = e.with_gap_bridge(-1.0);
            }
            let mut roll = 0.0;
            let mut last = Attitude::unknown();
            for k in 0..=1600 {
                let t = k as f64 * 1e-3;
                let w = 0.5 * t;
                roll += w * 1e-3;
                let missing = gap && (1000..1100).contains(&k);
                last = e.update(&SpatialSample::new(
                    if k == 0 { 0.0 } else { 1e-3 },
                    [f64::NAN; 2],
                    [if missing { f64::NAN } else { w }, 0.0, 0.0],
                    up_from_roll_pitch(roll, 0.0).map(|v| v * 9.81),
                ));
            }
            last
        };
        let clean = run(false, true);
        let off = |a: Attitude<f64>| {
            inclination_error(a.roll, a.pitch, clean.roll, clean.pitch).to_degrees()
        };
        let (bridged, held) = (off(run(true, true)), off(run(true, false)));
        println!("0.5 s after the gap: {bridged:.4} deg bridged, {held:.4} deg held");
        assert!(bridged < 0.01, "{bridged}");
        assert!(held > 0.1, "{held}");
    }

    /// On a still, tilted body with an ideal IMU every peer reads its roll and pitch (the
    /// quaternion conventions agree with MODEL.md 7.1).
    #[test]
    fn every_peer_reads_a_still_tilt() {
        let (roll, pitch) = (0.3, -0.2);
        let f = up_from_roll_pitch(roll, pitch).map(|v| v * 9.81);
        for (name, mut e) in peers() {
            let mut a = None;
            for k in 0..20_000 {
                let s =
                    SpatialSample::new(if k == 0 { 0.0 } else { 1e-3 }, [f64::NAN; 2], [0.0; 3], f);
                a = Some(e.update(&s));
            }
            let a = a.unwrap();
            assert!(
                (a.roll - roll).abs() < 1e-3 && (a.pitch - pitch).abs() < 1e-3,
                "{name}: {a:?}"
            );
        }
    }
}

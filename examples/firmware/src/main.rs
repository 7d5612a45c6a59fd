//! The firmware loop: one sensor sample in, every estimator updated, the estimates out,
//! at the sample rate, in `f32`, with no allocation and no standard library.
//!
//! On a real board `read_sensors` reads the encoder, gyro and accelerometer drivers and
//! `publish` hands the angle to the controller; here both are volatile accesses to
//! statics (standing in for memory-mapped registers) so that nothing is optimised away
//! and the binary's size is the size of the estimators. There is no runtime crate: the
//! entry point `_start` is the reset handler's body.
//!
//! Time: the estimators take `dt = t - t_prev` in `f32`. A free-running clock in seconds
//! loses resolution as it grows (at t = 16384 s the `f32` spacing is 2 ms, coarser than a
//! 1 kHz sample step), so the loop feeds time since start from an integer tick counter,
//! reset to zero at boot, and restarts the estimators (`reset`) every [`RESTART_AFTER_S`]
//! seconds (docs/reliability.md has the measurement).
#![no_std]
#![no_main]

use core::panic::PanicInfo;
use core::ptr::{addr_of, addr_of_mut, read_volatile, write_volatile};

use pendtilt_core::estimators::accel::{Accel, AccelSettings};
use pendtilt_core::estimators::alg1::{Alg1, Alg1Settings};
use pendtilt_core::estimators::alg2::{Alg2, Alg2Settings};
use pendtilt_core::estimators::alg3::{Alg3, Alg3Settings};
use pendtilt_core::estimators::pendulum::{Pendulum, PendulumSettings};
use pendtilt_core::kalman::tilt::UNUSABLE;
use pendtilt_core::kalman::{KalmanSettings, TiltKalman};
use pendtilt_core::{Estimate, Estimator, PendulumParams, Sample};

/// Sample rate of the loop [Hz].
const RATE_HZ: u32 = 1000;
/// Restart the estimators (and the time origin) after this long [s]. Measured on the
/// simulated scooter ride (`tests/f32_vs_f64.rs`): with the f32 clock 60 s old every
/// estimator is within 0.003 deg RMS of f64; 300 s old, 0.01 deg; 1 hour old, 0.87 deg
/// (the f32 time spacing, 0.24 ms, jitters dt by a quarter of the 1 ms step). A restart
/// costs the differentiators' settling (about half a second at the default cutoff), so a
/// firmware that cannot accept that should keep time in a wider type (see
/// docs/reliability.md).
const RESTART_AFTER_S: u32 = 60;
/// Eq (22) window capacity in samples (if the window source is chosen): 32, not the
/// library's 256, to keep RAM small.
const W: usize = 32;

/// Stand-ins for the sensor registers: tick counter, encoder [rad], gyro [rad/s],
/// accelerometer [m/s^2]. A board support package would read its drivers instead.
static mut TICKS: u32 = 0;
static mut SENSORS: [f32; 4] = [0.0; 4];
/// Stand-in for the controller's input: one angle [rad] and its flags per estimator.
static mut OUT: [(f32, u16); 6] = [(0.0, 0); 6];

fn read_sensors(t0_ticks: u32) -> Sample<f32> {
    // SAFETY: single-threaded firmware; volatile reads of plain statics.
    let (ticks, s) = unsafe {
        (
            read_volatile(addr_of!(TICKS)),
            read_volatile(addr_of!(SENSORS)),
        )
    };
    Sample {
        // Time since the last restart, from an integer counter: no lost resolution.
        t: ticks.wrapping_sub(t0_ticks) as f32 / RATE_HZ as f32,
        phi: s[0],
        gyro: s[1],
        ax: s[2],
        ay: s[3],
    }
}

fn publish(i: usize, e: Estimate<f32>) {
    // SAFETY: as above; `i` < 6 by construction.
    unsafe {
        let out = &mut *addr_of_mut!(OUT);
        write_volatile(&mut out[i], (e.theta, e.flags.bits()));
    }
}

/// The estimator bank of the firmware: the paper's estimators and its Kalman filter on
/// Algorithm 2, all in `f32`, on the stack.
struct Bank {
    accel: Accel<f32>,
    pendulum: Pendulum<f32>,
    alg1: Alg1<f32>,
    alg2: Alg2<f32, W>,
    alg3: Alg3<f32, W>,
    kf_alg2: TiltKalman<f32>,
}

impl Bank {
    fn new() -> Self {
        // The rig's parameters; a firmware would read them from flash.
        let p = PendulumParams::<f32>::default();
        Self {
            accel: Accel::new(AccelSettings::default()),
            pendulum: Pendulum::new(PendulumSettings {}),
            alg1: Alg1::new(Alg1Settings::from_params(p)),
            alg2: Alg2::new(Alg2Settings::from_params(p)),
            alg3: Alg3::new(Alg3Settings::from_params(p)),
            kf_alg2: TiltKalman::new(KalmanSettings::default()),
        }
    }

    fn reset(&mut self) {
        self.accel.reset();
        self.pendulum.reset();
        self.alg1.reset();
        self.alg2.reset();
        self.alg3.reset();
        self.kf_alg2.reset();
    }

    /// One sample through every estimator.
    fn step(&mut self, s: &Sample<f32>) {
        publish(0, self.accel.update(s));
        publish(1, self.pendulum.update(s));
        publish(2, self.alg1.update(s));
        let a2 = self.alg2.update(s);
        publish(3, a2);
        publish(4, self.alg3.update(s));
        // The Kalman filter uses Algorithm 2's angle unless it is flagged unusable.
        let z = if a2.flags.intersects(UNUSABLE) {
            f32::NAN
        } else {
            a2.theta
        };
        let r = KalmanSettings::<f32>::default().r_pendulum;
        publish(5, self.kf_alg2.step(s.t, s.gyro, &[(z, r)]));
    }
}

/// Busy-waits for the next tick (a real firmware sleeps until the sampling interrupt).
fn wait_for_tick(last: u32) -> u32 {
    loop {
        // SAFETY: as above.
        let now = unsafe { read_volatile(addr_of!(TICKS)) };
        if now != last {
            return now;
        }
    }
}

/// The entry point (the body of the reset handler).
#[no_mangle]
pub extern "C" fn _start() -> ! {
    let mut bank = Bank::new();
    let mut t0 = 0u32;
    let mut last = 0u32;
    loop {
        last = wait_for_tick(last);
        if last.wrapping_sub(t0) >= RESTART_AFTER_S * RATE_HZ {
            bank.reset();
            t0 = last;
        }
        let s = read_sensors(t0);
        // A flagged sample is the controller's to judge; the loop never stops on one.
        bank.step(&s);
    }
}

#[panic_handler]
fn panic(_: &PanicInfo) -> ! {
    // The estimators do not panic on any input (fuzzed); a panic here is a bug.
    loop {}
}

//! The firmware loop: one sensor sample in, every estimator updated, the estimates out,
//! at the sample rate, in `f32`, with no allocation and no standard library.
//!
//! On a real board `read_sensors` reads the encoder, gyro and accelerometer drivers and
//! `publish` hands the angle to the controller; here both are volatile accesses to
//! statics (standing in for memory-mapped registers) so that nothing is optimised away
//! and the binary's size is the size of the estimators. There is no runtime crate: the
//! entry point `_start` is the reset handler's body.
//!
//! Time: the estimators take the step `dt`, never an absolute time. A [`StepGate`] over the
//! free-running microsecond counter ([`Micros`], wrapping every 71 minutes) turns its
//! readings into `dt` exactly, so the loop runs for any length of time without a restart
//! (`tests/f32_vs_f64.rs` runs a 2-hour log in f32 against f64).
#![no_std]
#![no_main]

use core::panic::PanicInfo;
use core::ptr::{addr_of, addr_of_mut, read_volatile, write_volatile};

use pendtilt_core::kalman::tilt::UNUSABLE;
// The estimators, their settings, Sample, Estimate, StepGate, Micros (the last rung of the
// core's examples ladder: crates/pendtilt-core/examples).
use pendtilt_core::prelude::*;

/// Eq (22) window capacity in samples (if the window source is chosen): 32, not the
/// library's 256, to keep RAM small.
const W: usize = 32;

/// Stand-ins for the sensor registers: microsecond counter, encoder [rad], gyro [rad/s],
/// accelerometer [m/s^2]. A board support package would read its drivers instead.
static mut TICKS: u32 = 0;
static mut SENSORS: [f32; 4] = [0.0; 4];
/// Stand-in for the controller's input: one angle [rad] and its flags per estimator.
static mut OUT: [(f32, u16); 6] = [(0.0, 0); 6];

fn read_sensors(gate: &mut StepGate<Micros>) -> Sample<f32> {
    // SAFETY: single-threaded firmware; volatile reads of plain statics.
    let (ticks, s) = unsafe {
        (
            read_volatile(addr_of!(TICKS)),
            read_volatile(addr_of!(SENSORS)),
        )
    };
    Sample {
        // The step since the last sample, from the integer counter: no lost resolution.
        dt: gate.step(Micros(ticks)),
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
        publish(5, self.kf_alg2.step(s.dt, s.gyro, &[(z, r)]));
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
    let mut gate = StepGate::new();
    let mut last = 0u32;
    loop {
        last = wait_for_tick(last);
        let s = read_sensors(&mut gate);
        // A flagged sample is the controller's to judge; the loop never stops on one.
        bank.step(&s);
    }
}

#[panic_handler]
fn panic(_: &PanicInfo) -> ! {
    // The estimators do not panic on any input (fuzzed); a panic here is a bug.
    loop {}
}

//! The 3-D firmware loop: the spatial estimators (MODEL.md section 7) in `f32`, no
//! allocation, no standard library, one sample of the two encoders, the 3-axis gyro and
//! the 3-axis accelerometer in, roll and pitch out per estimator. As `src/main.rs`, the
//! sensors and the output are volatile statics standing in for registers, so the binary's
//! size is the size of the estimators (`size` in `.ci/run` reports it).
#![no_std]
#![no_main]

use core::panic::PanicInfo;
use core::ptr::{addr_of, addr_of_mut, read_volatile, write_volatile};

use pendtilt_core::spatial::accel::{Accel, AccelSettings};
use pendtilt_core::spatial::ekf::{Ekf, Settings};
use pendtilt_core::spatial::inv::{Inv3d, Inv3dSettings};
use pendtilt_core::spatial::pendulum::{Pendulum, PendulumSettings};
use pendtilt_core::spatial::{Attitude, SpatialSample};
use pendtilt_core::{Estimator, Micros, StepGate};

/// Eq (22) window capacity of inv3d's front ends (if the window source is chosen).
const W: usize = 32;

/// Stand-ins for the registers: microsecond counter; phi_x, phi_y [rad], gyro [rad/s],
/// accelerometer [m/s^2].
static mut TICKS: u32 = 0;
static mut SENSORS: [f32; 8] = [0.0; 8];
/// Stand-in for the controller's input: roll, pitch [rad] and flags per estimator.
static mut OUT: [(f32, f32, u16); 4] = [(0.0, 0.0, 0); 4];

fn read_sensors(gate: &mut StepGate<Micros>) -> SpatialSample<f32> {
    // SAFETY: single-threaded firmware; volatile reads of plain statics.
    let (ticks, s) = unsafe {
        (
            read_volatile(addr_of!(TICKS)),
            read_volatile(addr_of!(SENSORS)),
        )
    };
    SpatialSample::new(
        gate.step(Micros(ticks)),
        [s[0], s[1]],
        [s[2], s[3], s[4]],
        [s[5], s[6], s[7]],
    )
}

fn publish(i: usize, a: Attitude<f32>) {
    // SAFETY: as above; `i` < 4 by construction.
    unsafe {
        let out = &mut *addr_of_mut!(OUT);
        write_volatile(&mut out[i], (a.roll, a.pitch, a.flags.bits()));
    }
}

/// The spatial bank, all in `f32`, on the stack.
struct Bank {
    pendulum: Pendulum<f32>,
    accel: Accel<f32>,
    inv: Inv3d<f32, W>,
    ekf: Ekf<f32>,
}

impl Bank {
    fn new() -> Self {
        // The rig's parameters (MODEL.md 7.6's defaults); a firmware would read them from
        // flash.
        Self {
            pendulum: Pendulum::new(PendulumSettings {}),
            accel: Accel::new(AccelSettings::default()),
            inv: Inv3d::new(Inv3dSettings::default()),
            ekf: Ekf::new(Settings::default()),
        }
    }

    fn step(&mut self, s: &SpatialSample<f32>) {
        publish(0, self.pendulum.update(s));
        publish(1, self.accel.update(s));
        publish(2, self.inv.update(s));
        publish(3, self.ekf.update(s));
    }
}

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
        bank.step(&s);
    }
}

#[panic_handler]
fn panic(_: &PanicInfo) -> ! {
    loop {}
}

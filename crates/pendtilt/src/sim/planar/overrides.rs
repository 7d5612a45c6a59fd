//! The command line's changes to a planar scenario (`pendtilt simulate`'s options), as
//! values: the pendulum, the timing, the motion, the vibration and the sensors, applied in
//! that order, `--set` after the named options and the switches that clear noise or
//! vibration last.
use anyhow::bail;

use super::Scenario;

/// The changes to a scenario, each field its option of `pendtilt simulate` (None or false:
/// the scenario's own).
#[derive(Debug, Clone, Default)]
pub struct Overrides {
    /// Pendulum mass m_p (kg).
    pub mass: Option<f64>,
    /// Pivot-to-CG distance l_p (m).
    pub length: Option<f64>,
    /// Inertia about the pivot I_p (kg m^2).
    pub inertia: Option<f64>,
    /// Pivot friction C (N m s/rad).
    pub damping: Option<f64>,
    /// Distance l12 from P1 to P2 (m).
    pub pivot_offset: Option<f64>,
    /// Duration (s).
    pub duration: Option<f64>,
    /// Sample rate (Hz).
    pub rate: Option<f64>,
    /// RK4 steps per sample.
    pub substeps: Option<u32>,
    /// Size of the body motion (rad).
    pub amplitude: Option<f64>,
    /// Frequency of the `sine` motion (Hz).
    pub frequency: Option<f64>,
    /// Engine fundamental (Hz).
    pub engine_hz: Option<f64>,
    /// Factor on every vibration amplitude.
    pub vibration_scale: Option<f64>,
    /// Accelerometer position relative to P2 in body axes (m): two values.
    pub accel_mount: Option<Vec<f64>>,
    /// Encoder resolution (bits per turn).
    pub encoder_bits: Option<u32>,
    /// Scenario keys set in TOML syntax, `KEY=VALUE`, in order.
    pub set: Vec<String>,
    /// No random sensor error.
    pub no_noise: bool,
    /// Ideal sensors.
    pub ideal_sensors: bool,
    /// No floor vibration.
    pub no_vibration: bool,
}

impl Overrides {
    /// Applies every change to `s`, in the order the module docs give; an option that does
    /// not fit the scenario is refused naming it.
    pub fn apply(&self, s: &mut Scenario) -> anyhow::Result<()> {
        apply_rig_and_timing(s, self);
        apply_motion_and_vibration(s, self)?;
        apply_sensors(s, self)
    }
}

/// The pendulum's and the timing's overrides.
fn apply_rig_and_timing(s: &mut Scenario, o: &Overrides) {
    let p = &mut s.pendulum;
    for (flag, v) in [
        (&mut p.mass, o.mass),
        (&mut p.length, o.length),
        (&mut p.inertia, o.inertia),
        (&mut p.damping, o.damping),
        (&mut p.pivot_offset, o.pivot_offset),
    ] {
        if let Some(v) = v {
            *flag = v;
        }
    }
    if let Some(d) = o.duration {
        s.duration = d;
    }
    if let Some(r) = o.rate {
        s.rate = r;
    }
    if let Some(n) = o.substeps {
        s.substeps = n;
    }
}

/// The motion's and the vibration's overrides.
fn apply_motion_and_vibration(s: &mut Scenario, o: &Overrides) -> anyhow::Result<()> {
    if let Some(a) = o.amplitude {
        s.motion.set_amplitude(a);
    }
    if let Some(f) = o.frequency {
        match &mut s.motion {
            super::motion::Motion::Sine(m) => m.frequency = f,
            m => bail!(
                "--frequency applies to the sine motion, this scenario's motion is '{}' \
                 (use --set motion.KEY=VALUE)",
                m.kind()
            ),
        }
    }
    if let Some(hz) = o.engine_hz {
        if s.vibration.harmonics.is_empty() {
            bail!("--engine-hz: this scenario has no vibration harmonics");
        }
        s.vibration.set_engine_frequency(hz);
    }
    if let Some(k) = o.vibration_scale {
        if !(k.is_finite() && k >= 0.0) {
            bail!("--vibration-scale: must be >= 0, got {k}");
        }
        s.vibration.scale(k);
    }
    Ok(())
}

/// The sensors' overrides, `--set`, then the switches that clear noise or vibration.
fn apply_sensors(s: &mut Scenario, o: &Overrides) -> anyhow::Result<()> {
    if let Some(m) = &o.accel_mount {
        let &[x, y] = m.as_slice() else {
            bail!("--accel-mount: give X,Y in metres, e.g. 0.02,-0.1 (got {m:?})");
        };
        s.sensors.accel.mount = [x, y];
    }
    if let Some(b) = o.encoder_bits {
        s.sensors.encoder.bits = b;
    }
    for a in &o.set {
        s.set(a)?;
    }
    if o.no_noise {
        s.sensors = std::mem::take(&mut s.sensors).without_noise();
    }
    if o.ideal_sensors {
        s.sensors = std::mem::take(&mut s.sensors).ideal();
    }
    if o.no_vibration {
        s.vibration = Default::default();
    }
    Ok(())
}

//! How each `[ekf3d]` value was found, in words (the [`Note`]s of [`super::Tuned3d`]),
//! and the values set from the measurements.
use super::forcing::Forcing3d;
use super::noise::Noise3d;
use super::speed::Jerk;
use crate::tune::Note;
use pendtilt_core::spatial::ekf::Settings;

fn push(notes: &mut Vec<Note>, key: &str, value: String, kept: bool, how: String) {
    notes.push(Note {
        key: format!("ekf3d.{key}"),
        value,
        kept_default: kept,
        how,
        fell_back: false,
    });
}

/// A value the log gave that no filter can use (a noise of 0): the start's is kept and
/// `pendtilt tune` warns.
fn fallback(notes: &mut Vec<Note>, key: &str, kept: String, why: String) {
    notes.push(Note {
        key: format!("ekf3d.{key}"),
        value: kept,
        kept_default: true,
        how: format!(
            "{why}, which would make the filter trust this sensor without bound: kept \
            the start's value"
        ),
        fell_back: true,
    });
}

const AXES: [&str; 3] = ["x", "y", "z"];

/// The sensors' figures into `s` from `n`, a note each.
pub(super) fn sensors(s: &mut Settings<f64>, n: &Noise3d, notes: &mut Vec<Note>) {
    encoder(s, n, notes);
    gyro(s, n, notes);
    match &n.accel {
        Ok(a) if a.density > 0.0 && a.density.is_finite() => {
            s.sensors.accel_density = a.density;
            push(
                notes,
                "accel_density",
                format!("{:.3e} m/s^2/sqrt(Hz)", a.density),
                false,
                format!(
                    "median of the ax and ay spectra over 0.3-0.45 of the rate; the \
                    vibration above {:.1} Hz reads {:.3} m/s^2 RMS (with vibration reaching that \
                    band it is an upper bound; ekf3d reads it only with use_accel)",
                    a.pendulum_band, a.vibration_rms
                ),
            );
        }
        Ok(a) => fallback(
            notes,
            "accel_density",
            format!("{:.3e}", s.sensors.accel_density),
            format!(
                "the accelerometer's top band gave a density of {:.3e}",
                a.density
            ),
        ),
        Err(why) => push(
            notes,
            "accel_density",
            format!("{:.3e}", s.sensors.accel_density),
            true,
            format!("{why}: kept the start's"),
        ),
    }
    match &n.speed {
        Some(Ok(v)) if *v > 0.0 => {
            s.speed.noise = *v;
            push(
                notes,
                "speed_noise",
                format!("{v:.4} m/s"),
                false,
                "second differences of the speed column (a vehicle's speed is smooth at the \
                    sample rate: they are its white noise)"
                    .into(),
            );
        }
        Some(Ok(_)) => fallback(
            notes,
            "speed_noise",
            format!("{:.4}", s.speed.noise),
            "the speed column never changed between rows".into(),
        ),
        Some(Err(why)) => push(
            notes,
            "speed_noise",
            format!("{:.4} m/s", s.speed.noise),
            true,
            format!("{why}: kept the start's"),
        ),
        None => {}
    }
}

fn encoder(s: &mut Settings<f64>, n: &Noise3d, notes: &mut Vec<Note>) {
    let ok: Vec<_> = n.encoder.iter().filter_map(|e| e.as_ref().ok()).collect();
    if ok.is_empty() || ok.iter().all(|e| e.white == 0.0 && e.step.is_none()) {
        let why = n
            .encoder
            .iter()
            .find_map(|e| e.as_ref().err())
            .cloned()
            .unwrap_or_else(|| {
                "the encoders never changed: a still pendulum within one step \
                shows neither the step nor the noise"
                    .into()
            });
        push(
            notes,
            "encoder_noise",
            format!(
                "{:.3e} rad, {} bits",
                s.sensors.encoder_noise, s.sensors.encoder_bits
            ),
            true,
            format!("{why}: kept the start's"),
        );
        return;
    }
    let bits: Vec<u32> = ok.iter().filter_map(|e| e.bits).collect();
    // Both axes quantised alike, or the finer one's rounding (the coarser's goes to the
    // noise).
    let b = bits.iter().copied().max();
    s.sensors.encoder_bits = b.unwrap_or(0);
    let var: f64 = ok
        .iter()
        .map(|e| {
            if e.bits.is_some() && e.bits == b {
                e.noise * e.noise
            } else {
                e.white * e.white
            }
        })
        .sum::<f64>()
        / ok.len() as f64;
    s.sensors.encoder_noise = var.sqrt();
    let steps: Vec<String> = n
        .encoder
        .iter()
        .zip(["phi_x", "phi_y"])
        .map(|(e, name)| match e {
            Ok(e) => format!(
                "{name}: {} bits, residual {:.3e} rad over {} samples",
                e.bits
                    .map_or("no power-of-two step".into(), |b| b.to_string()),
                e.white,
                e.samples
            ),
            Err(w) => format!("{name}: {w}"),
        })
        .collect();
    push(
        notes,
        "encoder_bits",
        s.sensors.encoder_bits.to_string(),
        false,
        format!("gaps between the distinct readings ({})", steps.join("; ")),
    );
    push(
        notes,
        "encoder_noise",
        format!("{:.3e} rad", s.sensors.encoder_noise),
        false,
        "second differences of phi_x and phi_y, less the rounding's q^2/12, root mean square of \
            the two"
            .into(),
    );
}

fn gyro(s: &mut Settings<f64>, n: &Noise3d, notes: &mut Vec<Note>) {
    let ok: Vec<_> = n
        .gyro
        .iter()
        .filter_map(|g| g.as_ref().ok())
        .filter(|g| g.density > 0.0 && g.density.is_finite())
        .collect();
    if ok.is_empty() {
        let why = n
            .gyro
            .iter()
            .find_map(|g| g.as_ref().err())
            .cloned()
            .unwrap_or_else(|| "the gyro read the same value throughout".into());
        push(
            notes,
            "gyro_density",
            format!("{:.3e} rad/s/sqrt(Hz)", s.sensors.gyro_density),
            true,
            format!("{why}: kept the start's"),
        );
        return;
    }
    let d = (ok.iter().map(|g| g.density * g.density).sum::<f64>() / ok.len() as f64).sqrt();
    s.sensors.gyro_density = d;
    let how: Vec<String> = n
        .gyro
        .iter()
        .zip(AXES)
        .map(|(g, a)| match g {
            Ok(g) => format!("{a}: {:.3e} ({})", g.density, g.method),
            Err(w) => format!("{a}: {w}"),
        })
        .collect();
    push(
        notes,
        "gyro_density",
        format!("{d:.3e} rad/s/sqrt(Hz)"),
        false,
        format!("root mean square of the three axes: {}", how.join("; ")),
    );
    let biases: Vec<f64> = n
        .gyro
        .iter()
        .filter_map(|g| g.as_ref().ok()?.bias)
        .collect();
    match biases.iter().map(|b| b.abs()).reduce(f64::max) {
        Some(b) => {
            // The filter starts its bias at 0 with this spread: it must cover the bias
            // seen (twice it), never narrower than the start's.
            let spread = (2.0 * b).max(s.sensors.gyro_bias);
            s.sensors.gyro_bias = spread;
            push(
                notes,
                "gyro_bias",
                format!("{spread:.3e} rad/s"),
                spread > 2.0 * b,
                format!(
                    "the largest bias seen on an axis, {b:.3e} rad/s (x and y: still \
                    stretches, else the gyro's integral against the encoder; z: still stretches \
                    only), twice it, never below the start's"
                ),
            );
        }
        None => push(
            notes,
            "gyro_bias",
            format!("{:.3e} rad/s", s.sensors.gyro_bias),
            true,
            "no axis' bias could be told (no still stretch, no encoder drift): kept the start's"
                .into(),
        ),
    }
}

/// The encoders' jitter into `s`.
pub(super) fn jitter(s: &mut Settings<f64>, j: &Result<f64, String>, notes: &mut Vec<Note>) {
    match j {
        Ok(v) => {
            s.encoder_jitter = *v;
            push(
                notes,
                "encoder_jitter",
                format!("{v:.3e} rad ({:.4} deg)", v.to_degrees()),
                false,
                "the encoders' power from 5 times each axis' natural frequency to 0.3 of the \
                    rate, less their white floor; root mean square of phi_x's and phi_y's"
                    .into(),
            );
        }
        Err(why) => push(
            notes,
            "encoder_jitter",
            format!("{:.3e} rad", s.encoder_jitter),
            true,
            format!("{why}: kept the start's"),
        ),
    }
}

/// The jitter's scale: the note of the jitter (the last one) says what it became.
pub(super) fn jitter_scale(v: f64, js: &crate::tune::forcing::JitterScale, notes: &mut [Note]) {
    if let Some(n) = notes
        .iter_mut()
        .rev()
        .find(|n| n.key == "ekf3d.encoder_jitter")
    {
        let tried: Vec<String> = js
            .tried
            .iter()
            .map(|(m, e)| format!("x{m:.3}: {:.4} deg", e.to_degrees()))
            .collect();
        n.value = format!("{v:.3e} rad ({:.4} deg)", v.to_degrees());
        n.how = format!(
            "{}; then x{:.3} (cap x{:.2}): ekf3d's error against the gyro's up direction in {} s \
                windows, per doubling kept while it falls by more than 5 %: {}",
            n.how,
            js.scale,
            js.cap,
            super::reference::WINDOW_SECONDS,
            tried.join(", ")
        );
    }
}

/// The vibration density into `s`.
pub(super) fn forcing(s: &mut Settings<f64>, f: &Result<Forcing3d, String>, notes: &mut Vec<Note>) {
    match f {
        Ok(f) if f.density > 0.0 && f.density.is_finite() => {
            s.environment.vibration_density = f.density;
            push(
                notes,
                "vibration_density",
                format!("{:.4} m/s^2/sqrt(Hz)", f.density),
                false,
                format!(
                    "the accelerometer less what ekf3d predicts of it (gravity on its up \
                    direction, O's acceleration, the lever arm from O): its density within a \
                    third of an octave of each joint's natural frequency x {:.4}, y {:.4}, and \
                    in {}-{} Hz (the body's slow motion) x {:.4}, y {:.4}; the largest (the \
                    sensor's noise and the filter's error are in it: an upper bound)",
                    f.near[0],
                    f.near[1],
                    super::forcing::MOTION_BAND[0],
                    super::forcing::MOTION_BAND[1],
                    f.motion[0],
                    f.motion[1]
                ),
            );
            if let Some(n) = notes
                .iter_mut()
                .rev()
                .find(|n| n.key == "ekf3d.vibration_density")
            {
                if f.rounds > 1 {
                    n.how += &format!(
                        "; ekf3d re-run at each density found, {} runs until it \
                        moved by less than 10 %",
                        f.rounds
                    );
                }
                if let Some(why) = &f.motion_short {
                    n.how += &format!(
                        "; DOUBT: the motion band not measured ({why}): the \
                        density near the natural frequencies alone, which on a ship or a car can \
                        be ten times too low"
                    );
                }
            }
        }
        Ok(_) => fallback(
            notes,
            "vibration_density",
            format!("{:.4}", s.environment.vibration_density),
            "the accelerometer's residual near the natural frequencies was 0".into(),
        ),
        Err(why) => push(
            notes,
            "vibration_density",
            format!("{:.4} m/s^2/sqrt(Hz)", s.environment.vibration_density),
            true,
            format!("{why}: kept the start's"),
        ),
    }
}

/// The values the log does not tell: kept, each a doubt.
pub(super) fn kept(s: &Settings<f64>, n: &Noise3d, notes: &mut Vec<Note>) {
    push(
        notes,
        "gyro_bias_walk",
        format!("{:.3e} rad/s/sqrt(s)", s.sensors.gyro_bias_walk),
        true,
        "DOUBT: a bias walk shows only over minutes of rest, which a ride does not give: kept \
            the start's"
            .into(),
    );
    if n.speed.is_none() {
        push(
            notes,
            "speed_noise",
            format!("{:.4} m/s", s.speed.noise),
            true,
            "the log has no speed column: not used, kept the start's".into(),
        );
    }
}

/// The jerk density into `s` from the speed's likelihood, a note (nothing without a
/// speed column).
pub(super) fn jerk(s: &mut Settings<f64>, j: &Option<Result<Jerk, String>>, notes: &mut Vec<Note>) {
    match j {
        None => {}
        Some(Ok(j)) => {
            s.speed.jerk_density = j.density;
            let bound = if j.at_bound {
                "; DOUBT: at the end of the search's range, which the log does not bound (a \
                 vehicle at a steady speed has no jerk to find)"
            } else {
                ""
            };
            push(
                notes,
                "jerk_density",
                format!("{:.4} m/s^3/sqrt(Hz)", j.density),
                false,
                format!(
                    "the most likely for the {} speed readings under ekf3d's speed model \
                     (white jerk, the measured speed noise); its normalised innovations' RMS \
                     {:.2}, 1 for a model that fits{bound}",
                    j.readings, j.normalised_rms
                ),
            );
        }
        Some(Err(why)) => push(
            notes,
            "jerk_density",
            format!("{:.3} m/s^3/sqrt(Hz)", s.speed.jerk_density),
            true,
            format!("DOUBT: {why}: kept the start's"),
        ),
    }
}

/// The adaptation's start and bounds ([`super::adaptation`]), a note each.
pub(super) fn adaptation(s: &Settings<f64>, standing: bool, notes: &mut Vec<Note>) {
    let a = &s.adaptation;
    let d = s.environment.vibration_density;
    push(
        notes,
        "adapt",
        a.enabled.to_string(),
        false,
        format!(
            "the forcing adapts online from the vibration density above ({d:.3e} \
             m/s^2/sqrt(Hz)), for motion this log did not show (a hand-held stretch, a \
             tumble); on the simulated vehicles, with its floor at the tuned density, it \
             changed one ride of 18 by more than 1 %; on the standing ones its lower floor \
             (below) took their error down"
        ),
    );
    push(
        notes,
        "adapt_min_factor",
        format!("{}", a.min_factor),
        false,
        if standing {
            "the speed never changed, so nothing but vibration forces the pendulum: the \
             innovations may bring the density down to a tenth of its variance (the tuned \
             density is an upper bound, holding the filter's own error)"
                .into()
        } else {
            "the floor is the tuned density itself: on a moving vehicle (or one without a \
             speed column) the unpredicted accelerations are real, and a lower floor cost \
             the simulated ships up to 1.6x"
                .into()
        },
    );
    push(
        notes,
        "adapt_max_factor",
        format!("{:.4e}", a.max_factor),
        false,
        format!(
            "up to {:.2} m/s^2/sqrt(Hz), ekf3d's default ceiling whatever the tuned density: \
             beyond any body the pendulum still follows",
            d * a.max_factor.sqrt()
        ),
    );
}

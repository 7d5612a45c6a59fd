//! Streaming estimators: one sample in, every chosen estimator's estimate out.
//!
//! [`Stream`] is the planar bank ([`pendtilt::bank::planar::Bank`]) that `pendtilt estimate` and
//! `pendtilt stream` run, built from a rig file as they build it; [`Stream3d`] the 3-D
//! bank ([`pendtilt::bank::spatial::Bank3d`]) with `estimate`'s 3-D setup. The time steps come
//! from the time stamps through the readers' [`StepGate`]. What the log readers add
//! around the bank (plausibility bounds, clips found ahead in the log, the unit checks,
//! the warnings) is not done here: samples go to the bank as given.
use std::path::PathBuf;

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray2, PyReadonlyArray1};
use pendtilt::bank::planar::Bank;
use pendtilt::bank::spatial::Bank3d;
use pendtilt::cli::options::{rig_bank_settings, LogColumns};
use pendtilt::config::RigConfig;
use pendtilt::io::ColumnMap;
use pendtilt::pipeline::spatial::{self, Options3d};
use pendtilt::sensors::{Inputs, SENSORS};
use pendtilt_core::spatial::SpatialSample;
use pendtilt_core::{Estimate, Sample, StepGate};
use pyo3::prelude::*;

use crate::{py_err, PendtiltError};

/// The sensors named in `sensors` (`phi`, `gyro`, `accel`: the table's names).
fn inputs_of(sensors: &[String]) -> PyResult<Inputs> {
    let mut i = Inputs::NONE;
    for s in sensors {
        let Some(spec) = SENSORS.iter().find(|spec| spec.name == s.as_str()) else {
            let known: Vec<_> = SENSORS.iter().map(|spec| spec.name).collect();
            return Err(PendtiltError::new_err(format!(
                "unknown sensor `{s}` (known: {})",
                known.join(", ")
            )));
        };
        i = i.with(spec.sensor);
    }
    Ok(i)
}

/// The planar estimator bank, one sample at a time.
#[pyclass(unsendable, module = "pendtilt._pendtilt")]
pub struct Stream {
    bank: Bank,
    gate: StepGate<f64>,
    est: Vec<Estimate<f64>>,
}

#[pymethods]
impl Stream {
    /// The bank for the rig file `rig` (default: MODEL.md's rig), the estimators
    /// `estimators` (default: every one the `sensors` feed) and the `sensors` present.
    #[new]
    #[pyo3(signature = (rig=None, estimators=None, sensors=vec!["phi".to_string(), "gyro".to_string(), "accel".to_string()]))]
    fn new(
        rig: Option<PathBuf>,
        estimators: Option<Vec<String>>,
        sensors: Vec<String>,
    ) -> PyResult<Self> {
        let rig = match rig {
            Some(p) => RigConfig::load(&p).map_err(|e| PendtiltError::new_err(e.to_string()))?,
            None => RigConfig::default(),
        };
        let bank = Bank::new(
            &rig_bank_settings(&rig),
            inputs_of(&sensors)?,
            estimators.as_deref(),
        )
        .map_err(PendtiltError::new_err)?;
        if bank.names().is_empty() {
            return Err(PendtiltError::new_err(
                "no estimator can run on these sensors",
            ));
        }
        Ok(Self {
            est: Vec::with_capacity(bank.names().len()),
            bank,
            gate: StepGate::new(),
        })
    }

    /// The estimators, in output order.
    #[getter]
    fn names(&self) -> Vec<&'static str> {
        self.bank.names().to_vec()
    }

    /// One sample at time `t` \[s\] (rad, rad/s, m/s^2; NaN: missing): each estimator's
    /// tilt \[rad\] (NaN while it has none), in [`Stream::names`] order.
    #[pyo3(signature = (t, phi=f64::NAN, gyro=f64::NAN, ax=f64::NAN, ay=f64::NAN))]
    fn update(&mut self, t: f64, phi: f64, gyro: f64, ax: f64, ay: f64) -> Vec<f64> {
        self.step(t, phi, gyro, ax, ay);
        self.est.iter().map(|e| e.theta).collect()
    }

    /// The flags of the last update, per estimator (bits; see `pendtilt.flag_names`).
    fn flags(&self) -> Vec<u16> {
        self.est.iter().map(|e| e.flags.bits()).collect()
    }

    /// Many samples (arrays of one length): the tilts \[rad\] and flags, one row per
    /// sample, one column per estimator.
    #[allow(clippy::type_complexity)] // two arrays
    fn update_many<'py>(
        &mut self,
        py: Python<'py>,
        t: PyReadonlyArray1<'py, f64>,
        phi: PyReadonlyArray1<'py, f64>,
        gyro: PyReadonlyArray1<'py, f64>,
        ax: PyReadonlyArray1<'py, f64>,
        ay: PyReadonlyArray1<'py, f64>,
    ) -> PyResult<(Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<u16>>)> {
        let cols = [&t, &phi, &gyro, &ax, &ay].map(|c| c.as_array());
        let n = cols[0].len();
        if cols.iter().any(|c| c.len() != n) {
            return Err(PendtiltError::new_err("the arrays differ in length"));
        }
        let w = self.bank.names().len();
        let mut theta = Array2::<f64>::zeros((n, w));
        let mut flags = Array2::<u16>::zeros((n, w));
        for k in 0..n {
            self.step(cols[0][k], cols[1][k], cols[2][k], cols[3][k], cols[4][k]);
            for (j, e) in self.est.iter().enumerate() {
                theta[[k, j]] = e.theta;
                flags[[k, j]] = e.flags.bits();
            }
        }
        Ok((theta.into_pyarray(py), flags.into_pyarray(py)))
    }

    /// Every estimator back to its start (the next sample is the first).
    fn reset(&mut self) {
        self.bank.reset();
        self.gate = StepGate::new();
    }
}

impl Stream {
    fn step(&mut self, t: f64, phi: f64, gyro: f64, ax: f64, ay: f64) {
        let sample = Sample {
            dt: self.gate.step(t),
            phi,
            gyro,
            ax,
            ay,
        };
        self.bank.update(&sample, &mut self.est);
    }
}

/// The 3-D estimator bank, one sample at a time.
#[pyclass(unsendable, module = "pendtilt._pendtilt")]
pub struct Stream3d {
    bank: Bank3d,
    gate: StepGate<f64>,
}

#[pymethods]
impl Stream3d {
    /// The 3-D bank as `pendtilt estimate` sets it up: the rig file `rig` (`[pendulum3d]`,
    /// `[mounting]`, `[ekf3d]`, `[gyro]`), else the `scenario` file's rig, else MODEL.md
    /// 7.6's; the scenario's sensor noise figures for ekf3d/ukf3d; `estimators` (default:
    /// every 3-D estimator).
    #[new]
    #[pyo3(signature = (rig=None, scenario=None, estimators=None))]
    fn new(
        rig: Option<PathBuf>,
        scenario: Option<PathBuf>,
        estimators: Option<Vec<String>>,
    ) -> PyResult<Self> {
        let columns = LogColumns {
            map: ColumnMap::new(),
            deg: None,
            time_unit: None,
            accel_unit: None,
            negate: None,
        };
        let no_log = PathBuf::new();
        let opts = Options3d {
            log: &no_log,
            log_name: None,
            params: rig.as_deref(),
            scenario: scenario.as_deref(),
            score_from: None,
            columns: &columns,
            only: estimators.as_deref(),
            quiet: true,
        };
        let setup = spatial::setup(&opts).map_err(py_err)?;
        let bank =
            Bank3d::new(&setup.settings, estimators.as_deref()).map_err(PendtiltError::new_err)?;
        Ok(Self {
            bank,
            gate: StepGate::new(),
        })
    }

    /// The estimators, in output order.
    #[getter]
    fn names(&self) -> Vec<&'static str> {
        self.bank.names()
    }

    /// One sample at time `t` \[s\]: encoder angles \[rad\], body rates \[rad/s\], specific
    /// force \[m/s^2\] (FLU), the vehicle's speed \[m/s\] (NaN: unknown). Each estimator's
    /// (roll, pitch) \[rad\].
    #[pyo3(signature = (t, phi_x, phi_y, gyro_x, gyro_y, gyro_z, ax, ay, az, speed=f64::NAN))]
    #[allow(clippy::too_many_arguments)] // the columns of a 3-D log
    fn update(
        &mut self,
        t: f64,
        phi_x: f64,
        phi_y: f64,
        gyro_x: f64,
        gyro_y: f64,
        gyro_z: f64,
        ax: f64,
        ay: f64,
        az: f64,
        speed: f64,
    ) -> Vec<(f64, f64)> {
        let s = SpatialSample {
            speed,
            ..SpatialSample::new(
                self.gate.step(t),
                [phi_x, phi_y],
                [gyro_x, gyro_y, gyro_z],
                [ax, ay, az],
            )
        };
        self.bank
            .update(&s)
            .iter()
            .map(|a| (a.roll, a.pitch))
            .collect()
    }

    /// The flags of the last update, per estimator (bits; see `pendtilt.flag_names`).
    fn flags(&self) -> Vec<u16> {
        self.bank.outputs().iter().map(|a| a.flags.bits()).collect()
    }

    /// The attitude quaternion (w, x, y, z; world <- body) of estimator `i` after the
    /// last update, for those that have one (ekf3d, ukf3d).
    fn quaternion(&self, i: usize) -> Option<[f64; 4]> {
        self.bank.quaternion(i)
    }
}

/// The names of the flags set in `bits`, as the estimates CSV writes them
/// (`asin_clamped|initialising`; empty when none).
#[pyfunction]
pub fn flag_names(bits: u16) -> String {
    pendtilt_core::Flags::from_bits_truncate(bits)
        .names()
        .to_string()
}

//! The native module of the `pendtilt` Python package (`pendtilt._pendtilt`).
//!
//! Every function here calls the pendtilt library through the code the `pendtilt` command
//! runs: the command line is parsed by the command's own definitions
//! ([`pendtilt::cli::Cli`]), so options, defaults and error messages are the command's;
//! `simulate`, `replay`, `fit` and `tune` run the command itself ([`run_cli`]); `estimate`
//! runs the command's pipeline ([`pendtilt::pipeline::run_parallel`] for a planar log,
//! [`pendtilt::pipeline::spatial::pass_on`] for a 3-D one) into NumPy arrays instead of a CSV
//! file ([`estimate`]). The Python layer (`pendtilt/__init__.py`) turns keyword arguments
//! into that command line. Long runs release the GIL.
use pyo3::create_exception;
use pyo3::prelude::*;

mod estimate;
mod rig;
mod source;
mod stream;
mod table;

create_exception!(
    _pendtilt,
    PendtiltError,
    pyo3::exceptions::PyValueError,
    "An error of pendtilt: the message is the one the `pendtilt` command prints after `error: `."
);

/// An error of the library as the command prints it (`{e:#}`: the message and its causes).
pub(crate) fn py_err(e: anyhow::Error) -> PyErr {
    PendtiltError::new_err(format!("{e:#}"))
}

/// Parses `argv` (`argv[0]` the program name) with the command's definitions; a parse
/// error is a [`PendtiltError`] with clap's message (usage included).
pub(crate) fn parse(argv: &[String]) -> PyResult<pendtilt::cli::Cli> {
    use clap::Parser;
    pendtilt::cli::Cli::try_parse_from(argv)
        .map_err(|e| PendtiltError::new_err(e.render().to_string().trim_end().to_string()))
}

/// Runs one `pendtilt` command line (`argv[0]` is the program name), without the GIL.
/// Its notices and tables go to the process's standard error and output, as the
/// command's do; an error is a [`PendtiltError`] with the command's message.
#[pyfunction]
fn run_cli(py: Python<'_>, argv: Vec<String>) -> PyResult<()> {
    let cli = parse(&argv)?;
    py.detach(|| pendtilt::cli::run(cli)).map_err(py_err)
}

/// The estimator catalogue: (name, model "planar" or "3d", family, sensors read, about).
#[pyfunction]
fn catalogue() -> Vec<(String, String, String, Vec<String>, String)> {
    use pendtilt::catalogue::{Model, CATALOGUE};
    CATALOGUE
        .iter()
        .map(|l| {
            (
                l.name.to_string(),
                match l.model {
                    Model::Planar => "planar",
                    Model::Spatial => "3d",
                }
                .to_string(),
                format!("{:?}", l.family),
                l.reads.names().iter().map(|s| s.to_string()).collect(),
                l.about.to_string(),
            )
        })
        .collect()
}

/// The version of the pendtilt library this module was built from.
#[pyfunction]
fn version() -> &'static str {
    pendtilt::cli::VERSION
}

#[pymodule]
fn _pendtilt(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("PendtiltError", m.py().get_type::<PendtiltError>())?;
    m.add_function(wrap_pyfunction!(run_cli, m)?)?;
    m.add_function(wrap_pyfunction!(catalogue, m)?)?;
    m.add_function(wrap_pyfunction!(version, m)?)?;
    m.add_function(wrap_pyfunction!(estimate::estimate, m)?)?;
    m.add_function(wrap_pyfunction!(estimate::write_csv, m)?)?;
    m.add_function(wrap_pyfunction!(table::read_csv, m)?)?;
    m.add_function(wrap_pyfunction!(rig::rig_check, m)?)?;
    m.add_function(wrap_pyfunction!(rig::rig_default, m)?)?;
    m.add_function(wrap_pyfunction!(stream::flag_names, m)?)?;
    m.add_class::<stream::Stream>()?;
    m.add_class::<stream::Stream3d>()?;
    Ok(())
}

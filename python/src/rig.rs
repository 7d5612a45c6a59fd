//! Rig files: checked and written as the command reads and writes them.
use pendtilt::bank::spatial::rig::Rig3dConfig;
use pendtilt::config::RigConfig;
use pyo3::prelude::*;

use crate::PendtiltError;

/// Checks rig file text (`origin` names it in errors) as the command reads it: a 3-D
/// rig (with a `[pendulum3d]` table) by [`Rig3dConfig::from_toml_str`], else a planar one
/// by [`RigConfig::from_toml_str`]. Returns `("planar", text as the command writes it,
/// doubts)` or `("3d", None, [])`; an error has the command's message.
#[pyfunction]
pub fn rig_check(text: &str, origin: &str) -> PyResult<(String, Option<String>, Vec<String>)> {
    let table: Result<toml::Table, _> = toml::from_str(text);
    if table.is_ok_and(|t| t.contains_key("pendulum3d")) {
        Rig3dConfig::from_toml_str(text, origin).map_err(PendtiltError::new_err)?;
        return Ok(("3d".into(), None, Vec::new()));
    }
    let rig = RigConfig::from_toml_str(text, origin)
        .map_err(|e| PendtiltError::new_err(e.to_string()))?;
    Ok(("planar".into(), Some(rig.to_toml_string()), rig.doubts()))
}

/// The default rig as the command writes it: planar (MODEL.md section 5), or 3-D
/// (MODEL.md 7.6, `pendtilt rig --template 3d`: every key at its default).
#[pyfunction]
#[pyo3(signature = (kind="planar"))]
pub fn rig_default(kind: &str) -> PyResult<String> {
    match kind {
        "planar" => Ok(RigConfig::default().to_toml_string()),
        "3d" => Ok(pendtilt::bank::spatial::rig::template()),
        other => Err(PendtiltError::new_err(format!(
            "unknown rig kind `{other}` (known: planar, 3d)"
        ))),
    }
}

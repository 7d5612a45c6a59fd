//! Writing a run: the CSV log of MODEL.md section 5, streamed row by row, and the log, rig
//! and scenario files of a run written together.

use std::io::{self, Write};
use std::path::{Path, PathBuf};

use anyhow::Context;

use crate::io::output::{self as safe, NamedPath, OutputFile};

use super::{SimRow, Simulator};

/// The log's header row.
pub const LOG_HEADER: &str = "t,phi,gyro,ax,ay,theta";

/// Writes one number: the shortest text that reads back to the same f64 (Ryu), with an
/// exponent for very small or large magnitudes (so noise of 1e-17 does not become a
/// 20-digit decimal). Ryu is several times faster than `Display`, and formatting is most of
/// the cost of a long run.
#[inline]
fn write_num<W: Write>(w: &mut W, x: f64) -> io::Result<()> {
    let mut buf = ryu::Buffer::new();
    w.write_all(buf.format(x).as_bytes())
}

/// Writes one CSV row (no header) for `row`.
pub fn write_row<W: Write>(w: &mut W, row: &SimRow) -> io::Result<()> {
    write_num(w, row.t)?;
    for x in [row.phi, row.gyro, row.ax, row.ay, row.theta] {
        w.write_all(b",")?;
        write_num(w, x)?;
    }
    w.write_all(b"\n")
}

/// Refuses a row whose simulated angle `name` = `x` \[rad\] is not finite or beyond
/// [`pendtilt_core::model::PHI_LIMIT`]: settings no integrator step can follow
/// (`vibration.broadband.rms = [1e300, 1e300]`) wrote phi 5.8e294 rad with exit 0.
pub fn check_angle(t: f64, name: &str, x: f64) -> io::Result<()> {
    let limit = pendtilt_core::model::PHI_LIMIT;
    if x.is_finite() && x.abs() <= limit {
        return Ok(());
    }
    Err(io::Error::new(
        io::ErrorKind::InvalidData,
        format!(
            "at t = {t} s the simulated {name} is {x:e} rad (not finite or beyond {limit} \
             rad): the settings drive the pendulum beyond any physical motion (check the \
             values given with --set, --config or --rig: their units, their magnitude)"
        ),
    ))
}

/// Rows per chunk handed from the simulating thread to the writing one.
const CHUNK: usize = 4096;

/// Streams every row of `sim` as CSV (header first) into `w`, calling `progress(done,
/// total)` every 8192 rows and at the end. Returns the number of rows written.
///
/// The simulation runs on a second thread and hands over chunks of rows through a bounded
/// channel, so simulating and formatting overlap on two cores while memory stays flat
/// (at most a few chunks in flight). The bytes are the same as a single-threaded run.
pub fn write_log<W: Write>(
    sim: Simulator,
    mut w: W,
    mut progress: impl FnMut(u64, u64),
) -> io::Result<u64> {
    let total = sim.total_rows();
    writeln!(w, "{LOG_HEADER}")?;
    let mut n = 0u64;
    std::thread::scope(|scope| -> io::Result<()> {
        let (tx, rx) = std::sync::mpsc::sync_channel::<Vec<SimRow>>(4);
        scope.spawn(move || {
            let mut sim = sim;
            loop {
                let chunk: Vec<SimRow> = sim.by_ref().take(CHUNK).collect();
                // An empty chunk ends the run; a send error means the writer gave up.
                if chunk.is_empty() || tx.send(chunk).is_err() {
                    break;
                }
            }
        });
        // Returning early on a write error drops `rx`, which stops the simulating thread.
        for chunk in rx {
            for row in &chunk {
                check_angle(row.t, "pendulum angle phi", row.phi)?;
                check_angle(row.t, "true tilt theta", row.theta)?;
                write_row(&mut w, row)?;
                n += 1;
                if n % 8192 == 0 {
                    progress(n, total);
                }
            }
        }
        Ok(())
    })?;
    progress(n, total);
    w.flush()?;
    Ok(n)
}

/// Where the rig TOML goes beside a log: `run.csv` -> `run.rig.toml`.
pub fn rig_path_for(log: &Path) -> PathBuf {
    sibling(log, "rig.toml")
}

/// Where the resolved scenario goes beside a log: `run.csv` -> `run.scenario.toml`.
pub fn scenario_path_for(log: &Path) -> PathBuf {
    sibling(log, "scenario.toml")
}

fn sibling(log: &Path, ext: &str) -> PathBuf {
    let stem = log
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "log".into());
    log.with_file_name(format!("{stem}.{ext}"))
}

/// What one run writes: the texts of the rig and scenario files, the inputs the outputs must
/// not overwrite, and the log writer.
pub struct Outputs<'a, F> {
    /// The rig TOML.
    pub rig_text: String,
    /// The resolved scenario TOML.
    pub scenario_text: String,
    /// Files read (`--config`, `--rig`) that no output may overwrite.
    pub inputs: Vec<NamedPath<'a>>,
    /// Writes the log into the (uncommitted) file; returns its rows.
    pub write_log: F,
}

/// Writes the log to `log`, the rig file to `rig_out` (default: beside the log) and the
/// scenario file beside the log, refusing an output that is an input or another output, and
/// renames them into place only when all were written. On standard output or a device the
/// log has no "beside": the rig file is written only when `rig_out` names it, the scenario
/// file not at all. Returns the rows written and the rig and scenario paths written.
pub fn write_files<F>(
    log: &Path,
    rig_out: Option<&Path>,
    out: Outputs<'_, F>,
) -> anyhow::Result<(u64, Option<PathBuf>, Option<PathBuf>)>
where
    F: FnOnce(&OutputFile) -> anyhow::Result<u64>,
{
    let no_beside = safe::has_no_beside(log);
    let rig_path = match rig_out {
        Some(p) => Some(p.to_path_buf()),
        None => (!no_beside).then(|| rig_path_for(log)),
    };
    let scen_path = (!no_beside).then(|| scenario_path_for(log));
    let mut outputs = vec![NamedPath::new("-o", log)];
    outputs.extend(rig_path.as_deref().map(|p| NamedPath::new("--rig-out", p)));
    outputs.extend(
        scen_path
            .as_deref()
            .map(|p| NamedPath::new("the scenario file written beside -o,", p)),
    );
    safe::check_distinct(&out.inputs, &outputs)?;
    let files = outputs
        .iter()
        .map(|o| OutputFile::create(o.option, o.path))
        .collect::<Result<Vec<_>, _>>()?;
    let texts = [out.rig_text, out.scenario_text];
    let n = (out.write_log)(&files[0])
        .and_then(|n| {
            for (f, text) in files[1..].iter().zip(&texts) {
                f.write_all(text.as_bytes())?;
            }
            Ok(n)
        })
        .with_context(|| {
            let not: Vec<String> = outputs.iter().map(|o| safe::not_written(o.path)).collect();
            not.join("; ")
        })?;
    // Every file was written: only now do they replace any earlier ones.
    for f in files {
        f.commit()?;
    }
    Ok((n, rig_path, scen_path))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_round_trip() {
        for x in [0.0, 1e-17, -3.5e-9, 0.001, 12.25, 9.80665, 1e300, -0.0] {
            let mut v = Vec::new();
            write_num(&mut v, x).unwrap();
            let s = String::from_utf8(v).unwrap();
            assert_eq!(s.parse::<f64>().unwrap(), x, "{s}");
            assert!(s.len() < 26, "{s}");
        }
    }

    #[test]
    fn sibling_paths() {
        assert_eq!(
            rig_path_for(Path::new("/tmp/a/run.csv")),
            PathBuf::from("/tmp/a/run.rig.toml")
        );
        assert_eq!(
            scenario_path_for(Path::new("run")),
            PathBuf::from("run.scenario.toml")
        );
    }
}

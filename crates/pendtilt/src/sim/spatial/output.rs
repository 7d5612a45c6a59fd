//! Writing a 3-D run: the CSV log of MODEL.md 7.6 (columns [`LogRow3d::COLUMNS`]), streamed
//! row by row, numbers in Ryu's shortest round-trip form (as the planar log).

use std::io::{self, Write};

use super::scenario::Run3d;
use super::sensors::LogRow3d;

/// Writes one CSV row (no header).
pub fn write_row<W: Write>(w: &mut W, row: &LogRow3d) -> io::Result<()> {
    let mut buf = ryu::Buffer::new();
    for (i, x) in row.values().into_iter().enumerate() {
        if i > 0 {
            w.write_all(b",")?;
        }
        w.write_all(buf.format(x).as_bytes())?;
    }
    w.write_all(b"\n")
}

/// Streams every row of `run` as CSV (header first) into `w`, calling `progress(done)` every
/// 8192 rows and at the end. Returns the number of rows written.
pub fn write_log<W: Write>(run: Run3d, mut w: W, mut progress: impl FnMut(u64)) -> io::Result<u64> {
    writeln!(w, "{}", LogRow3d::COLUMNS.join(","))?;
    let mut n = 0u64;
    for (_, row) in run {
        for (name, x) in [
            ("encoder angle phi_x", row.phi[0]),
            ("encoder angle phi_y", row.phi[1]),
            ("true roll", row.roll),
            ("true pitch", row.pitch),
        ] {
            crate::sim::planar::output::check_angle(row.t, name, x)?;
        }
        write_row(&mut w, &row)?;
        n += 1;
        if n % 8192 == 0 {
            progress(n);
        }
    }
    progress(n);
    w.flush()?;
    Ok(n)
}

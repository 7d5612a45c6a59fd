//! `pendtilt.read_csv`: a CSV table (a log, or an output of the command) as columns.
use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::PyList;

use crate::py_err;

/// One column as read: numbers while every cell is one, else text.
enum Col {
    Numbers(Vec<f64>),
    Text(Vec<String>),
}

/// Reads the CSV file at `path` (a header, `#` comment lines skipped) into `(names,
/// columns)`: a column whose every cell is a number (an empty cell is NaN) is a float64
/// array, with the exact value of each cell's text (Rust's correctly rounded parse, as
/// the command reads it); any other column is a list of str (the `_flags` columns).
#[pyfunction]
pub fn read_csv<'py>(
    py: Python<'py>,
    path: std::path::PathBuf,
) -> PyResult<(Vec<String>, Bound<'py, PyList>)> {
    let (names, cols) = py
        .detach(|| -> anyhow::Result<_> {
            let mut r = csv::ReaderBuilder::new()
                .comment(Some(b'#'))
                .trim(csv::Trim::All)
                .flexible(false)
                .from_path(&path)
                .map_err(|e| anyhow::anyhow!("cannot read {}: {e}", path.display()))?;
            let names: Vec<String> = r.headers()?.iter().map(str::to_string).collect();
            let mut cols: Vec<Col> = names.iter().map(|_| Col::Numbers(Vec::new())).collect();
            let mut rec = csv::StringRecord::new();
            while r
                .read_record(&mut rec)
                .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?
            {
                for (c, cell) in cols.iter_mut().zip(rec.iter()) {
                    match c {
                        Col::Numbers(v) => {
                            let x = if cell.is_empty() {
                                Some(f64::NAN)
                            } else {
                                cell.parse::<f64>().ok()
                            };
                            match x {
                                Some(x) => v.push(x),
                                None => {
                                    let mut text: Vec<String> =
                                        v.iter().map(|x| format!("{x}")).collect();
                                    text.push(cell.to_string());
                                    *c = Col::Text(text);
                                }
                            }
                        }
                        Col::Text(v) => v.push(cell.to_string()),
                    }
                }
            }
            Ok((names, cols))
        })
        .map_err(py_err)?;
    let out = PyList::empty(py);
    for c in cols {
        match c {
            Col::Numbers(v) => out.append(v.into_pyarray(py))?,
            Col::Text(v) => out.append(v)?,
        }
    }
    Ok((names, out))
}

//! MATLAB level-5 MAT files (MATLAB `save -v7` or `-v6`, scipy's `savemat`), numeric
//! arrays only: enough to read published IMU data sets such as BROAD, which ship as `.mat`.
//!
//! What is read: every numeric variable (`double`, `single`, `int8` to `uint64`, and
//! `logical`, which MATLAB stores as `uint8` with a flag), converted to `f64` and kept
//! column-major as stored, with its dimensions. Whatever the storage type (MATLAB stores a
//! `double` array of small integers as `int16` bytes, say), the values are the same.
//! `int64` and `uint64` values beyond 2^53 lose their last digits in the conversion.
//!
//! What is skipped, never an error: char arrays, cells, structs, objects, sparse matrices
//! and any other class are listed by name with their [`VarKind`], without data. Elements
//! without a name (the subsystem data MATLAB appends for objects) are left out entirely.
//! A complex array keeps its real part: the imaginary part is checked to be there and
//! dropped, and the variable's kind says [`VarKind::Complex`].
//!
//! Both byte orders are read (`IM`, little-endian, as every current MATLAB writes, and
//! `MI`, big-endian, by byte-swapping). A v7.3 file is HDF5 inside, and gets an error that
//! says how to save it instead. No input makes the reader panic: every size in the file
//! is checked against the bytes actually there before anything is allocated, and a
//! compressed element may not inflate to more than [`MAX_INFLATED_BYTES`].
//!
//! ```no_run
//! use pendtilt::io::mat::MatFile;
//! let mat = MatFile::open("10_undisturbed_slow_translation_A.mat")?;
//! let acc = mat.get("imu_acc").ok_or("no imu_acc")?;
//! let (n, x0) = (acc.rows(), acc.get(0, 0));
//! let ax = acc.column(0);
//! # let _ = (n, x0, ax);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use std::fmt::Write as _;
use std::io::Read;
use std::path::Path;

use flate2::read::ZlibDecoder;

/// The most one compressed element may inflate to (1 GiB): a few kilobytes of zlib can
/// claim gigabytes, and a data set that large belongs in another format anyway.
pub const MAX_INFLATED_BYTES: u64 = 1 << 30;

/// Header length: 116 bytes of text, 8 of subsystem offset, 2 of version, 2 of endian.
const HEADER_LEN: usize = 128;
const V5_TEXT: &[u8] = b"MATLAB 5.0 MAT-file";
const V73_TEXT: &[u8] = b"MATLAB 7.3 MAT-file";
/// Where a v7.3 file's HDF5 superblock starts (after its 512-byte user block).
const HDF5_AT: usize = 512;
const HDF5_SIGNATURE: &[u8] = b"\x89HDF";

// Data types of the element tags (MATLAB "MAT-File Format", table 1-1).
const MI_INT8: u32 = 1;
const MI_UINT8: u32 = 2;
const MI_INT16: u32 = 3;
const MI_UINT16: u32 = 4;
const MI_INT32: u32 = 5;
const MI_UINT32: u32 = 6;
const MI_SINGLE: u32 = 7;
const MI_DOUBLE: u32 = 9;
const MI_INT64: u32 = 12;
const MI_UINT64: u32 = 13;
const MI_MATRIX: u32 = 14;
const MI_COMPRESSED: u32 = 15;

// Array classes (the low byte of the first array-flags word).
const MX_CELL: u32 = 1;
const MX_STRUCT: u32 = 2;
const MX_OBJECT: u32 = 3;
const MX_CHAR: u32 = 4;
const MX_SPARSE: u32 = 5;
const MX_DOUBLE: u32 = 6;
const MX_UINT64: u32 = 15;
/// Opaque objects (function handles, `string`) have no dimensions before their name.
const MX_OPAQUE: u32 = 17;

const FLAG_COMPLEX: u32 = 0x0800;
const FLAG_LOGICAL: u32 = 0x0200;

/// One numeric variable: its values as `f64`, column-major as MATLAB stores them.
#[derive(Debug, Clone, PartialEq)]
pub struct MatArray {
    /// The variable's name in the file.
    pub name: String,
    /// The dimensions, at least two for anything MATLAB writes (a scalar is `[1, 1]`).
    pub dims: Vec<usize>,
    /// The values, column-major: element `(r, c)` of a 2-D array is `data[c * rows + r]`.
    pub data: Vec<f64>,
}

impl MatArray {
    /// The number of rows: `dims[0]` (1 if there are no dimensions).
    pub fn rows(&self) -> usize {
        self.dims.first().copied().unwrap_or(1)
    }

    /// The number of columns, the array seen as 2-D: the product of every dimension after
    /// the first (a 3x4x5 array has 20 columns of 3).
    pub fn cols(&self) -> usize {
        self.dims.iter().skip(1).product()
    }

    /// The value at `(row, col)`, the array seen as 2-D.
    ///
    /// # Panics
    /// If `row >= rows()` or the element is past the data (an index out of range, as with
    /// slices); a row past the end would otherwise silently read the next column.
    pub fn get(&self, row: usize, col: usize) -> f64 {
        assert!(
            row < self.rows(),
            "MatArray `{}`: row {row} out of range ({} rows)",
            self.name,
            self.rows()
        );
        self.data[col * self.rows() + row]
    }

    /// Column `col` of the array seen as 2-D, `rows()` values.
    ///
    /// # Panics
    /// If the column is past the data.
    pub fn column(&self, col: usize) -> &[f64] {
        let rows = self.rows();
        &self.data[col * rows..(col + 1) * rows]
    }
}

/// What a variable holds: the numeric kinds are read into a [`MatArray`], the others are
/// only listed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum VarKind {
    /// A real numeric array.
    Numeric,
    /// A logical array (stored as `uint8`), read as 0 and 1.
    Logical,
    /// A complex numeric array: its real part is read, its imaginary part dropped.
    Complex,
    /// A char array (text): skipped.
    Char,
    /// A cell array: skipped.
    Cell,
    /// A struct: skipped.
    Struct,
    /// A MATLAB object (old-style class): skipped.
    Object,
    /// A sparse matrix: skipped.
    Sparse,
    /// Any other class, by its number (16 function handle, 17 opaque, ...): skipped.
    Other(u8),
}

impl VarKind {
    /// Whether the variable was read into a [`MatArray`].
    pub fn is_numeric(self) -> bool {
        matches!(self, VarKind::Numeric | VarKind::Logical | VarKind::Complex)
    }
}

impl std::fmt::Display for VarKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            VarKind::Numeric => f.write_str("numeric"),
            VarKind::Logical => f.write_str("logical"),
            VarKind::Complex => f.write_str("complex (real part read)"),
            VarKind::Char => f.write_str("char"),
            VarKind::Cell => f.write_str("cell"),
            VarKind::Struct => f.write_str("struct"),
            VarKind::Object => f.write_str("object"),
            VarKind::Sparse => f.write_str("sparse"),
            VarKind::Other(class) => write!(f, "class {class}"),
        }
    }
}

/// A variable in file order: its kind, and where its array is if it has one.
#[derive(Debug, Clone)]
struct Variable {
    name: String,
    kind: VarKind,
    array: Option<usize>,
}

/// A whole MAT file: the numeric arrays in file order, and every variable by name.
#[derive(Debug, Clone)]
pub struct MatFile {
    origin: String,
    arrays: Vec<MatArray>,
    variables: Vec<Variable>,
}

/// Why a MAT file could not be read. Every message starts with the file (the `origin`
/// given), then where it helps the byte offset and the variable.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum MatError {
    /// The file could not be read at all.
    #[error("{origin}: cannot read: {source}")]
    Io {
        /// The file.
        origin: String,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// A MATLAB v7.3 file: HDF5 inside, which this reader does not read.
    #[error("{origin}: is a MATLAB v7.3 (HDF5) file: save it with -v7, or give a CSV")]
    V73 {
        /// The file.
        origin: String,
    },
    /// Not a MAT file at all (no level-5 header).
    #[error("{origin}: not a MATLAB v5 MAT-file: {detail}")]
    NotMat {
        /// The file.
        origin: String,
        /// What was found instead.
        detail: String,
    },
    /// The file ends inside the header or an element.
    #[error("{origin}: {}: truncated: {what} needs {needed} bytes, only {available} remain", place(.offset, .inflated, .variable))]
    Truncated {
        /// The file.
        origin: String,
        /// The byte where the cut element starts (for a compressed element, its own start).
        offset: u64,
        /// Inside a compressed element: the offset in its inflated bytes.
        inflated: Option<u64>,
        /// The variable, once its name is known.
        variable: Option<String>,
        /// The part that is cut ("the header", "the real part", ...).
        what: String,
        /// The bytes it needs.
        needed: u64,
        /// The bytes left.
        available: u64,
    },
    /// An element that contradicts itself or the format.
    #[error("{origin}: {}: {detail}", place(.offset, .inflated, .variable))]
    Malformed {
        /// The file.
        origin: String,
        /// The byte where the element starts (for a compressed element, its own start).
        offset: u64,
        /// Inside a compressed element: the offset in its inflated bytes.
        inflated: Option<u64>,
        /// The variable, once its name is known.
        variable: Option<String>,
        /// What is wrong.
        detail: String,
    },
    /// A compressed element that does not inflate, or inflates to too much.
    #[error("{origin}: byte {offset}: compressed element: {detail}")]
    Inflate {
        /// The file.
        origin: String,
        /// The byte where the compressed element starts.
        offset: u64,
        /// What went wrong.
        detail: String,
    },
}

/// "byte 1234", "byte 128, inflated byte 40", then ": variable `name`" when known.
fn place(offset: &u64, inflated: &Option<u64>, variable: &Option<String>) -> String {
    let mut s = format!("byte {offset}");
    if let Some(inner) = inflated {
        let _ = write!(s, ", inflated byte {inner}");
    }
    if let Some(name) = variable {
        let _ = write!(s, ": variable `{name}`");
    }
    s
}

impl MatFile {
    /// Reads a MAT file; errors name the file as `path` is written.
    pub fn open(path: impl AsRef<Path>) -> Result<MatFile, MatError> {
        let path = path.as_ref();
        let origin = path.display().to_string();
        match std::fs::read(path) {
            Ok(bytes) => MatFile::from_bytes(&bytes, &origin),
            Err(source) => Err(MatError::Io { origin, source }),
        }
    }

    /// Reads a MAT file's bytes; `origin` (a file name, say) starts every error message.
    pub fn from_bytes(bytes: &[u8], origin: &str) -> Result<MatFile, MatError> {
        parse(bytes, origin, MAX_INFLATED_BYTES)
    }

    /// The numeric array called `name` (the first, should a file repeat a name); `None`
    /// for a missing or non-numeric variable (see [`MatFile::kind`]).
    pub fn get(&self, name: &str) -> Option<&MatArray> {
        self.variables
            .iter()
            .find(|v| v.name == name)
            .and_then(|v| v.array)
            .and_then(|i| self.arrays.get(i))
    }

    /// The names of every variable in file order, numeric or not.
    pub fn names(&self) -> impl Iterator<Item = &str> + '_ {
        self.variables.iter().map(|v| v.name.as_str())
    }

    /// What the variable called `name` holds, `None` if there is none.
    pub fn kind(&self, name: &str) -> Option<VarKind> {
        self.variables
            .iter()
            .find(|v| v.name == name)
            .map(|v| v.kind)
    }

    /// The numeric arrays, in file order.
    pub fn arrays(&self) -> &[MatArray] {
        &self.arrays
    }

    /// The variables that were listed but not read (char, cell, struct, ...), with their
    /// kinds, in file order: for messages such as "`info` is a char array".
    pub fn skipped(&self) -> impl Iterator<Item = (&str, VarKind)> + '_ {
        self.variables
            .iter()
            .filter(|v| v.array.is_none())
            .map(|v| (v.name.as_str(), v.kind))
    }

    /// The `origin` the file was read under (its path for [`MatFile::open`]).
    pub fn origin(&self) -> &str {
        &self.origin
    }

    /// Whether `bytes` start like a level-5 MAT file: the text "MATLAB 5.0 MAT-file" and
    /// version 0x0100 with a valid endian indicator at byte 124. For choosing a reader by
    /// content; [`MatFile::from_bytes`] itself only needs the version word.
    pub fn is_mat_v5(bytes: &[u8]) -> bool {
        bytes.starts_with(V5_TEXT) && endian_of(bytes).is_some()
    }
}

/// The byte order a header's version and endian word declares, for a v5 file.
mod parse;
use parse::{endian_of, parse};

#[cfg(test)]
mod tests;

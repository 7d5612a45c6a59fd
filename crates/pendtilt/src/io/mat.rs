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
fn endian_of(bytes: &[u8]) -> Option<Endian> {
    match bytes.get(124..HEADER_LEN)? {
        [0x00, 0x01, b'I', b'M'] => Some(Endian::Little),
        [0x01, 0x00, b'M', b'I'] => Some(Endian::Big),
        _ => None,
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Endian {
    Little,
    Big,
}

impl Endian {
    /// The u32 at `pos`; callers have checked the bounds, and 0 stands in otherwise.
    fn u32_at(self, buf: &[u8], pos: usize) -> u32 {
        let word: [u8; 4] = pos
            .checked_add(4)
            .and_then(|end| buf.get(pos..end))
            .and_then(|b| b.try_into().ok())
            .unwrap_or([0; 4]);
        match self {
            Endian::Little => u32::from_le_bytes(word),
            Endian::Big => u32::from_be_bytes(word),
        }
    }
}

/// Where a buffer being parsed sits in the file, for error messages.
#[derive(Debug, Clone, Copy)]
enum Loc {
    /// The file's own bytes: positions are file offsets.
    File,
    /// The inflated bytes of the compressed element starting at this file offset.
    Inflated(u64),
}

impl Loc {
    fn at(self, pos: usize) -> (u64, Option<u64>) {
        match self {
            Loc::File => (pos as u64, None),
            Loc::Inflated(start) => (start, Some(pos as u64)),
        }
    }
}

/// One data element: its type, its data, and where the next one starts.
struct Element<'b> {
    ty: u32,
    data: &'b [u8],
    data_pos: usize,
    next: usize,
}

struct Parser<'a> {
    origin: &'a str,
    endian: Endian,
    limit: u64,
}

/// The whole reader, with the inflation limit as a parameter so tests can reach it.
fn parse(bytes: &[u8], origin: &str, limit: u64) -> Result<MatFile, MatError> {
    let endian = header(bytes, origin)?;
    let parser = Parser {
        origin,
        endian,
        limit,
    };
    let mut file = MatFile {
        origin: origin.to_string(),
        arrays: Vec::new(),
        variables: Vec::new(),
    };
    let mut pos = HEADER_LEN;
    while pos < bytes.len() {
        // A writer may pad the last element; a few zero bytes are not a cut element.
        if bytes.len() - pos < 8 && bytes[pos..].iter().all(|&b| b == 0) {
            break;
        }
        let el = parser.element(bytes, pos, bytes.len(), Loc::File, None, "a variable")?;
        match el.ty {
            MI_COMPRESSED => {
                let inflated = parser.inflate(el.data, pos)?;
                let loc = Loc::Inflated(pos as u64);
                let inner = parser.element(
                    &inflated,
                    0,
                    inflated.len(),
                    loc,
                    None,
                    "the compressed variable",
                )?;
                if inner.ty == MI_MATRIX {
                    let end = inner.data_pos + inner.data.len();
                    parser.matrix(&inflated, inner.data_pos, end, loc, &mut file)?;
                }
            }
            MI_MATRIX => {
                let end = el.data_pos + el.data.len();
                parser.matrix(bytes, el.data_pos, end, Loc::File, &mut file)?;
            }
            // Nothing else belongs at the top level; whatever it is holds no variable.
            _ => {}
        }
        pos = el.next;
    }
    Ok(file)
}

/// Checks the 128-byte header and returns the byte order, or says what the file is.
fn header(bytes: &[u8], origin: &str) -> Result<Endian, MatError> {
    let endian = endian_of(bytes);
    let hdf5_inside = bytes.get(HDF5_AT..HDF5_AT + HDF5_SIGNATURE.len()) == Some(HDF5_SIGNATURE);
    if bytes.starts_with(V73_TEXT) || (hdf5_inside && endian.is_none()) {
        return Err(MatError::V73 {
            origin: origin.to_string(),
        });
    }
    let not_mat = |detail: String| MatError::NotMat {
        origin: origin.to_string(),
        detail,
    };
    if bytes.is_empty() {
        return Err(not_mat("the file is empty".to_string()));
    }
    if bytes.starts_with(HDF5_SIGNATURE) {
        return Err(not_mat(
            "it is an HDF5 file without the MAT-file header".to_string(),
        ));
    }
    let looks_matlab = bytes.iter().zip(b"MATLAB").all(|(a, b)| a == b);
    if bytes.len() < HEADER_LEN {
        if looks_matlab {
            return Err(MatError::Truncated {
                origin: origin.to_string(),
                offset: 0,
                inflated: None,
                variable: None,
                what: "the header".to_string(),
                needed: HEADER_LEN as u64,
                available: bytes.len() as u64,
            });
        }
        return Err(not_mat(format!(
            "{} bytes, shorter than the 128-byte header",
            bytes.len()
        )));
    }
    match endian {
        Some(endian) => Ok(endian),
        None if looks_matlab => Err(MatError::Malformed {
            origin: origin.to_string(),
            offset: 124,
            inflated: None,
            variable: None,
            detail: format!(
                "the version and endian word is {:02x} {:02x} {:02x} {:02x}, \
                 not 01 00 with \"IM\" or \"MI\"",
                bytes[124], bytes[125], bytes[126], bytes[127]
            ),
        }),
        None => Err(not_mat(
            "no \"MATLAB 5.0 MAT-file\" header with version 0x0100 at byte 124".to_string(),
        )),
    }
}

impl Parser<'_> {
    fn truncated(
        &self,
        loc: Loc,
        pos: usize,
        variable: Option<&str>,
        what: String,
        needed: usize,
        available: usize,
    ) -> MatError {
        let (offset, inflated) = loc.at(pos);
        MatError::Truncated {
            origin: self.origin.to_string(),
            offset,
            inflated,
            variable: variable.map(str::to_string),
            what,
            needed: needed as u64,
            available: available as u64,
        }
    }

    fn malformed(&self, loc: Loc, pos: usize, variable: Option<&str>, detail: String) -> MatError {
        let (offset, inflated) = loc.at(pos);
        MatError::Malformed {
            origin: self.origin.to_string(),
            offset,
            inflated,
            variable: variable.map(str::to_string),
            detail,
        }
    }

    /// The element whose tag starts at `pos`, which must end by `end`. The small form
    /// (byte count in the upper 16 bits of the first word) is 8 bytes in all; the others
    /// are padded to 8 bytes, except compressed ones (MATLAB and scipy do not pad those).
    fn element<'b>(
        &self,
        buf: &'b [u8],
        pos: usize,
        end: usize,
        loc: Loc,
        variable: Option<&str>,
        what: &str,
    ) -> Result<Element<'b>, MatError> {
        let end = end.min(buf.len());
        let available = end.saturating_sub(pos);
        if available < 8 {
            let what = format!("the tag of {what}");
            return Err(self.truncated(loc, pos, variable, what, 8, available));
        }
        let first = self.endian.u32_at(buf, pos);
        if first >> 16 != 0 {
            let size = (first >> 16) as usize;
            if size > 4 {
                let detail = format!(
                    "{what}: a small element holds at most 4 bytes, this one claims {size}"
                );
                return Err(self.malformed(loc, pos, variable, detail));
            }
            return Ok(Element {
                ty: first & 0xffff,
                data: &buf[pos + 4..pos + 4 + size],
                data_pos: pos + 4,
                next: pos + 8,
            });
        }
        let size = self.endian.u32_at(buf, pos + 4) as usize;
        let data_pos = pos + 8;
        if size > end - data_pos {
            let what = what.to_string();
            return Err(self.truncated(loc, pos, variable, what, size, end - data_pos));
        }
        let padded = if first == MI_COMPRESSED {
            size
        } else {
            size.saturating_add(7) & !7
        };
        Ok(Element {
            ty: first,
            data: &buf[data_pos..data_pos + size],
            data_pos,
            next: data_pos.saturating_add(padded).min(end),
        })
    }

    /// Inflates the compressed element starting at file offset `pos`: first its tag, for
    /// the size it declares, then just that many bytes, so what is allocated is bounded by
    /// both the limit and what the stream really holds.
    fn inflate(&self, zlib: &[u8], pos: usize) -> Result<Vec<u8>, MatError> {
        let fail = |detail: String| MatError::Inflate {
            origin: self.origin.to_string(),
            offset: pos as u64,
            detail,
        };
        let corrupt =
            |e: std::io::Error| fail(format!("the zlib stream is corrupt or cut short ({e})"));
        let mut decoder = ZlibDecoder::new(zlib);
        let mut out = Vec::new();
        (&mut decoder)
            .take(8)
            .read_to_end(&mut out)
            .map_err(corrupt)?;
        if out.len() < 8 {
            // Too short for a tag: the element check reports it as truncated.
            return Ok(out);
        }
        let first = self.endian.u32_at(&out, 0);
        let size = if first >> 16 != 0 {
            0
        } else {
            u64::from(self.endian.u32_at(&out, 4))
        };
        let total = 8 + size.saturating_add(7) / 8 * 8;
        if total > self.limit {
            return Err(fail(format!(
                "the element inside declares {total} bytes, more than the {} a compressed \
                 element may inflate to",
                bytes_text(self.limit)
            )));
        }
        decoder
            .take(total - 8)
            .read_to_end(&mut out)
            .map_err(corrupt)?;
        Ok(out)
    }

    /// Reads the matrix whose subelements lie in `buf[start..end]` into `file`: a numeric
    /// array, or a listed name for any other class.
    fn matrix(
        &self,
        buf: &[u8],
        start: usize,
        end: usize,
        loc: Loc,
        file: &mut MatFile,
    ) -> Result<(), MatError> {
        if start >= end {
            // An empty matrix element (MATLAB writes these for empty cells): nothing.
            return Ok(());
        }
        let flags = self.element(buf, start, end, loc, None, "the array flags")?;
        if flags.ty != MI_UINT32 || flags.data.len() < 4 {
            let detail = format!(
                "the array flags are {} bytes of {}, not uint32 words",
                flags.data.len(),
                type_name(flags.ty)
            );
            return Err(self.malformed(loc, start, None, detail));
        }
        let word = self.endian.u32_at(flags.data, 0);
        let class = word & 0xff;
        if !(MX_DOUBLE..=MX_UINT64).contains(&class) {
            // Never an error: list it by name if the name can be found at all.
            if let Some(name) = self.other_name(buf, flags.next, end, class, loc) {
                file.variables.push(Variable {
                    name,
                    kind: kind_of_class(class),
                    array: None,
                });
            }
            return Ok(());
        }
        let dims_el = self.element(buf, flags.next, end, loc, None, "the dimensions")?;
        let name_el = self.element(buf, dims_el.next, end, loc, None, "the name")?;
        let name = name_text(name_el.data);
        if name.is_empty() {
            // Subsystem data, or something only an object refers to: not a variable.
            return Ok(());
        }
        let var = Some(name.as_str());
        let dims = self.dims(&dims_el, flags.next, loc, var)?;
        let real = self.element(buf, name_el.next, end, loc, var, "the real part")?;
        let data = self.numbers(&real, name_el.next, loc, var, &dims)?;
        if word & FLAG_COMPLEX != 0 {
            // Read to check it is there, then dropped (see the module documentation).
            self.element(buf, real.next, end, loc, var, "the imaginary part")?;
        }
        let kind = if word & FLAG_COMPLEX != 0 {
            VarKind::Complex
        } else if word & FLAG_LOGICAL != 0 {
            VarKind::Logical
        } else {
            VarKind::Numeric
        };
        file.variables.push(Variable {
            name: name.clone(),
            kind,
            array: Some(file.arrays.len()),
        });
        file.arrays.push(MatArray { name, dims, data });
        Ok(())
    }

    /// The name of a non-numeric variable, leniently: `None` when it cannot be found.
    fn other_name(
        &self,
        buf: &[u8],
        pos: usize,
        end: usize,
        class: u32,
        loc: Loc,
    ) -> Option<String> {
        let mut pos = pos;
        if class != MX_OPAQUE {
            pos = self.element(buf, pos, end, loc, None, "").ok()?.next;
        }
        let name = name_text(self.element(buf, pos, end, loc, None, "").ok()?.data);
        (!name.is_empty()).then_some(name)
    }

    /// The dimensions, from an int32 element whose tag is at `pos`.
    fn dims(
        &self,
        el: &Element<'_>,
        pos: usize,
        loc: Loc,
        var: Option<&str>,
    ) -> Result<Vec<usize>, MatError> {
        if el.ty != MI_INT32 || el.data.is_empty() || el.data.len() % 4 != 0 {
            let detail = format!(
                "the dimensions are {} bytes of {}, not int32 values",
                el.data.len(),
                type_name(el.ty)
            );
            return Err(self.malformed(loc, pos, var, detail));
        }
        let mut dims = Vec::with_capacity(el.data.len() / 4);
        for i in 0..el.data.len() / 4 {
            let d = self.endian.u32_at(el.data, 4 * i) as i32;
            match usize::try_from(d) {
                Ok(d) => dims.push(d),
                Err(_) => {
                    let detail = format!("dimension {} is negative ({d})", i + 1);
                    return Err(self.malformed(loc, pos, var, detail));
                }
            }
        }
        Ok(dims)
    }

    /// The real part's values as f64, once their count is checked against the dimensions
    /// (before anything is allocated).
    fn numbers(
        &self,
        el: &Element<'_>,
        pos: usize,
        loc: Loc,
        var: Option<&str>,
        dims: &[usize],
    ) -> Result<Vec<f64>, MatError> {
        let Some(width) = type_width(el.ty) else {
            let detail = format!("the real part is {}, not a numeric type", type_name(el.ty));
            return Err(self.malformed(loc, pos, var, detail));
        };
        if el.data.len() % width != 0 {
            let detail = format!(
                "the real part is {} bytes, not a whole number of {} values ({width} bytes each)",
                el.data.len(),
                type_name(el.ty)
            );
            return Err(self.malformed(loc, pos, var, detail));
        }
        let count = el.data.len() / width;
        let shape = dims_text(dims);
        let need = dims.iter().try_fold(1usize, |n, &d| n.checked_mul(d));
        if need != Some(count) {
            let detail = match need {
                Some(need) => {
                    format!("the data holds {count} values, the dimensions {shape} need {need}")
                }
                None => format!("the dimensions {shape} are too large"),
            };
            return Err(self.malformed(loc, pos, var, detail));
        }
        Ok(convert(el.ty, el.data, self.endian))
    }
}

/// The bytes one value of a numeric data type takes, `None` for the others.
fn type_width(ty: u32) -> Option<usize> {
    match ty {
        MI_INT8 | MI_UINT8 => Some(1),
        MI_INT16 | MI_UINT16 => Some(2),
        MI_INT32 | MI_UINT32 | MI_SINGLE => Some(4),
        MI_DOUBLE | MI_INT64 | MI_UINT64 => Some(8),
        _ => None,
    }
}

/// A data type's name for messages.
fn type_name(ty: u32) -> String {
    let name = match ty {
        MI_INT8 => "int8",
        MI_UINT8 => "uint8",
        MI_INT16 => "int16",
        MI_UINT16 => "uint16",
        MI_INT32 => "int32",
        MI_UINT32 => "uint32",
        MI_SINGLE => "single",
        MI_DOUBLE => "double",
        MI_INT64 => "int64",
        MI_UINT64 => "uint64",
        MI_MATRIX => "a matrix",
        MI_COMPRESSED => "compressed data",
        16 => "utf8",
        17 => "utf16",
        18 => "utf32",
        _ => return format!("data type {ty}"),
    };
    name.to_string()
}

fn kind_of_class(class: u32) -> VarKind {
    match class {
        MX_CELL => VarKind::Cell,
        MX_STRUCT => VarKind::Struct,
        MX_OBJECT => VarKind::Object,
        MX_CHAR => VarKind::Char,
        MX_SPARSE => VarKind::Sparse,
        other => VarKind::Other(other as u8),
    }
}

/// A name element's text: ASCII in practice, trailing NULs dropped.
fn name_text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes)
        .trim_end_matches('\0')
        .to_string()
}

/// "3x5", as MATLAB writes sizes.
fn dims_text(dims: &[usize]) -> String {
    let parts: Vec<String> = dims.iter().map(usize::to_string).collect();
    parts.join("x")
}

/// "1 GiB" for the real limit, a byte count for the small ones tests use.
fn bytes_text(n: u64) -> String {
    if n >= 1 << 30 && n % (1 << 30) == 0 {
        format!("{} GiB", n >> 30)
    } else {
        format!("{n} bytes")
    }
}

/// The values of numeric data type `ty` (checked by the caller) as f64.
fn convert(ty: u32, data: &[u8], endian: Endian) -> Vec<f64> {
    macro_rules! values {
        ($t:ty, $n:expr) => {
            data.chunks_exact($n)
                .map(|chunk| {
                    let bytes: [u8; $n] = chunk.try_into().unwrap_or([0; $n]);
                    let value = match endian {
                        Endian::Little => <$t>::from_le_bytes(bytes),
                        Endian::Big => <$t>::from_be_bytes(bytes),
                    };
                    value as f64
                })
                .collect()
        };
    }
    match ty {
        MI_INT8 => values!(i8, 1),
        MI_UINT8 => values!(u8, 1),
        MI_INT16 => values!(i16, 2),
        MI_UINT16 => values!(u16, 2),
        MI_INT32 => values!(i32, 4),
        MI_UINT32 => values!(u32, 4),
        MI_SINGLE => values!(f32, 4),
        MI_DOUBLE => values!(f64, 8),
        MI_INT64 => values!(i64, 8),
        MI_UINT64 => values!(u64, 8),
        _ => Vec::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use flate2::write::ZlibEncoder;
    use flate2::Compression;
    use proptest::prelude::*;
    use std::io::Write;

    /// Writes MAT v5 byte images by hand, in either byte order.
    #[derive(Clone, Copy)]
    struct W {
        big: bool,
    }

    const LE: W = W { big: false };
    const BE: W = W { big: true };

    impl W {
        fn u32(self, v: u32) -> [u8; 4] {
            if self.big {
                v.to_be_bytes()
            } else {
                v.to_le_bytes()
            }
        }

        fn header(self) -> Vec<u8> {
            self.header_text("MATLAB 5.0 MAT-file, Platform: test, Created on: today")
        }

        fn header_text(self, text: &str) -> Vec<u8> {
            let mut h = vec![b' '; 116];
            h[..text.len()].copy_from_slice(text.as_bytes());
            h.extend_from_slice(&[0; 8]);
            if self.big {
                h.extend_from_slice(&[1, 0, b'M', b'I']);
            } else {
                h.extend_from_slice(&[0, 1, b'I', b'M']);
            }
            h
        }

        /// A full-tag element, padded to 8 bytes.
        fn el(self, ty: u32, data: &[u8]) -> Vec<u8> {
            let mut e = self.u32(ty).to_vec();
            e.extend(self.u32(data.len() as u32));
            e.extend_from_slice(data);
            e.resize(e.len().div_ceil(8) * 8, 0);
            e
        }

        /// A small-form element: byte count in the upper 16 bits, data in the last 4 bytes.
        fn small(self, ty: u32, data: &[u8]) -> Vec<u8> {
            assert!(data.len() <= 4);
            let mut e = self.u32(((data.len() as u32) << 16) | ty).to_vec();
            e.extend_from_slice(data);
            e.resize(8, 0);
            e
        }

        /// A miMATRIX; names of up to 4 bytes take the small form, as MATLAB writes them.
        fn matrix(self, flags: u32, dims: &[i32], name: &str, rest: &[Vec<u8>]) -> Vec<u8> {
            let mut body = self.el(MI_UINT32, &[self.u32(flags), self.u32(0)].concat());
            let dim_bytes: Vec<u8> = dims.iter().flat_map(|&d| self.u32(d as u32)).collect();
            body.extend(self.el(MI_INT32, &dim_bytes));
            if name.len() <= 4 {
                body.extend(self.small(MI_INT8, name.as_bytes()));
            } else {
                body.extend(self.el(MI_INT8, name.as_bytes()));
            }
            for part in rest {
                body.extend_from_slice(part);
            }
            self.el(MI_MATRIX, &body)
        }

        /// An miCOMPRESSED element holding `element`, unpadded as MATLAB and scipy write.
        fn compressed(self, element: &[u8]) -> Vec<u8> {
            let mut encoder = ZlibEncoder::new(Vec::new(), Compression::default());
            encoder.write_all(element).unwrap();
            let z = encoder.finish().unwrap();
            let mut e = self.u32(MI_COMPRESSED).to_vec();
            e.extend(self.u32(z.len() as u32));
            e.extend(z);
            e
        }

        fn doubles(self, values: &[f64]) -> Vec<u8> {
            let bytes: Vec<u8> = values
                .iter()
                .flat_map(|v| {
                    if self.big {
                        v.to_be_bytes()
                    } else {
                        v.to_le_bytes()
                    }
                })
                .collect();
            self.el(MI_DOUBLE, &bytes)
        }

        fn singles(self, values: &[f32]) -> Vec<u8> {
            let bytes: Vec<u8> = values
                .iter()
                .flat_map(|v| {
                    if self.big {
                        v.to_be_bytes()
                    } else {
                        v.to_le_bytes()
                    }
                })
                .collect();
            self.el(MI_SINGLE, &bytes)
        }

        fn int16s(self, values: &[i16]) -> Vec<u8> {
            let bytes: Vec<u8> = values
                .iter()
                .flat_map(|v| {
                    if self.big {
                        v.to_be_bytes()
                    } else {
                        v.to_le_bytes()
                    }
                })
                .collect();
            self.el(MI_INT16, &bytes)
        }

        /// The variables of the sample file, one element each.
        fn variables(self) -> Vec<Vec<u8>> {
            // a = [0 1 2; 3 4 5], column-major 0 3 1 4 2 5.
            let a = self.matrix(
                MX_DOUBLE,
                &[2, 3],
                "a",
                &[self.doubles(&[0.0, 3.0, 1.0, 4.0, 2.0, 5.0])],
            );
            // A logical column [1; 0]: uint8 class (9) with the logical flag, small data.
            let mask = self.matrix(
                9 | FLAG_LOGICAL,
                &[2, 1],
                "mask",
                &[self.small(MI_UINT8, &[1, 0])],
            );
            // A uint8 column as BROAD's `movement`, long name in the full form.
            let movement = self.matrix(9, &[3, 1], "movement", &[self.el(MI_UINT8, &[0, 7, 255])]);
            let gain = self.matrix(7, &[1, 3], "gain", &[self.singles(&[0.5, -1.25, 3.0])]);
            // A double array stored compactly as int16, as MATLAB does for small integers.
            let imu_acc = self.matrix(
                MX_DOUBLE,
                &[3, 2],
                "imu_acc",
                &[self.int16s(&[1, -2, 3, 400, -500, 600])],
            );
            let utf16: Vec<u8> = "text"
                .encode_utf16()
                .flat_map(|c| self.u32(c.into())[..2].to_vec())
                .collect();
            let info = self.matrix(MX_CHAR, &[1, 4], "info", &[self.el(MI_UINT16, &utf16)]);
            // A cell holding a nameless double, and a complex pair.
            let inner = self.matrix(MX_DOUBLE, &[1, 1], "", &[self.doubles(&[9.0])]);
            let cell = self.matrix(MX_CELL, &[1, 1], "c", &[inner]);
            let z = self.matrix(
                MX_DOUBLE | FLAG_COMPLEX,
                &[1, 2],
                "z",
                &[self.doubles(&[1.0, 2.0]), self.doubles(&[3.0, 4.0])],
            );
            let rate = self.matrix(
                MX_DOUBLE,
                &[1, 1],
                "sampling_rate",
                &[self.doubles(&[285.5])],
            );
            vec![a, mask, movement, gain, imu_acc, info, cell, z, rate]
        }

        fn sample(self, compress: bool) -> Vec<u8> {
            let mut file = self.header();
            for v in self.variables() {
                if compress {
                    file.extend(self.compressed(&v));
                } else {
                    file.extend(v);
                }
            }
            file
        }
    }

    fn err(bytes: &[u8]) -> String {
        MatFile::from_bytes(bytes, "trial.mat")
            .unwrap_err()
            .to_string()
    }

    #[test]
    fn reads_hand_built_files_compressed_or_not_in_both_byte_orders() {
        for w in [LE, BE] {
            for compress in [false, true] {
                let case = format!("big {} compressed {compress}", w.big);
                let mat = MatFile::from_bytes(&w.sample(compress), "sample.mat").expect(&case);
                let names: Vec<&str> = mat.names().collect();
                assert_eq!(
                    names,
                    [
                        "a",
                        "mask",
                        "movement",
                        "gain",
                        "imu_acc",
                        "info",
                        "c",
                        "z",
                        "sampling_rate"
                    ],
                    "{case}"
                );
                let a = mat.get("a").unwrap();
                assert_eq!(a.dims, [2, 3], "{case}");
                assert_eq!(a.data, [0.0, 3.0, 1.0, 4.0, 2.0, 5.0], "{case}");
                let mask = mat.get("mask").unwrap();
                assert_eq!(
                    (mask.dims.as_slice(), mask.data.as_slice()),
                    (&[2, 1][..], &[1.0, 0.0][..])
                );
                assert_eq!(mat.kind("mask"), Some(VarKind::Logical));
                assert_eq!(
                    mat.get("movement").unwrap().data,
                    [0.0, 7.0, 255.0],
                    "{case}"
                );
                assert_eq!(mat.get("gain").unwrap().data, [0.5, -1.25, 3.0], "{case}");
                let acc = mat.get("imu_acc").unwrap();
                assert_eq!(acc.dims, [3, 2], "{case}");
                assert_eq!(acc.column(1), [400.0, -500.0, 600.0], "{case}");
                assert_eq!(mat.get("sampling_rate").unwrap().data, [285.5], "{case}");
                assert_eq!(mat.arrays().len(), 7, "{case}");
            }
        }
    }

    #[test]
    fn char_and_cell_variables_are_listed_without_data() {
        let mat = MatFile::from_bytes(&LE.sample(true), "sample.mat").unwrap();
        assert!(mat.get("info").is_none());
        assert!(mat.get("c").is_none());
        assert_eq!(mat.kind("info"), Some(VarKind::Char));
        assert_eq!(mat.kind("c"), Some(VarKind::Cell));
        assert_eq!(mat.kind("nothing"), None);
        let skipped: Vec<(&str, VarKind)> = mat.skipped().collect();
        assert_eq!(skipped, [("info", VarKind::Char), ("c", VarKind::Cell)]);
        assert!(!VarKind::Char.is_numeric() && VarKind::Logical.is_numeric());
    }

    #[test]
    fn struct_sparse_and_opaque_variables_are_listed_without_data() {
        let w = LE;
        let mut file = w.header();
        // A struct with one field `x`: field-name length, the names, then the fields.
        let field = w.matrix(MX_DOUBLE, &[1, 1], "", &[w.doubles(&[1.0])]);
        file.extend(w.matrix(
            MX_STRUCT,
            &[1, 1],
            "st",
            &[
                w.small(MI_INT32, &w.u32(32)),
                w.el(MI_INT8, &[b'x'; 32]),
                field,
            ],
        ));
        // A sparse 2x2 with one nonzero: row indices, column starts, values.
        file.extend(w.matrix(
            MX_SPARSE,
            &[2, 2],
            "sp",
            &[
                w.small(MI_INT32, &w.u32(1)),
                w.el(MI_INT32, &[0; 12]),
                w.doubles(&[5.0]),
            ],
        ));
        // An opaque object: flags, then its name with no dimensions before it.
        let mut opaque = w.el(MI_UINT32, &[w.u32(MX_OPAQUE), w.u32(0)].concat());
        opaque.extend(w.small(MI_INT8, b"fh"));
        opaque.extend(w.el(MI_INT8, b"MCOS"));
        file.extend(w.el(MI_MATRIX, &opaque));
        file.extend(w.compressed(&w.matrix(MX_DOUBLE, &[1, 1], "after", &[w.doubles(&[2.0])])));
        let mat = MatFile::from_bytes(&file, "s.mat").unwrap();
        let skipped: Vec<(&str, VarKind)> = mat.skipped().collect();
        assert_eq!(
            skipped,
            [
                ("st", VarKind::Struct),
                ("sp", VarKind::Sparse),
                ("fh", VarKind::Other(17))
            ]
        );
        assert_eq!(mat.get("after").unwrap().data, [2.0]);
    }

    #[test]
    fn complex_arrays_keep_their_real_part() {
        let mat = MatFile::from_bytes(&LE.sample(false), "sample.mat").unwrap();
        assert_eq!(mat.get("z").unwrap().data, [1.0, 2.0]);
        assert_eq!(mat.kind("z"), Some(VarKind::Complex));
        // The imaginary part must be there.
        let w = LE;
        let mut file = w.header();
        file.extend(w.matrix(MX_DOUBLE | FLAG_COMPLEX, &[1, 1], "z", &[w.doubles(&[1.0])]));
        assert_eq!(
            err(&file),
            "trial.mat: byte 192: variable `z`: truncated: the tag of the imaginary part needs 8 \
             bytes, only 0 remain"
        );
    }

    #[test]
    fn every_numeric_data_type_converts() {
        let w = LE;
        // (array class, data type, bytes, value): each class 6 to 15 once.
        let cases: [(u32, u32, Vec<u8>, f64); 10] = [
            (8, MI_INT8, (-128i8).to_le_bytes().to_vec(), -128.0),
            (9, MI_UINT8, 255u8.to_le_bytes().to_vec(), 255.0),
            (10, MI_INT16, (-32768i16).to_le_bytes().to_vec(), -32768.0),
            (11, MI_UINT16, 65535u16.to_le_bytes().to_vec(), 65535.0),
            (12, MI_INT32, (-7i32).to_le_bytes().to_vec(), -7.0),
            (13, MI_UINT32, 4_000_000_000u32.to_le_bytes().to_vec(), 4e9),
            (7, MI_SINGLE, 0.25f32.to_le_bytes().to_vec(), 0.25),
            (6, MI_DOUBLE, 1.0e-300f64.to_le_bytes().to_vec(), 1.0e-300),
            (
                14,
                MI_INT64,
                (-1i64 << 40).to_le_bytes().to_vec(),
                -(2f64.powi(40)),
            ),
            (
                15,
                MI_UINT64,
                (1u64 << 63).to_le_bytes().to_vec(),
                2f64.powi(63),
            ),
        ];
        for (class, ty, bytes, want) in cases {
            let mut file = w.header();
            // Each as the full form, and as the small form where it fits.
            file.extend(w.matrix(class, &[1, 1], "full", &[w.el(ty, &bytes)]));
            if bytes.len() <= 4 {
                file.extend(w.matrix(class, &[1, 1], "sm", &[w.small(ty, &bytes)]));
            }
            let mat = MatFile::from_bytes(&file, "t.mat").unwrap();
            assert_eq!(mat.get("full").unwrap().data, [want], "type {ty}");
            if let Some(small) = mat.get("sm") {
                assert_eq!(small.data, [want], "type {ty}");
            }
        }
    }

    #[test]
    fn accessors_see_the_array_column_major() {
        let a = MatArray {
            name: "a".into(),
            dims: vec![2, 3],
            data: vec![0.0, 3.0, 1.0, 4.0, 2.0, 5.0],
        };
        assert_eq!((a.rows(), a.cols()), (2, 3));
        assert_eq!(a.get(1, 0), 3.0);
        assert_eq!(a.get(0, 2), 2.0);
        assert_eq!(a.column(1), [1.0, 4.0]);
        let cube = MatArray {
            name: "cube".into(),
            dims: vec![2, 2, 2],
            data: (0..8).map(f64::from).collect(),
        };
        assert_eq!((cube.rows(), cube.cols()), (2, 4));
        assert_eq!(cube.column(3), [6.0, 7.0]);
    }

    #[test]
    #[should_panic(expected = "row 2 out of range")]
    fn get_refuses_a_row_past_the_column() {
        let a = MatArray {
            name: "a".into(),
            dims: vec![2, 2],
            data: vec![0.0; 4],
        };
        a.get(2, 0);
    }

    #[test]
    fn count_mismatch_names_file_offset_and_variable() {
        let w = LE;
        let mut file = w.header();
        file.extend(w.matrix(MX_DOUBLE, &[3, 5], "imu_acc", &[w.doubles(&[0.0; 10])]));
        assert_eq!(
            err(&file),
            "trial.mat: byte 184: variable `imu_acc`: the data holds 10 values, the dimensions \
             3x5 need 15"
        );
        // Inside a compressed element: its start, and the offset in the inflated bytes.
        let mut file = w.header();
        file.extend(w.compressed(&w.matrix(
            MX_DOUBLE,
            &[3, 5],
            "imu_acc",
            &[w.doubles(&[0.0; 10])],
        )));
        assert_eq!(
            err(&file),
            "trial.mat: byte 128, inflated byte 56: variable `imu_acc`: the data holds 10 \
             values, the dimensions 3x5 need 15"
        );
    }

    #[test]
    fn malformed_elements_are_explained() {
        let w = LE;
        let mut file = w.header();
        file.extend(w.matrix(MX_DOUBLE, &[2, -1], "neg", &[w.doubles(&[])]));
        assert_eq!(
            err(&file),
            "trial.mat: byte 152: variable `neg`: dimension 2 is negative (-1)"
        );
        let mut file = w.header();
        file.extend(w.matrix(MX_DOUBLE, &[1, 1], "txt", &[w.el(16, b"abcdefgh")]));
        assert_eq!(
            err(&file),
            "trial.mat: byte 176: variable `txt`: the real part is utf8, not a numeric type"
        );
        let mut file = w.header();
        file.extend(w.matrix(MX_DOUBLE, &[1, 1], "odd", &[w.el(MI_DOUBLE, &[0; 12])]));
        assert_eq!(
            err(&file),
            "trial.mat: byte 176: variable `odd`: the real part is 12 bytes, not a whole number \
             of double values (8 bytes each)"
        );
        let mut file = w.header();
        file.extend(w.matrix(
            MX_DOUBLE,
            &[1 << 30, 1 << 30, 1 << 30],
            "huge",
            &[w.doubles(&[])],
        ));
        assert_eq!(
            err(&file),
            "trial.mat: byte 184: variable `huge`: the dimensions 1073741824x1073741824x1073741824 are too large"
        );
        let mut file = w.header();
        file.extend(w.u32(7 << 16 | MI_INT8));
        file.extend([0; 4]);
        assert_eq!(
            err(&file),
            "trial.mat: byte 128: a variable: a small element holds at most 4 bytes, this one claims 7"
        );
    }

    #[test]
    fn truncated_files_say_what_is_cut() {
        let file = LE.sample(false);
        assert_eq!(
            err(&file[..50]),
            "trial.mat: byte 0: truncated: the header needs 128 bytes, only 50 remain"
        );
        assert_eq!(
            err(&file[..132]),
            "trial.mat: byte 128: truncated: the tag of a variable needs 8 bytes, only 4 remain"
        );
        // The first variable `a` is 104 bytes: 8 of tag, 96 of subelements.
        assert_eq!(
            err(&file[..200]),
            "trial.mat: byte 128: truncated: a variable needs 96 bytes, only 64 remain"
        );
        let zipped = LE.sample(true);
        let last = LE.compressed(&LE.variables()[8]);
        let (start, size) = (zipped.len() - last.len(), last.len() - 8);
        assert_eq!(
            err(&zipped[..zipped.len() - 3]),
            format!(
                "trial.mat: byte {start}: truncated: a variable needs {size} bytes, only {} \
                 remain",
                size - 3
            )
        );
        // A compressed element whose stream is cut short inside.
        let mut file = LE.header();
        let whole = LE.compressed(&LE.variables()[0]);
        let mut short = whole[..whole.len() - 20].to_vec();
        let size = LE.u32(short.len() as u32 - 8);
        short[4..8].copy_from_slice(&size);
        file.extend(short);
        assert_eq!(
            err(&file),
            "trial.mat: byte 128: compressed element: the zlib stream is corrupt or cut short \
             (incomplete deflate stream)"
        );
    }

    #[test]
    fn v73_files_are_refused_with_advice() {
        let message = "trial.mat: is a MATLAB v7.3 (HDF5) file: save it with -v7, or give a CSV";
        let mut file = vec![0u8; 1024];
        let header = LE.header_text(
            "MATLAB 7.3 MAT-file, Platform: GLNXA64, Created on: today HDF5 schema 1.00 .",
        );
        file[..128].copy_from_slice(&header);
        file[124..128].copy_from_slice(&[0, 2, b'I', b'M']);
        file[512..520].copy_from_slice(b"\x89HDF\r\n\x1a\n");
        assert_eq!(err(&file), message);
        // Either sign is enough: the HDF5 superblock behind a header without a v5 version.
        file[..10].copy_from_slice(b"something ");
        assert_eq!(err(&file), message);
        assert!(!MatFile::is_mat_v5(&file));
    }

    #[test]
    fn other_files_are_not_mat_files() {
        assert_eq!(
            err(b""),
            "trial.mat: not a MATLAB v5 MAT-file: the file is empty"
        );
        assert_eq!(
            err(b"t,theta\n0,1\n"),
            "trial.mat: not a MATLAB v5 MAT-file: 12 bytes, shorter than the 128-byte header"
        );
        let csv = "t,theta\n".repeat(40);
        assert_eq!(
            err(csv.as_bytes()),
            "trial.mat: not a MATLAB v5 MAT-file: no \"MATLAB 5.0 MAT-file\" header with version \
             0x0100 at byte 124"
        );
        let mut bad = LE.header();
        bad[124] = 7;
        assert_eq!(
            err(&bad),
            "trial.mat: byte 124: the version and endian word is 07 01 49 4d, not 01 00 with \
             \"IM\" or \"MI\""
        );
        assert_eq!(
            err(b"\x89HDF\r\n\x1a\n and more"),
            "trial.mat: not a MATLAB v5 MAT-file: it is an HDF5 file without the MAT-file header"
        );
    }

    #[test]
    fn is_mat_v5_sniffs_the_header() {
        assert!(MatFile::is_mat_v5(&LE.header()));
        assert!(MatFile::is_mat_v5(&BE.header()));
        assert!(MatFile::is_mat_v5(&LE.sample(true)));
        assert!(!MatFile::is_mat_v5(&LE.header()[..127]));
        assert!(!MatFile::is_mat_v5(&LE.header_text("Octave binary")));
        assert!(!MatFile::is_mat_v5(b"t,theta\n0,1\n"));
        let mut v73 = LE.header();
        v73[124..126].copy_from_slice(&[0, 2]);
        assert!(!MatFile::is_mat_v5(&v73));
    }

    #[test]
    fn header_only_and_zero_padded_files_have_no_variables() {
        let mat = MatFile::from_bytes(&LE.header(), "empty.mat").unwrap();
        assert_eq!(mat.names().count(), 0);
        let mut padded = LE.sample(true);
        padded.extend([0; 5]);
        assert_eq!(
            MatFile::from_bytes(&padded, "p.mat")
                .unwrap()
                .arrays()
                .len(),
            7
        );
        assert_eq!(mat.origin(), "empty.mat");
    }

    #[test]
    fn inflating_past_the_limit_is_an_error() {
        let w = LE;
        let mut file = w.header();
        file.extend(w.compressed(&w.matrix(
            MX_DOUBLE,
            &[1, 100],
            "big",
            &[w.doubles(&[1.0; 100])],
        )));
        let message = parse(&file, "z.mat", 256).unwrap_err().to_string();
        assert_eq!(
            message,
            "z.mat: byte 128: compressed element: the element inside declares 856 bytes, more \
             than the 256 bytes a compressed element may inflate to"
        );
        assert!(parse(&file, "z.mat", 856).is_ok());
        // A tag claiming 4 GiB inflates nothing: refused from the tag alone.
        let mut file = w.header();
        file.extend(w.compressed(&[w.u32(MI_MATRIX), w.u32(u32::MAX)].concat()));
        assert_eq!(
            err(&file),
            "trial.mat: byte 128: compressed element: the element inside declares 4294967304 \
             bytes, more than the 1 GiB a compressed element may inflate to"
        );
    }

    #[test]
    fn corrupt_zlib_is_an_error() {
        let mut file = LE.header();
        let mut z = LE.compressed(&LE.variables()[0]);
        for b in &mut z[10..20] {
            *b ^= 0x55;
        }
        file.extend(z);
        let message = err(&file);
        assert!(
            message
                .starts_with("trial.mat: byte 128: compressed element: the zlib stream is corrupt"),
            "{message}"
        );
    }

    #[test]
    fn absurd_sizes_fail_without_allocating() {
        let w = LE;
        let mut file = w.header();
        file.extend(w.u32(MI_MATRIX));
        file.extend(w.u32(u32::MAX));
        file.extend([0; 16]);
        assert_eq!(
            err(&file),
            "trial.mat: byte 128: truncated: a variable needs 4294967295 bytes, only 16 remain"
        );
    }

    #[test]
    fn every_truncation_fails_cleanly_or_reads_a_prefix() {
        for w in [LE, BE] {
            for compress in [false, true] {
                let full = w.sample(compress);
                let all: Vec<String> = MatFile::from_bytes(&full, "f.mat")
                    .unwrap()
                    .names()
                    .map(str::to_string)
                    .collect();
                for len in 0..full.len() {
                    match MatFile::from_bytes(&full[..len], "f.mat") {
                        Ok(mat) => {
                            let names: Vec<&str> = mat.names().collect();
                            assert!(
                                names.len() < all.len()
                                    && all.starts_with(
                                        &names.iter().map(|n| n.to_string()).collect::<Vec<_>>()
                                    ),
                                "len {len}"
                            );
                        }
                        Err(e) => assert!(e.to_string().starts_with("f.mat: "), "len {len}: {e}"),
                    }
                }
            }
        }
    }

    #[test]
    fn open_names_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("trial.mat");
        std::fs::write(&path, LE.sample(true)).unwrap();
        let mat = MatFile::open(&path).unwrap();
        assert_eq!(mat.get("a").unwrap().get(1, 2), 5.0);
        assert_eq!(mat.origin(), path.display().to_string());
        let missing = dir.path().join("missing.mat");
        let message = MatFile::open(&missing).unwrap_err().to_string();
        assert!(
            message.starts_with(&format!("{}: cannot read: ", missing.display())),
            "{message}"
        );
    }

    proptest! {
        #[test]
        fn mutated_files_never_panic(
            compress in any::<bool>(),
            big in any::<bool>(),
            edits in proptest::collection::vec((any::<usize>(), any::<u8>()), 1..12),
        ) {
            let mut file = W { big }.sample(compress);
            for (at, value) in edits {
                let i = HEADER_LEN + at % (file.len() - HEADER_LEN);
                file[i] = value;
            }
            if let Err(e) = MatFile::from_bytes(&file, "m.mat") {
                prop_assert!(e.to_string().starts_with("m.mat: "));
            }
        }

        #[test]
        fn random_bodies_never_panic(body in proptest::collection::vec(any::<u8>(), 0..400)) {
            let mut file = LE.header();
            file.extend(body);
            let _ = MatFile::from_bytes(&file, "r.mat");
        }
    }
}

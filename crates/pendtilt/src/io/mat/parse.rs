//! The level-5 element parser: the header, the tagged elements (plain or compressed), the
//! matrices inside them, and the conversion of their numbers.
use super::*;

pub(super) fn endian_of(bytes: &[u8]) -> Option<Endian> {
    match bytes.get(124..HEADER_LEN)? {
        [0x00, 0x01, b'I', b'M'] => Some(Endian::Little),
        [0x01, 0x00, b'M', b'I'] => Some(Endian::Big),
        _ => None,
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Endian {
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
pub(super) fn parse(bytes: &[u8], origin: &str, limit: u64) -> Result<MatFile, MatError> {
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

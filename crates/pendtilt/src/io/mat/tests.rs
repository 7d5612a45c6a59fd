//! The MAT reader against hand-built files: every type, both byte orders, compression,
//! and every way a file can be cut or corrupt.
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
    file.extend(w.compressed(&w.matrix(MX_DOUBLE, &[3, 5], "imu_acc", &[w.doubles(&[0.0; 10])])));
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
    file.extend(w.compressed(&w.matrix(MX_DOUBLE, &[1, 100], "big", &[w.doubles(&[1.0; 100])])));
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
        message.starts_with("trial.mat: byte 128: compressed element: the zlib stream is corrupt"),
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

//! The header: the time column and the others missing, misnamed, duplicated, mapped,
//! quoted, in capitals, carrying units, or met again in the middle of the log.
use crate::common::log_reader::{fails, ok, open, read_all};
use pendtilt::io::{Column, LogErrorKind, ReaderOptions, TimeUnit, WarningKind};

#[test]
fn missing_time_column_is_an_error_with_a_hint() {
    let e = fails("time,phi\n0,1\n", ReaderOptions::default());
    assert!(matches!(*e.kind, LogErrorKind::MissingTime { .. }), "{e}");
    let msg = e.to_string();
    assert!(msg.starts_with("log.csv:1: no `t` column"), "{msg}");
    assert!(
        msg.contains("time, phi") && msg.contains("--map t="),
        "{msg}"
    );

    let e = fails("0,0.1,0.2\n0.001,0.1,0.2\n", ReaderOptions::default());
    assert!(e.to_string().contains("looks like data"), "{e}");

    let e = fails("T,phi\n0,1\n", ReaderOptions::default());
    assert!(e.to_string().contains("did you mean `T`"), "{e}");

    let e = fails("t;phi;gyro\n0;1;2\n", ReaderOptions::default());
    assert!(e.to_string().contains("separated by `;`"), "{e}");
    // The fix, not only the question (earlier: the CLI has no delimiter option).
    assert!(
        e.to_string().contains(
            "the log must be comma-separated: convert it with `tr ';' ',' < log.csv > \
             log_commas.csv` (numbers with a decimal comma, `0,5`: `sed 's/,/./g'` first)"
        ),
        "{e}"
    );
    let e = fails("t\tphi\n0\t1\n", ReaderOptions::default());
    assert!(e.to_string().contains("separated by tabs"), "{e}");
    assert!(e.to_string().contains("`tr '\\t' ','"), "{e}");
    let semicolon = ReaderOptions {
        delimiter: b';',
        ..ReaderOptions::default()
    };
    let (records, _, error) = read_all("t;phi;gyro\n0;1;2\n", semicolon);
    assert!(error.is_none());
    assert_eq!(records[0].sample.gyro, 2.0);
}

#[test]
fn a_time_column_under_another_name_is_named_in_the_hint() {
    // A new user's `time` got `--map t=NAME`, the fix left to guess.
    let hint = |header: &str| {
        let e = fails(
            &format!("{header},phi,gyro\n0,1,2\n"),
            ReaderOptions::default(),
        );
        assert!(matches!(*e.kind, LogErrorKind::MissingTime { .. }), "{e}");
        e.to_string()
    };
    for (header, fix) in [
        ("time", "did you mean `time`? (--map t=time)"),
        ("timestamp", "did you mean `timestamp`? (--map t=timestamp)"),
        ("Time", "did you mean `Time`? (--map t=Time)"),
        ("Time [s]", "did you mean `Time [s]`? (--map 't=Time [s]')"),
        ("t_s", "(--map t=t_s)"),
        ("seconds", "(--map t=seconds)"),
        // A smaller unit in the name: its --time-unit too.
        ("time_ms", "(--map t=time_ms --time-unit ms)"),
        (
            "Timestamp (us)",
            "(--map 't=Timestamp (us)' --time-unit us)",
        ),
    ] {
        let msg = hint(header);
        assert!(msg.contains(fix), "{header}: {msg}");
    }
    // Names that are not time: the general hint, never a guess.
    for header in ["temp", "t_env", "theta_ref"] {
        let msg = hint(header);
        assert!(
            msg.contains("name the time column with --map t=NAME"),
            "{header}: {msg}"
        );
    }
    // With --time-unit already given, it is not asked for again.
    let ms = ReaderOptions {
        time_unit: Some(TimeUnit::Ms),
        ..ReaderOptions::default()
    };
    let e = fails("time_ms,phi\n0,1\n", ms);
    assert!(e.to_string().contains("(--map t=time_ms)"), "{e}");
}

#[test]
fn missing_optional_columns_are_reported_not_errors() {
    let text = "t,phi,temp\n0,0.1,20\n";
    let reader = open(text, ReaderOptions::default()).unwrap();
    let cols = reader.columns();
    assert!(cols.has(Column::Phi) && !cols.has(Column::Gyro));
    assert_eq!(
        cols.missing(),
        vec![Column::Gyro, Column::Ax, Column::Ay, Column::Theta]
    );
    assert_eq!(cols.ignored, vec!["temp".to_string()]);
    assert_eq!(
        cols.to_string(),
        "columns: t, phi; missing: gyro, ax, ay, theta; ignored: temp"
    );
    let (records, _) = ok(text);
    assert!(records[0].sample.gyro.is_nan() && records[0].theta.is_none());
}

#[test]
fn case_mismatch_is_suggested_never_guessed() {
    let reader = open("t,Phi\n0,1\n", ReaderOptions::default()).unwrap();
    assert!(!reader.columns().has(Column::Phi));
    let s = reader.columns().to_string();
    assert!(s.contains("--map phi=Phi"), "{s}");
}

#[test]
fn duplicate_used_column_is_an_error_naming_both_fields() {
    let e = fails("t,phi,gyro,phi\n0,1,2,3\n", ReaderOptions::default());
    assert!(
        matches!(*e.kind, LogErrorKind::DuplicateColumn { first: 2, .. }),
        "{e}"
    );
    assert_eq!(e.line, Some(1));
    assert_eq!(e.column.as_ref().unwrap().position, 4);
    let msg = e.to_string();
    assert!(
        msg.starts_with("log.csv:1: column 4 (`phi`): duplicate column"),
        "{msg}"
    );
    assert!(msg.contains("field 2"), "{msg}");
}

#[test]
fn duplicate_ignored_column_is_a_warning() {
    let (records, warnings) = ok("t,temp,temp\n0,1,2\n");
    assert_eq!(records.len(), 1);
    assert_eq!(warnings.len(), 1);
    assert_eq!(warnings[0].kind, WarningKind::DuplicateIgnoredColumn);
    assert!(
        warnings[0]
            .to_string()
            .starts_with("log.csv:1: column `temp`"),
        "{}",
        warnings[0]
    );
}

#[test]
fn too_many_fields_is_an_error_but_a_trailing_comma_is_not() {
    let e = fails("t,phi\n0,1\n0.001,1,7\n", ReaderOptions::default());
    assert!(matches!(
        *e.kind,
        LogErrorKind::TooManyFields {
            found: 3,
            expected: 2
        }
    ));
    assert_eq!(e.to_string(), "log.csv:3: 3 fields, the header has 2");
    let (records, _) = ok("t,phi\n0,1,\n");
    assert_eq!(records[0].sample.phi, 1.0);
}

#[test]
fn column_map_reads_other_names() {
    let text = "time_s,enc_angle,gz,phi\n0,0.5,0.25,9\n";
    let options = ReaderOptions {
        map: "t=time_s,phi=enc_angle,gyro=gz".parse().unwrap(),
        ..ReaderOptions::default()
    };
    let reader = open(text, options.clone()).unwrap();
    let cols = reader.columns();
    assert_eq!(
        cols.status(Column::Phi).source.as_deref(),
        Some("enc_angle")
    );
    assert!(cols.status(Column::Phi).mapped);
    assert_eq!(cols.ignored, vec!["phi".to_string()]);
    assert!(cols
        .to_string()
        .starts_with("columns: t <- time_s, phi <- enc_angle, gyro <- gz"));
    let (records, _, error) = read_all(text, options);
    assert!(error.is_none());
    assert_eq!(
        (records[0].t, records[0].sample.phi, records[0].sample.gyro),
        (0.0, 0.5, 0.25)
    );
}

#[test]
fn a_header_column_mapped_elsewhere_does_not_also_feed_its_own_name() {
    let options = ReaderOptions {
        map: "theta=phi".parse().unwrap(),
        ..ReaderOptions::default()
    };
    let reader = open("t,phi\n0,1\n", options).unwrap();
    assert!(reader.columns().has(Column::Theta));
    assert!(!reader.columns().has(Column::Phi));
}

#[test]
fn mapping_onto_an_absent_column_is_an_error() {
    let options = ReaderOptions {
        map: "phi=enc".parse().unwrap(),
        ..ReaderOptions::default()
    };
    let e = fails("t,encoder\n0,1\n", options);
    assert!(matches!(*e.kind, LogErrorKind::MappedSourceMissing { .. }));
    let msg = e.to_string();
    assert!(
        msg.starts_with("log.csv:1: --map phi=enc: no column `enc`"),
        "{msg}"
    );
    assert!(msg.contains("t, encoder"), "{msg}");
}

#[test]
fn quoted_header_and_cells() {
    let (records, _) = ok("\"t\",\"phi\"\n\"0\",\"0.5\"\n");
    assert_eq!(records[0].sample.phi, 0.5);
    let e = fails("t,phi\n0,\"0.5\n", ReaderOptions::default());
    assert!(matches!(*e.kind, LogErrorKind::UnterminatedQuote));
    assert_eq!(
        e.to_string(),
        "log.csv:2: column 2 (`phi`): a quoted field is not closed on its line"
    );
}

#[test]
fn a_header_line_in_the_middle_is_named_as_one() {
    // Two logs joined, or a logger restarted into the same stream. Before: `column 1
    // (`t`): not a number: `t``, which points at a cell, not at what happened.
    let e = fails(
        "# log\nt,phi\n0,1\n0.001,1\n# restart\nt,phi\n0,1\n",
        ReaderOptions::default(),
    );
    assert_eq!(
        e.to_string(),
        "log.csv:6: the header again (as on line 2): two logs joined, or a logger that \
         restarted into the same file or stream? remove this line, or split the log here"
    );
    let e = fails("t,phi\n0,1\nphi,t\n", ReaderOptions::default());
    assert!(
        e.to_string()
            .starts_with("log.csv:3: a new header (phi, t; line 1 has t, phi): two logs joined"),
        "{e}"
    );
    // A word in a data cell is still a cell that is not a number.
    let e = fails("t,phi\n0,1\n0.001,t\n", ReaderOptions::default());
    assert_eq!(
        e.to_string(),
        "log.csv:3: column 2 (`phi`): not a number: `t`"
    );
}

#[test]
fn a_header_that_names_the_other_unit_is_warned_about_on_line_1() {
    let read = unit_warnings;
    // Degrees in the name, read as radians: file, line 1, the column, the fix.
    let w = read(
        "t,phi (deg),gyro[deg/s],ax,ay",
        "phi=phi (deg),gyro=gyro[deg/s]",
        "",
    );
    assert_eq!(
        w,
        [
            "log.csv:1: column `phi (deg)` (phi): its name says degrees, and it is read in \
             radians (no --deg): read it with --deg phi",
            "log.csv:1: column `gyro[deg/s]` (gyro): its name says deg/s, and it is read in \
             rad/s (no --deg): read it with --deg gyro"
        ]
    );
    let w = read("t,phi,gyro_deg_s,ax,ay", "gyro=gyro_deg_s", "");
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(w[0].ends_with("read it with --deg gyro"), "{w:?}");
    for h in ["gyro_dps", "gyro (°/s)", "Gyro_Degrees"] {
        assert_eq!(
            read(&format!("t,phi,{h},ax,ay"), &format!("gyro={h}"), "").len(),
            1,
            "{h}"
        );
    }
    // Radians in the name, read with --deg.
    let w = read(
        "t,phi_rad,gyro[rad/s],ax,ay",
        "phi=phi_rad,gyro=gyro[rad/s]",
        "phi,gyro",
    );
    assert_eq!(
        w[1],
        "log.csv:1: column `gyro[rad/s]` (gyro): its name says rad/s, and it is read in deg/s \
         (--deg): leave gyro out of --deg"
    );
    // Right as read, or saying nothing about units: not a word.
    for (header, map, deg) in [
        (
            "t,phi (deg),gyro[deg/s],ax,ay",
            "phi=phi (deg),gyro=gyro[deg/s]",
            "phi,gyro",
        ),
        (
            "t,phi_rad,gyro[rad/s],ax,ay",
            "phi=phi_rad,gyro=gyro[rad/s]",
            "",
        ),
        ("t,phi,gyro,ax,ay", "", ""),
        ("t,phi,gyro,ax,ay", "", "phi,gyro"),
        (
            "t,enc_angle,gradient,ax,ay",
            "phi=enc_angle,gyro=gradient",
            "",
        ),
        ("t,phi,radius_gyro,ax,ay", "gyro=radius_gyro", "gyro"),
        ("t,phi,gyro,ax_deg,ay", "ax=ax_deg", ""),
    ] {
        assert!(read(header, map, deg).is_empty(), "{header} {map} {deg}");
    }
}

/// The unit warnings of a short log with `header`, read with `--map map` and `--deg deg`
/// (empty: none).
fn unit_warnings(header: &str, map: &str, deg: &str) -> Vec<String> {
    use pendtilt::io::{ColumnMap, DegreeColumns};
    let text = format!("{header}\n0,0.01,0.02,0,9.8\n0.001,0.01,0.02,0,9.8\n");
    let options = ReaderOptions {
        map: if map.is_empty() {
            ColumnMap::new()
        } else {
            map.parse().unwrap()
        },
        degrees: if deg.is_empty() {
            DegreeColumns::none()
        } else {
            deg.parse().unwrap()
        },
        ..ReaderOptions::default()
    };
    let (records, warnings, error) = read_all(&text, options);
    assert!(error.is_none() && records.len() == 2, "{error:?}");
    warnings
        .iter()
        .filter(|w| w.kind == WarningKind::UnitMismatch)
        .map(|w| w.to_string())
        .collect()
}

#[test]
fn a_missing_column_whose_name_carries_a_unit_is_suggested_with_the_unit_option() {
    let text = "t,phi_deg,gyro[rad/s],ax,ay\n0,1,0.02,0,9.8\n";
    let r = open(text, ReaderOptions::default()).unwrap();
    let c = r.columns().to_string();
    assert!(
        c.contains("phi (the header has `phi_deg`: --map phi=phi_deg --deg phi?)")
            && c.contains("gyro (the header has `gyro[rad/s]`: --map 'gyro=gyro[rad/s]'?)"),
        "{c}"
    );
}

/// A units line under the header and a logger's marker of a missing reading (`NA`, `-`,
/// `null`, ...) are still errors (nothing is guessed), but say what the text likely is
/// and what to do, in the planar and the 3-D reader (earlier: `not a number: `s`` and
/// `not a number: `NA`` alone). A units line made a comment, as said, reads.
#[test]
fn a_units_line_or_a_missing_marker_says_what_to_do() {
    let units = "t,phi,gyro\ns,rad,rad/s\n0,0.1,0.2\n0.001,0.1,0.2\n";
    let e = fails(units, ReaderOptions::default()).to_string();
    assert_eq!(
        e,
        "log.csv:2: column 1 (`t`): not a number: `s`; the first row under the header is \
         text: a units line? make it a comment with `#` (`sed -i '2s/^/#/' log.csv`) or \
         delete it"
    );
    let (records, _) = ok(&units.replace("\ns,rad", "\n#s,rad"));
    assert_eq!(records.len(), 2);
    for marker in ["NA", "N/A", "null", "None", "-", "?"] {
        let text = format!("t,phi,gyro\n0,0.1,0.2\n0.001,{marker},0.2\n");
        let e = fails(&text, ReaderOptions::default()).to_string();
        assert_eq!(
            e,
            format!(
                "log.csv:3: column 2 (`phi`): not a number: `{marker}`; if `{marker}` marks a \
                 missing reading, leave the cell empty (or write nan): an empty cell reads as \
                 missing, and the estimators hold and flag the sample"
            )
        );
    }
    // A word in a later row is no units line; a plain typo gets no hint.
    let e = fails("t,phi\n0,0.1\nabc,def\n", ReaderOptions::default()).to_string();
    assert_eq!(e, "log.csv:3: column 1 (`t`): not a number: `abc`");
    // The 3-D reader says the same.
    let head = "t,phi_x,phi_y,gyro_x,gyro_y,gyro_z,ax,ay,az";
    let three = |body: &str| {
        pendtilt::io::Log3dReader::new(format!("{head}\n{body}").as_bytes(), "log.csv")
            .unwrap()
            .collect::<Result<Vec<_>, _>>()
            .unwrap_err()
            .to_string()
    };
    let e = three("s,rad,rad,rad/s,rad/s,rad/s,m/s^2,m/s^2,m/s^2\n0,0,0,0,0,0,0,0,9.8\n");
    assert!(
        e.ends_with(
            "a units line? make it a comment with `#` (`sed -i '2s/^/#/' log.csv`) or delete it"
        ),
        "{e}"
    );
    let e = three("0,0,0,0,0,0,0,0,9.8\n0.001,0,0,NA,0,0,0,0,9.8\n");
    assert!(
        e.starts_with(
            "log.csv:3: column 4 (`gyro_x`): not a number: `NA`; if `NA` marks a missing reading"
        ),
        "{e}"
    );
}

/// A header in capitals: the planar hint gives the whole `--map` at once, and following
/// it reads the log; a 3-D header in capitals is named as one (earlier: `did you mean
/// `T`? (--map t=T)`, one column per round; on a 3-D log in capitals that hint led to
/// `--map t=T,ax=AX,ay=AY`, which ran the planar `accel` on the 3-D axes, exit 0).
#[test]
fn a_header_in_capitals_gets_one_whole_map_and_a_3d_one_is_named() {
    let upper = "T,PHI,GYRO,AX,AY\n0,0.1,0.2,0.3,9.8\n0.001,0.1,0.2,0.3,9.8\n";
    let e = fails(upper, ReaderOptions::default()).to_string();
    assert!(
        e.ends_with("did you mean `T`? (--map t=T,phi=PHI,gyro=GYRO,ax=AX,ay=AY)"),
        "{e}"
    );
    let map = "t=T,phi=PHI,gyro=GYRO,ax=AX,ay=AY"
        .parse::<pendtilt::io::ColumnMap>()
        .unwrap();
    let (records, _, error) = read_all(
        upper,
        ReaderOptions {
            map,
            ..ReaderOptions::default()
        },
    );
    assert!(error.is_none(), "{error:?}");
    assert_eq!((records.len(), records[1].sample.ay), (2, 9.8));

    let upper3d = "T,PHI_X,PHI_Y,GYRO_X,GYRO_Y,GYRO_Z,AX,AY,AZ\n0,0,0,0,0,0,0,0,9.8\n";
    let want = "log.csv:1: a 3-D log (MODEL.md 7.6) with its column names in capitals: its \
                columns are read by their names in lower case (t, phi_x, phi_y, gyro_x, ...); \
                write the header in lower case: `sed -i '1s/.*/\\L&/' log.csv`";
    let e = fails(upper3d, ReaderOptions::default()).to_string();
    assert!(e.starts_with(want), "{e}");
    let map = "t=T,ax=AX,ay=AY"
        .parse::<pendtilt::io::ColumnMap>()
        .unwrap();
    let options = ReaderOptions {
        map,
        ..ReaderOptions::default()
    };
    let e = fails(upper3d, options).to_string();
    assert!(e.starts_with(want), "{e}");
}

/// A header with a trailing comma (every row too) reads as without it, and the report of
/// the columns names the empty field instead of an empty name (earlier: `ignored: `).
#[test]
fn a_trailing_comma_on_every_line_names_its_unnamed_field() {
    let text = "t,phi,\n0,0.1,\n0.001,0.2,\n";
    let reader = open(text, ReaderOptions::default()).unwrap();
    assert_eq!(
        reader.columns().to_string(),
        "columns: t, phi; missing: gyro, ax, ay, theta; ignored: (unnamed field 3)"
    );
    let (records, warnings) = ok(text);
    assert_eq!(records.len(), 2);
    assert!(warnings.is_empty(), "{warnings:?}");
}

/// Each column's sensor is the one whose planar columns name it in the sensor table.
#[test]
fn each_columns_sensor_is_the_tables() {
    use pendtilt::io::Column;
    use pendtilt::sensors::Sensor;
    for c in Column::ALL {
        let by_table =
            (Sensor::ALL.into_iter()).find(|s| s.spec().planar_columns.contains(&c.name()));
        assert_eq!(c.sensor(), by_table, "{c}");
    }
    assert!(Column::provides(Sensor::Accel, |c| c != Column::T));
    assert!(!Column::provides(Sensor::Accel, |c| c != Column::Ay));
}

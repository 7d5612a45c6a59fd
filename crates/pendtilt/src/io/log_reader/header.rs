//! The header of a log: the names, which field each contract column is, the duplicates.
use super::*;

impl<R: BufRead> LogReader<R> {
    /// Reads the header line and resolves the contract columns: the names, then which
    /// field feeds each column, then the duplicate check, then the scales.
    pub(super) fn read_header(&mut self) -> Result<(), LogError> {
        self.read_names()?;
        let listing = self.header.join(", ");
        let statuses = self.resolve_columns(&listing)?;
        if statuses[Column::T.index()].position.is_none() {
            return Err(self.missing_time(&statuses, listing));
        }
        self.refuse_3d(&statuses, &listing)?;
        let used: Vec<usize> = statuses.iter().filter_map(|s| s.position).collect();
        self.check_duplicates(&used)?;
        if let Some(u) = self.options.time_unit {
            self.scale[Column::T.index()] = u.seconds();
        }
        if let Some(u) = self.options.accel_unit {
            for c in [Column::Ax, Column::Ay] {
                self.scale[c.index()] = u.metres_per_second_squared();
            }
        }
        for s in &statuses {
            self.positions[s.column.index()] = s.position;
            if s.degrees {
                self.scale[s.column.index()] = std::f64::consts::PI / 180.0;
            }
        }
        // --negate: the sign, on top of the unit.
        for c in Column::ALL {
            if self.options.negate.contains(c) {
                self.scale[c.index()] = -self.scale[c.index()];
            }
        }
        self.report = ColumnReport {
            ignored: self
                .header
                .iter()
                .enumerate()
                .filter(|(i, _)| !used.contains(i))
                // A trailing comma's field has no name: say which field it is.
                .map(|(i, h)| {
                    if h.is_empty() {
                        format!("(unnamed field {})", i + 1)
                    } else {
                        h.clone()
                    }
                })
                .collect(),
            columns: statuses,
        };
        Ok(())
    }

    /// Reads the header line into `self.header` (an error for an empty file, UTF-16 or
    /// invalid UTF-8).
    fn read_names(&mut self) -> Result<(), LogError> {
        if !self.next_line()? {
            return Err(self.error(None, None, LogErrorKind::Empty));
        }
        if self.lines.line() == 1
            && (self.lines.bytes().starts_with(b"\xFF\xFE")
                || self.lines.bytes().starts_with(b"\xFE\xFF"))
        {
            return Err(self.error(Some(1), None, LogErrorKind::Utf16));
        }
        self.split()?;
        self.header_line = self.lines.line();
        let quoted = self.lines.bytes().contains(&b'"');
        let mut header = Vec::with_capacity(self.lines.ranges().len());
        for k in 0..self.lines.field_count() {
            let (a, b) = self.lines.ranges()[k];
            let Ok(name) = std::str::from_utf8(&self.lines.bytes()[a..b]) else {
                let line = Some(self.lines.line());
                return Err(self.error(line, None, LogErrorKind::InvalidUtf8));
            };
            header.push(if quoted {
                unquote(name)
            } else {
                name.to_string()
            });
        }
        self.header = header;
        Ok(())
    }

    /// Which header field feeds each contract column (in [`Column::ALL`] order): the
    /// mapped one, else its own name unless that header column is mapped onto another
    /// contract column. An error for a `--map` source not in the header (`listing`).
    fn resolve_columns(&mut self, listing: &str) -> Result<Vec<ColumnStatus>, LogError> {
        let mapped_sources: Vec<String> = Column::ALL
            .into_iter()
            .filter_map(|c| self.options.map.source(c).map(String::from))
            .collect();
        let mut statuses = Vec::with_capacity(6);
        for column in Column::ALL {
            let (source, mapped) = match self.options.map.source(column) {
                Some(s) => (Some(s.to_string()), true),
                None if mapped_sources.iter().any(|m| m == column.name()) => (None, false),
                None => (Some(column.name().to_string()), false),
            };
            let position = source
                .as_deref()
                .and_then(|s| self.header.iter().position(|h| h == s));
            if mapped && position.is_none() {
                let line = Some(self.lines.line());
                return Err(self.error(
                    line,
                    None,
                    LogErrorKind::MappedSourceMissing {
                        column: column.name().to_string(),
                        source_name: source.unwrap_or_default(),
                        header: listing.to_string(),
                    },
                ));
            }
            let suggestion = if position.is_none() {
                self.header
                    .iter()
                    .find(|h| h.trim().eq_ignore_ascii_case(column.name()))
                    .cloned()
                    .or_else(|| unit_named_suggestion(column, &self.header))
                    .or_else(|| {
                        (column == Column::T)
                            .then(|| time_named_suggestion(&self.header))
                            .flatten()
                    })
            } else {
                None
            };
            let degrees = self.options.degrees.contains(column);
            if let Some(p) = position {
                let name = self.header[p].clone();
                if let Some(message) = header_unit_warning(column, &name, degrees) {
                    self.warn(WarningKind::UnitMismatch, Some(column), Some(name), message);
                }
            }
            statuses.push(ColumnStatus {
                column,
                source: position.and(source),
                position,
                mapped,
                degrees,
                suggestion,
            });
        }

        Ok(statuses)
    }

    /// A header with the encoder or gyro columns of a 3-D log (MODEL.md 7.6) and neither
    /// `phi` nor `gyro` is a 3-D log, complete or not: read as planar, only `accel` would
    /// run, on the 3-D log's axes, and give a wrong angle without a word. An error, naming
    /// what is missing for a 3-D log and how to read one axis as a planar log.
    fn refuse_3d(&mut self, statuses: &[ColumnStatus], listing: &str) -> Result<(), LogError> {
        const SPATIAL: [&str; 5] = ["phi_x", "phi_y", "gyro_x", "gyro_y", "gyro_z"];
        let planar = |c: Column| statuses[c.index()].position.is_some();
        // Named but for case too: read as planar (with `--map t=T,ax=AX,ay=AY`) only
        // `accel` would run, on the 3-D axes.
        let found: Vec<&str> = SPATIAL
            .into_iter()
            .filter(|c| self.header.iter().any(|h| h.eq_ignore_ascii_case(c)))
            .collect();
        if found.is_empty() {
            // A 3-D log under other names (`time, enc_x, ..., gz, ax, ay, az`): read as
            // planar only `accel` would run, on its x and y axes.
            let az = self.header.iter().any(|h| h.eq_ignore_ascii_case("az"));
            if az && !planar(Column::Phi) && !planar(Column::Gyro) {
                let what = "a column `az` and neither `phi` nor `gyro`: a 3-D log under other \
                            names? Read as planar only `accel` would run, on its x and y axes. \
                            Map its columns onto the 3-D names (MODEL.md 7.6), e.g. --map \
                            t=time,phi_x=enc_x,phi_y=enc_y,gyro_x=gx,gyro_y=gy,gyro_z=gz";
                return Err(self.not_planar(what.to_string(), listing.to_string()));
            }
            return Ok(());
        }
        if planar(Column::Phi) || planar(Column::Gyro) {
            return self.refuse_3d_accel_axes(statuses, listing);
        }
        if let Some(what) = self.capital_3d() {
            return Err(self.not_planar(what, listing.to_string()));
        }
        let missing: Vec<String> = crate::io::LOG3D_COLUMNS[..crate::io::LOG3D_REQUIRED]
            .iter()
            .filter(|c| !self.header.iter().any(|h| h == *c))
            .map(|c| format!("`{c}`"))
            .collect();
        let what = if missing.is_empty() {
            "a 3-D log (MODEL.md 7.6), and this command reads planar logs (t, phi, gyro, ax, \
             ay): `estimate` and `report` read 3-D logs, given as a file (a pipe cannot be \
             looked at before it is read)"
                .to_string()
        } else {
            // A missing one under its name and a unit (`gyro_x[deg/s]`): its fix.
            let required = &crate::io::LOG3D_COLUMNS[..crate::io::LOG3D_REQUIRED];
            let line = self.lines.line();
            let units = crate::io::unit_named_3d_hint(required, &self.header, &self.file, line)
                .map(|h| format!("; {h}"))
                .unwrap_or_default();
            // A column named twice is most likely the missing one misnamed: say so (the
            // message named only the missing one, and the header listing hid the twin).
            let twice: Vec<String> = crate::io::LOG3D_COLUMNS
                .iter()
                .filter_map(|c| {
                    let at: Vec<String> = (self.header.iter().enumerate())
                        .filter(|(_, h)| h == c)
                        .map(|(i, _)| (i + 1).to_string())
                        .collect();
                    (at.len() > 1).then(|| format!("`{c}` is fields {}", at.join(" and ")))
                })
                .collect();
            let twice = if twice.is_empty() {
                String::new()
            } else {
                format!(
                    ", and {}: is one of them the missing one?",
                    twice.join(", ")
                )
            };
            format!(
                "the header has the 3-D columns {} but no {}{twice}: a 3-D log (MODEL.md 7.6) \
                 needs t, phi_x, phi_y, gyro_x, gyro_y, gyro_z, ax, ay, az{units}",
                found.join(", "),
                missing.join(", ")
            )
        };
        Err(self.not_planar(what, listing.to_string()))
    }

    /// One axis of a 3-D log read as planar (`--map phi=phi_x,gyro=gyro_x`) with the 3-D
    /// `ax`, `ay` as the planar ones: the roll axis's plane is the 3-D y, z (MODEL.md 7.4),
    /// so `accel` gave -173 deg and Madgwick -140 deg on a level ride, exit 0. An error
    /// with the whole map; `ax=ay,ay=az` given (or a log without `az`) passes.
    fn refuse_3d_accel_axes(
        &mut self,
        statuses: &[ColumnStatus],
        listing: &str,
    ) -> Result<(), LogError> {
        let source = |c: Column| statuses[c.index()].source.as_deref();
        let has_az = self.header.iter().any(|h| h == "az");
        if !has_az || (source(Column::Ax) != Some("ax") && source(Column::Ay) != Some("ay")) {
            return Ok(());
        }
        let what = format!(
            "--map reads one axis of a 3-D log (MODEL.md 7.6) as planar (phi <- {}) with its \
             `ax`, `ay` as the planar ax, ay; the planar pendulum is the 3-D roll axis, whose \
             plane is the 3-D y, z: every estimator reading the accelerometer would be \
             wrong by up to 180 deg",
            source(Column::Phi).unwrap_or("-")
        );
        Err(self.not_planar(what, listing.to_string()))
    }

    /// When the header has a 3-D log's columns (MODEL.md 7.6), some of them in other case
    /// (`PHI_X`): what to say (they are read by their names, in lower case).
    fn capital_3d(&self) -> Option<String> {
        let required = &crate::io::LOG3D_COLUMNS[..crate::io::LOG3D_REQUIRED];
        let all = required
            .iter()
            .all(|c| self.header.iter().any(|h| h.eq_ignore_ascii_case(c)));
        let exact = required.iter().all(|c| self.header.iter().any(|h| h == c));
        if !all || exact {
            return None;
        }
        let fix = if self.file.starts_with('<') {
            String::new()
        } else {
            format!(": `sed -i '{}s/.*/\\L&/' {}`", self.lines.line(), self.file)
        };
        Some(format!(
            "a 3-D log (MODEL.md 7.6) with its column names in capitals: its columns are read \
             by their names in lower case (t, phi_x, phi_y, gyro_x, ...); write the header in \
             lower case{fix}"
        ))
    }

    /// The error for a header without a time column, with a hint at the likely cause.
    /// The header's error for a log that is not planar: `what` it is, with the header's
    /// `listing`.
    fn not_planar(&mut self, what: String, header: String) -> LogError {
        let line = Some(self.lines.line());
        self.error(line, None, LogErrorKind::NotPlanar { what, header })
    }

    fn missing_time(&mut self, statuses: &[ColumnStatus], listing: String) -> LogError {
        if let Some(what) = self.capital_3d() {
            return self.not_planar(what, listing);
        }
        let hint = if let Some(s) = &statuses[Column::T.index()].suggestion {
            // Every column named but for case in one --map, not one round per column.
            let map: Vec<String> = statuses
                .iter()
                .filter_map(|st| Some(format!("{}={}", st.column, st.suggestion.as_ref()?)))
                .collect();
            // A name that states a smaller unit (`time_ms`) wants --time-unit too.
            let unit = match time_unit_in_name(s) {
                Some(u) if u != "s" && self.options.time_unit.is_none() => {
                    format!(" --time-unit {u}")
                }
                _ => String::new(),
            };
            format!(
                "; did you mean `{s}`? (--map {}{unit})",
                shell_word(&map.join(","))
            )
        } else if self.header.iter().all(|h| h.parse::<f64>().is_ok()) {
            "; the first line looks like data: the log needs a header row \
             (t,phi,gyro,ax,ay,theta)"
                .to_string()
        } else if self.header.len() == 1 && (listing.contains(';') || listing.contains('\t')) {
            // The commands read commas only: say how to convert, a decimal comma first.
            let (sep, tr) = if listing.contains(';') {
                ("`;`", "tr ';' ','")
            } else {
                ("tabs", "tr '\\t' ','")
            };
            format!(
                "; the header is a single field: the fields are separated by {sep}, and the log \
                 must be comma-separated: convert it with `{tr} < log.csv > log_commas.csv` \
                 (numbers with a decimal comma, `0,5`: `sed 's/,/./g'` first)"
            )
        } else {
            "; name the time column with --map t=NAME".to_string()
        };
        let line = Some(self.lines.line());
        self.error(
            line,
            None,
            LogErrorKind::MissingTime {
                header: listing,
                hint,
            },
        )
    }

    /// Duplicate header names: an error when the name feeds a contract column (its field
    /// in `used`), else a warning.
    fn check_duplicates(&mut self, used: &[usize]) -> Result<(), LogError> {
        for i in 0..self.header.len() {
            let name = &self.header[i];
            if name.is_empty() {
                continue;
            }
            let Some(first) = self.header[..i].iter().position(|h| h == name) else {
                continue;
            };
            if used.contains(&first) {
                let name = name.clone();
                let line = Some(self.lines.line());
                return Err(self.error(
                    line,
                    Some(CellRef {
                        position: i + 1,
                        header: name.clone(),
                    }),
                    LogErrorKind::DuplicateColumn {
                        name,
                        first: first + 1,
                    },
                ));
            }
            let name = name.clone();
            self.warn(
                WarningKind::DuplicateIgnoredColumn,
                None,
                Some(name),
                format!(
                    "appears as fields {} and {}; it is not used, so both are ignored",
                    first + 1,
                    i + 1
                ),
            );
        }
        Ok(())
    }
}

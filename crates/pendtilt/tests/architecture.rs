//! The std crate's layers (docs/architecture.md): a module imports from its own layer and
//! the layers below, never from one above. Read from the source itself, so that an import
//! running back up fails here with its file and line.
use std::path::{Path, PathBuf};

/// The layers, bottom first, and the top-level modules of each.
const LAYERS: [(&str, &[&str]); 7] = [
    (
        "ground: the sensor contract and the catalogue",
        &["sensors", "catalogue"],
    ),
    ("data: logs, units, rig files", &["io", "units", "config"]),
    ("models: the simulators", &["sim"]),
    ("estimators: the banks and the peers", &["bank", "peers"]),
    (
        "runs: the pass, replay, fit, tune",
        &["pipeline", "replay", "fit", "tune"],
    ),
    (
        "outputs: reports and the paper's experiment",
        &["report", "experiment"],
    ),
    ("front: the command line", &["cli", "lib", "main"]),
];

fn layer_of(module: &str) -> Option<usize> {
    LAYERS.iter().position(|(_, ms)| ms.contains(&module))
}

fn sources(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            sources(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// The crate modules a line names: `crate::x`, and each `x` of `crate::{x, y::z}`.
fn named(line: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut rest = line;
    while let Some(i) = rest.find("crate::") {
        rest = &rest[i + "crate::".len()..];
        if let Some(group) = rest.strip_prefix('{') {
            let end = group.find('}').unwrap_or(group.len());
            for item in group[..end].split(',') {
                let ident: String = item
                    .trim()
                    .chars()
                    .take_while(|c| c.is_alphanumeric() || *c == '_')
                    .collect();
                out.push(ident);
            }
        } else {
            out.push(
                rest.chars()
                    .take_while(|c| c.is_alphanumeric() || *c == '_')
                    .collect(),
            );
        }
    }
    out.retain(|s| !s.is_empty());
    out
}

#[test]
fn no_import_runs_back_up_a_layer() {
    let (modules, imports) = read_imports();
    assert!(modules.len() > 100, "read {} files", modules.len());
    let mut wrong: Vec<String> = modules
        .iter()
        .filter(|(_, module)| layer_of(module).is_none())
        .map(|(file, module)| format!("{file}: module `{module}` is in no layer"))
        .collect();
    for i in &imports {
        if let (Some(own), Some(l)) = (layer_of(&i.importer), layer_of(&i.imported)) {
            if l > own {
                wrong.push(format!(
                    "{}: `{}` ({}) imports `{}` ({}): {}",
                    i.at, i.importer, LAYERS[own].0, i.imported, LAYERS[l].0, i.line
                ));
            }
        }
    }
    assert!(
        wrong.is_empty(),
        "imports running back up:\n{}",
        wrong.join("\n")
    );
}

#[test]
fn the_reader_of_imports_finds_plain_and_grouped_paths() {
    assert_eq!(named("use crate::io::{A, B};"), ["io"]);
    assert_eq!(
        named("use crate::{bank::Bank, sensors, report::x};"),
        ["bank", "sensors", "report"]
    );
    assert_eq!(
        named("let x = crate::units::f(crate::bank::planar::RESTART_GAP);"),
        ["units", "bank"]
    );
    assert!(named("use super::x;").is_empty());
    // A module above its importer is caught: the layer table orders them.
    assert!(layer_of("cli") > layer_of("report") && layer_of("sensors") < layer_of("io"));
}

/// One import of another top-level module by the crate's own code.
struct Import {
    importer: String,
    imported: String,
    /// `file:line`.
    at: String,
    line: String,
}

/// Every source file with its top-level module, and every import of another top-level
/// module in the crate's own code (unit tests may reach anywhere, comments say nothing).
fn read_imports() -> (Vec<(String, String)>, Vec<Import>) {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    sources(&src, &mut files);
    files.sort();
    let (mut modules, mut imports) = (Vec::new(), Vec::new());
    for f in &files {
        let rel = f.strip_prefix(&src).unwrap();
        let first = rel.components().next().unwrap().as_os_str();
        let module = first.to_string_lossy().trim_end_matches(".rs").to_string();
        modules.push((rel.display().to_string(), module.clone()));
        let text = std::fs::read_to_string(f).unwrap();
        for (k, line) in text.lines().enumerate() {
            if line.starts_with("#[cfg(test)]") {
                break;
            }
            if line.trim_start().starts_with("//") {
                continue;
            }
            for m in named(line) {
                if m != module {
                    imports.push(Import {
                        importer: module.clone(),
                        imported: m,
                        at: format!("{}:{}", rel.display(), k + 1),
                        line: line.trim().to_string(),
                    });
                }
            }
        }
    }
    (modules, imports)
}

/// Every `(importer, imported, where)` between the layers' modules.
fn edges() -> Vec<(String, String, String)> {
    let (_, imports) = read_imports();
    imports
        .into_iter()
        .filter(|i| layer_of(&i.imported).is_some())
        .map(|i| (i.importer, i.imported, i.at))
        .collect()
}

/// Within a layer modules may import each other one way only: two that import each
/// other are one module in two places (the pairs io/units, config/io, bank/peers and
/// the planar and 3-D simulators once did).
#[test]
fn no_two_modules_import_each_other() {
    let e = edges();
    assert!(e.len() > 100, "{} imports read", e.len());
    let mut circles = Vec::new();
    for (a, b, at) in &e {
        if a < b {
            if let Some((_, _, back)) = e.iter().find(|(x, y, _)| x == b && y == a) {
                circles.push(format!(
                    "`{a}` imports `{b}` ({at}) and `{b}` imports `{a}` ({back})"
                ));
            }
        }
    }
    circles.dedup_by(|x, y| x.split(" (").next() == y.split(" (").next());
    assert!(
        circles.is_empty(),
        "import circles:\n{}",
        circles.join("\n")
    );
}

/// The simulators build on the core's model alone (its parameters, samples, mounting and
/// the encoder's range), never on an estimator's module: a change to a filter cannot
/// change what is simulated.
#[test]
fn the_simulators_import_only_the_cores_model() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    sources(&src.join("sim"), &mut files);
    assert!(files.len() > 10, "{} simulator files", files.len());
    let mut wrong = Vec::new();
    for f in &files {
        let text = std::fs::read_to_string(f).unwrap();
        for (k, line) in text.lines().enumerate() {
            if line.starts_with("#[cfg(test)]") {
                break;
            }
            if line.trim_start().starts_with("//") {
                continue;
            }
            let mut rest = line;
            while let Some(i) = rest.find("pendtilt_core::") {
                rest = &rest[i + "pendtilt_core::".len()..];
                if !rest.starts_with("model::") {
                    wrong.push(format!(
                        "{}:{}: {}",
                        f.strip_prefix(&src).unwrap().display(),
                        k + 1,
                        line.trim()
                    ));
                }
            }
        }
    }
    assert!(
        wrong.is_empty(),
        "the simulators reach past the model:\n{}",
        wrong.join("\n")
    );
}

/// A source file longer than this is several concerns in one place.
const MAX_FILE_LINES: usize = 700;
/// A function longer than this (from its `fn` line to its closing brace) is several steps
/// in one place.
const MAX_FN_LINES: usize = 80;

/// Every `.rs` file the size rules hold for: each crate's src, tests, examples, benches
/// and build script, the Python binding's and the firmware's sources; with the
/// workspace's root.
fn sized_sources() -> (PathBuf, Vec<PathBuf>) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .canonicalize()
        .unwrap();
    let mut dirs = Vec::new();
    let mut files = Vec::new();
    for e in std::fs::read_dir(root.join("crates")).unwrap() {
        let krate = e.unwrap().path();
        for sub in ["src", "tests", "examples", "benches"] {
            dirs.push(krate.join(sub));
        }
        files.extend(Some(krate.join("build.rs")).filter(|b| b.is_file()));
    }
    dirs.push(root.join("python/src"));
    dirs.push(root.join("examples/firmware/src"));
    for d in dirs.iter().filter(|d| d.is_dir()) {
        sources(d, &mut files);
    }
    files.sort();
    (root, files)
}

/// `text` with string, raw string and char literals and comments blanked out (their
/// quotes kept, their lines kept), so that only the code's own braces are left.
fn code_only(text: &str) -> String {
    let c: Vec<char> = text.chars().collect();
    let mut out = String::with_capacity(text.len());
    let keep_lines = |out: &mut String, s: &[char]| {
        out.extend(s.iter().filter(|ch| **ch == '\n'));
    };
    let mut i = 0;
    while i < c.len() {
        let ident = |k: usize| c[k].is_alphanumeric() || c[k] == '_';
        // `r"..."` and `br"..."` are raw strings; `for"` or `bar"` would not be.
        let ident_before = i > 0 && ident(i - 1) && !(c[i - 1] == 'b' && (i < 2 || !ident(i - 2)));
        let end = if c[i] == '/' && c.get(i + 1) == Some(&'/') {
            (i..c.len()).find(|&k| c[k] == '\n').unwrap_or(c.len())
        } else if c[i] == '/' && c.get(i + 1) == Some(&'*') {
            block_comment_end(&c, i)
        } else if c[i] == '"' {
            string_end(&c, i)
        } else if c[i] == 'r' && !ident_before && matches!(c.get(i + 1), Some('"' | '#')) {
            raw_string_end(&c, i).unwrap_or(i + 1)
        } else if c[i] == '\'' {
            char_end(&c, i).unwrap_or(i + 1)
        } else {
            i + 1
        };
        if end == i + 1 {
            out.push(c[i]);
        } else {
            let quoted = matches!(c[i], '"' | '\'' | 'r');
            if quoted {
                out.push_str("\"\"");
            }
            keep_lines(&mut out, &c[i..end]);
        }
        i = end;
    }
    out
}

/// Just past the `*/` closing the block comment opened at `i` (they nest).
fn block_comment_end(c: &[char], i: usize) -> usize {
    let (mut depth, mut k) = (0, i);
    while k < c.len() {
        if c[k] == '/' && c.get(k + 1) == Some(&'*') {
            depth += 1;
            k += 2;
        } else if c[k] == '*' && c.get(k + 1) == Some(&'/') {
            depth -= 1;
            k += 2;
            if depth == 0 {
                return k;
            }
        } else {
            k += 1;
        }
    }
    c.len()
}

/// Just past the `"` closing the string opened at `i` (escapes skipped).
fn string_end(c: &[char], i: usize) -> usize {
    let mut k = i + 1;
    while k < c.len() {
        match c[k] {
            '\\' => k += 2,
            '"' => return k + 1,
            _ => k += 1,
        }
    }
    c.len()
}

/// Just past the raw string `r#".."#` starting at `i`; `None` if `i` starts none.
fn raw_string_end(c: &[char], i: usize) -> Option<usize> {
    let hashes = c[i + 1..].iter().take_while(|ch| **ch == '#').count();
    if c.get(i + 1 + hashes) != Some(&'"') {
        return None;
    }
    let close: Vec<char> = std::iter::once('"')
        .chain(std::iter::repeat_n('#', hashes))
        .collect();
    let from = i + 2 + hashes;
    let at = (from..c.len()).find(|&k| c[k..].starts_with(&close));
    Some(at.map_or(c.len(), |k| k + close.len()))
}

/// Just past the char literal (`'x'`, `'\n'`, `'\u{7f}'`) starting at `i`; `None` for a
/// lifetime or a label (`'a`).
fn char_end(c: &[char], i: usize) -> Option<usize> {
    if c.get(i + 1) == Some(&'\\') {
        let close = (i + 3..c.len().min(i + 12)).find(|&k| c[k] == '\'')?;
        return Some(close + 1);
    }
    (c.get(i + 2) == Some(&'\'') && c.get(i + 1) != Some(&'\n')).then_some(i + 3)
}

/// The name a line of code declares a function by (`pub(crate) const unsafe fn name`),
/// if it does.
fn fn_name(line: &str) -> Option<&str> {
    let mut rest = line.trim_start();
    loop {
        let before = rest;
        if let Some(r) = rest.strip_prefix("pub(") {
            rest = r.split_once(')')?.1.trim_start();
        }
        for word in ["pub ", "const ", "async ", "unsafe ", "extern \"\" "] {
            if let Some(r) = rest.strip_prefix(word) {
                rest = r.trim_start();
            }
        }
        if rest == before {
            break;
        }
    }
    let name = rest.strip_prefix("fn ")?.trim_start();
    let end = name
        .find(|ch: char| !(ch.is_alphanumeric() || ch == '_'))
        .unwrap_or(name.len());
    (end > 0).then(|| &name[..end])
}

/// Each function in `text`: (its `fn` line, 1-based; its name; its length in lines from
/// that line to its closing brace). A declaration without a body (`fn f();`) is one line.
fn functions(text: &str) -> Vec<(usize, String, usize)> {
    let code = code_only(text);
    let lines: Vec<&str> = code.lines().collect();
    let mut out = Vec::new();
    for (i, line) in lines.iter().enumerate() {
        let Some(name) = fn_name(line) else {
            continue;
        };
        let (mut depth, mut started, mut j) = (0i64, false, i);
        while j < lines.len() {
            for ch in lines[j].chars() {
                match ch {
                    '{' => (depth, started) = (depth + 1, true),
                    '}' => depth -= 1,
                    _ => {}
                }
            }
            let declared = !started && lines[j].trim_end().ends_with(';');
            if (started && depth <= 0) || declared {
                break;
            }
            j += 1;
        }
        out.push((i + 1, name.to_string(), j.min(lines.len() - 1) - i + 1));
    }
    out
}

/// No source file runs over [`MAX_FILE_LINES`]: a longer one is several concerns, to be
/// split into modules.
#[test]
fn no_source_file_runs_over_700_lines() {
    let (root, files) = sized_sources();
    assert!(
        files.len() > 300,
        "{} files under {}",
        files.len(),
        root.display()
    );
    let mut long = Vec::new();
    for f in &files {
        let n = std::fs::read_to_string(f).unwrap().lines().count();
        if n > MAX_FILE_LINES {
            let rel = f.strip_prefix(&root).unwrap();
            long.push(format!("{}: {n} lines", rel.display()));
        }
    }
    assert!(
        long.is_empty(),
        "files over {MAX_FILE_LINES} lines (split each into modules, one concern per \
         module):\n{}",
        long.join("\n")
    );
}

/// No function runs over [`MAX_FN_LINES`], from its `fn` line to its closing brace: a
/// longer one is several steps, to be named.
#[test]
fn no_function_runs_over_80_lines() {
    let (root, files) = sized_sources();
    let mut long = Vec::new();
    let mut seen = 0;
    for f in &files {
        let rel = f.strip_prefix(&root).unwrap();
        for (line, name, n) in functions(&std::fs::read_to_string(f).unwrap()) {
            seen += 1;
            if n > MAX_FN_LINES {
                long.push(format!("{}:{line}: {name}: {n} lines", rel.display()));
            }
        }
    }
    assert!(seen > 3000, "{seen} functions read");
    assert!(
        long.is_empty(),
        "functions over {MAX_FN_LINES} lines (split each into named steps: a helper \
         function per step, with a one-line doc saying why it exists; a test that checks \
         independent things into several tests):\n{}",
        long.join("\n")
    );
}

#[test]
fn the_function_counter_counts_from_fn_to_its_closing_brace() {
    let src = r#"fn three() {
    let x = 1;
}
pub(crate) fn braces_in_literals<'a>(s: &'a str) -> usize {
    let open = "{ {";
    let c = '{';
    let raw = r"}";
    // } in a comment
    /* and { in a block */
    open.len() + s.len() + raw.len() + c.len_utf8()
}
fn nested_closure() {
    let f = |x: i32| {
        let g = || {
            x + 1
        };
        g()
    };
    f(1);
}
trait T {
    fn declared(&self);
}
"#;
    let found = functions(src);
    let got: Vec<(usize, &str, usize)> =
        found.iter().map(|(l, n, k)| (*l, n.as_str(), *k)).collect();
    assert_eq!(
        got,
        [
            (1, "three", 3),
            (4, "braces_in_literals", 8),
            (12, "nested_closure", 9),
            (22, "declared", 1),
        ]
    );
    assert_eq!(
        fn_name("    pub(super) const unsafe fn x_1() {"),
        Some("x_1")
    );
    assert_eq!(fn_name("let f: fn(u8) = g;"), None);
    assert_eq!(fn_name("    Fn(u8) -> u8,"), None);
}

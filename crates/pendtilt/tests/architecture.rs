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
    ("models: the simulators", &["sim", "sim3d"]),
    (
        "estimators: the banks and the peers",
        &["bank", "bank3d", "peers"],
    ),
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
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    sources(&src, &mut files);
    files.sort();
    let mut wrong = Vec::new();
    for f in &files {
        let rel = f.strip_prefix(&src).unwrap();
        let first = rel
            .components()
            .next()
            .unwrap()
            .as_os_str()
            .to_string_lossy();
        let module = first.trim_end_matches(".rs");
        let Some(own) = layer_of(module) else {
            wrong.push(format!(
                "{}: module `{module}` is in no layer",
                rel.display()
            ));
            continue;
        };
        let text = std::fs::read_to_string(f).unwrap();
        for (k, line) in text.lines().enumerate() {
            // Unit tests may reach anywhere; the module's own code may not.
            if line.starts_with("#[cfg(test)]") {
                break;
            }
            if line.trim_start().starts_with("//") {
                continue;
            }
            for m in named(line) {
                match layer_of(&m) {
                    Some(l) if l > own => wrong.push(format!(
                        "{}:{}: `{module}` ({}) imports `{m}` ({}): {}",
                        rel.display(),
                        k + 1,
                        LAYERS[own].0,
                        LAYERS[l].0,
                        line.trim()
                    )),
                    _ => {}
                }
            }
        }
    }
    assert!(
        files.len() > 100,
        "read {} files from {}",
        files.len(),
        src.display()
    );
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
        named("let x = crate::units::f(crate::bank::RESTART_GAP);"),
        ["units", "bank"]
    );
    assert!(named("use super::x;").is_empty());
    // A module above its importer is caught: the layer table orders them.
    assert!(layer_of("cli") > layer_of("report") && layer_of("sensors") < layer_of("io"));
}

/// Every `(importer, imported, where)` of the crate's own code (unit tests left out),
/// by top-level module.
fn edges() -> Vec<(String, String, String)> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    sources(&src, &mut files);
    files.sort();
    let mut out = Vec::new();
    for f in &files {
        let rel = f.strip_prefix(&src).unwrap();
        let first = rel.components().next().unwrap().as_os_str();
        let module = first.to_string_lossy().trim_end_matches(".rs").to_string();
        let text = std::fs::read_to_string(f).unwrap();
        for (k, line) in text.lines().enumerate() {
            if line.starts_with("#[cfg(test)]") {
                break;
            }
            if line.trim_start().starts_with("//") {
                continue;
            }
            for m in named(line) {
                if m != module && layer_of(&m).is_some() {
                    out.push((module.clone(), m, format!("{}:{}", rel.display(), k + 1)));
                }
            }
        }
    }
    out
}

/// Within a layer modules may import each other one way only: two that import each
/// other are one module in two places (the pairs io/units, config/io, bank/peers and
/// sim/sim3d once did).
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
    for m in ["sim", "sim3d"] {
        sources(&src.join(m), &mut files);
    }
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

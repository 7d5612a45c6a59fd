//! Records the commit the binary is built from, for `pendtilt --version`.
use std::process::Command;

fn main() {
    let commit = Command::new("git")
        .args(["describe", "--always", "--dirty", "--abbrev=12"])
        .output()
        .ok()
        .filter(|o| o.status.success())
        .and_then(|o| String::from_utf8(o.stdout).ok())
        .map(|s| s.trim().to_string())
        .filter(|s| !s.is_empty())
        .unwrap_or_else(|| "unknown".to_string());
    println!("cargo:rustc-env=PENDTILT_COMMIT={commit}");
    // Rebuilt when HEAD moves (a commit, a checkout). The paths come from git, so that a
    // worktree (whose `.git` is a file) watches its own; cargo takes a missing path as
    // always stale, so only paths that exist are named, and outside git none is.
    println!("cargo:rerun-if-changed=build.rs");
    for what in ["HEAD", "index"] {
        let path = Command::new("git")
            .args(["rev-parse", "--git-path", what])
            .output()
            .ok()
            .filter(|o| o.status.success())
            .and_then(|o| String::from_utf8(o.stdout).ok())
            .map(|s| s.trim().to_string());
        if let Some(path) = path.filter(|p| std::path::Path::new(p).exists()) {
            println!("cargo:rerun-if-changed={path}");
        }
    }
}

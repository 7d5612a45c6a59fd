//! The partial outputs of a run, removed when a signal ends it.
use std::io;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use super::absolute;

/// The temporary files and staging directories of the outputs being written, for
/// [`remove_partial_on_interrupt`]: their drop (or commit) removes them on a normal end,
/// but a signal ends the process without running it.
static PENDING: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// One entry of [`PENDING`], taken out when dropped.
#[derive(Debug)]
pub(super) struct Pending(PathBuf);

impl Pending {
    pub(super) fn new(path: &Path) -> Self {
        let path = absolute(path);
        PENDING
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .push(path.clone());
        Self(path)
    }
}

impl Drop for Pending {
    fn drop(&mut self) {
        let mut pending = PENDING.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(i) = pending.iter().position(|p| *p == self.0) {
            pending.swap_remove(i);
        }
    }
}

/// Removes every partial output (the `.NAME.XXXXXX.partial` files and staging directories
/// beside the targets) when the process gets SIGINT (Ctrl-C), SIGTERM or SIGHUP, then ends
/// it with status 128 + the signal's number, saying so on standard error. Without it an
/// interrupted run left them behind, hidden, as large as the run had got (2.7 GB after 20
/// s of `simulate --duration 1e7`). For the `pendtilt` binary: call it first thing in
/// `main`, before any thread starts; the signals are then blocked in every thread and
/// taken by one that waits for them (so the removal is ordinary code, not a signal
/// handler's). A no-op off Unix.
///
/// # Errors
/// When the signal mask cannot be set or the thread cannot start.
pub fn remove_partial_on_interrupt() -> io::Result<()> {
    #[cfg(unix)]
    {
        // SAFETY: sigset_t is plain data, initialised by sigemptyset before any use; the
        // calls only read and write the set and this thread's mask.
        let set = unsafe {
            let mut set: libc::sigset_t = std::mem::zeroed();
            libc::sigemptyset(&mut set);
            for sig in [libc::SIGINT, libc::SIGTERM, libc::SIGHUP] {
                libc::sigaddset(&mut set, sig);
            }
            let rc = libc::pthread_sigmask(libc::SIG_BLOCK, &set, std::ptr::null_mut());
            if rc != 0 {
                return Err(io::Error::from_raw_os_error(rc));
            }
            set
        };
        std::thread::Builder::new()
            .name("interrupt".into())
            .spawn(move || loop {
                let mut sig: libc::c_int = 0;
                // SAFETY: `set` is an initialised signal set, `sig` a valid out pointer.
                if unsafe { libc::sigwait(&set, &mut sig) } != 0 {
                    continue;
                }
                let paths = PENDING.lock().unwrap_or_else(|e| e.into_inner()).clone();
                for p in &paths {
                    let _ = if p.is_dir() {
                        std::fs::remove_dir_all(p)
                    } else {
                        std::fs::remove_file(p)
                    };
                }
                let removed = if paths.is_empty() {
                    String::new()
                } else {
                    format!(
                        "; the partial output was removed, nothing was written ({})",
                        paths
                            .iter()
                            .map(|p| p.display().to_string())
                            .collect::<Vec<_>>()
                            .join(", ")
                    )
                };
                eprintln!("\ninterrupted (signal {sig}){removed}");
                std::process::exit(128 + sig);
            })?;
    }
    Ok(())
}

/// Every file under `dir`, recursively.
pub(super) fn collect_files(dir: &Path, out: &mut Vec<PathBuf>) -> io::Result<()> {
    for entry in std::fs::read_dir(dir)? {
        let path = entry?.path();
        if path.is_dir() {
            collect_files(&path, out)?;
        } else {
            out.push(path);
        }
    }
    out.sort();
    Ok(())
}

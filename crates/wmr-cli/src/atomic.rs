//! Output written beside OUT under a temporary name and renamed when complete, so an
//! error, a panic or Ctrl-C never leaves a half-written OUT nor destroys an existing one.

use std::fs::File;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use anyhow::{Context as _, Result};
use tempfile::NamedTempFile;

/// The temporary file in flight, removed by the Ctrl-C handler.
static IN_FLIGHT: Mutex<Option<PathBuf>> = Mutex::new(None);

/// Installs the Ctrl-C (SIGINT, SIGTERM) handler: remove the temporary file, exit 130.
pub fn install_interrupt_handler() -> Result<()> {
    ctrlc::set_handler(|| {
        // Holding the lock while exiting keeps `persist` from renaming at the same time.
        let guard = IN_FLIGHT.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
        if let Some(path) = guard.as_ref() {
            let _ = std::fs::remove_file(path);
        }
        eprintln!("wmr-cli: interrupted, no output written");
        std::process::exit(130);
    })
    .context("cannot install the Ctrl-C handler")
}

/// A temporary file in OUT's directory that becomes OUT on [`AtomicOut::persist`] and
/// is removed when dropped otherwise.
pub struct AtomicOut {
    /// `None` once persisted.
    temp: Option<NamedTempFile>,
    out: PathBuf,
}

impl AtomicOut {
    /// Creates `.<OUT name>.<random>.tmp` beside `out`.
    pub fn create(out: &Path) -> Result<Self> {
        let dir = match out.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        let name = out.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        let temp = tempfile::Builder::new()
            .prefix(&format!(".{name}."))
            .suffix(".tmp")
            .tempfile_in(&dir)
            .with_context(|| format!("cannot create a temporary file in {}", dir.display()))?;
        *IN_FLIGHT.lock().unwrap_or_else(|p| p.into_inner()) = Some(temp.path().to_path_buf());
        Ok(Self { temp: Some(temp), out: out.to_path_buf() })
    }

    /// A second handle on the temporary file, for a writer that must own its file.
    pub fn file(&self) -> Result<File> {
        let temp = self.temp.as_ref().context("the output is already complete")?;
        temp.as_file().try_clone().context("cannot reopen the temporary output file")
    }

    /// Syncs the data and renames the temporary file to OUT (replacing it atomically).
    pub fn persist(mut self) -> Result<()> {
        let temp = self.temp.take().context("the output is already complete")?;
        temp.as_file().sync_all().context("cannot flush the output file")?;
        // The temporary file is private (0600); OUT gets the mode of the file it
        // replaces, or the usual 0644.
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt as _;
            let mode = std::fs::metadata(&self.out).map(|m| m.permissions().mode() & 0o7777).unwrap_or(0o644);
            temp.as_file()
                .set_permissions(std::fs::Permissions::from_mode(mode))
                .context("cannot set the output file's mode")?;
        }
        let mut guard = IN_FLIGHT.lock().unwrap_or_else(|p| p.into_inner());
        // On error `temp` comes back inside the error and is removed when it drops.
        let done = temp.persist(&self.out).map(drop).map_err(|e| e.error);
        *guard = None;
        drop(guard);
        done.with_context(|| format!("cannot write {}", self.out.display()))
    }
}

impl Drop for AtomicOut {
    fn drop(&mut self) {
        // NamedTempFile removes the file itself; only forget it here.
        if let Some(temp) = &self.temp
            && let Ok(mut guard) = IN_FLIGHT.lock()
            && guard.as_deref() == Some(temp.path())
        {
            *guard = None;
        }
    }
}

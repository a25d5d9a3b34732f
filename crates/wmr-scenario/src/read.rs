//! Reading a scenario file within limits, so that a file (typed by hand, downloaded, or
//! mutated by a fuzzer) gets one clear error instead of an exhausted memory or a read
//! that never ends: a regular file of at most [`MAX_FILE_BYTES`], UTF-8 text, named by
//! its stem.

use std::cell::RefCell;
use std::fs::File;
use std::io::{self, Read as _};
use std::path::{Path, PathBuf};

use crate::error::{ScenarioError, shown};

/// Largest scenario file read, bytes (16 MiB: a million `[[run]]`s fit).
pub const MAX_FILE_BYTES: u64 = 16 << 20;

/// The scenario name a file gets when it has no `name`: its stem (`fig7` for
/// `examples/paper/fig7.toml`), or `scenario`.
pub fn default_name(path: &Path) -> String {
    path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| "scenario".to_owned())
}

/// Reads a scenario file: a regular file (not a FIFO, a device or a directory, which
/// could block or never end) of at most [`MAX_FILE_BYTES`], UTF-8 text. Errors name the
/// path; for a file that cannot be opened, [`ScenarioError::io`] holds the reason.
///
/// The path is opened once, without blocking (a FIFO opens at once, with no writer), and
/// the opened handle is what is checked and read: a file swapped for a FIFO or a folder
/// after a check can neither block the read nor be read in its place.
pub fn read_text(path: &Path) -> Result<String, ScenarioError> {
    read_text_within(path, None)
}

/// [`read_text`] of a file a scenario names, refused when the opened file lies outside
/// the folders `opened` allows (checked on the handle, before anything is read).
pub(crate) fn read_text_within(
    path: &Path,
    opened: Option<&crate::files::Opened<'_>>,
) -> Result<String, ScenarioError> {
    let name = shown(path);
    let io_err = |e: io::Error| ScenarioError::unreadable(e.kind(), format!("cannot read {name}: {e}"));
    // Refused before opening when it already is no regular file (opening a device may do
    // something), then again on the handle: what is read is what was checked.
    if let Ok(meta) = std::fs::metadata(path) {
        check_regular(&meta, &name)?;
    }
    let file = open_nonblocking(path).map_err(io_err)?;
    if let Some(o) = opened {
        o.check(&file, path)?;
    }
    let meta = file.metadata().map_err(io_err)?;
    check_regular(&meta, &name)?;
    record(path);
    let too_big = |len: u64| {
        ScenarioError::new(
            "",
            format!("{name} is {len} bytes: a scenario file may be at most {} MiB", MAX_FILE_BYTES >> 20),
        )
    };
    if meta.len() > MAX_FILE_BYTES {
        return Err(too_big(meta.len()));
    }
    let mut bytes = Vec::with_capacity(usize::try_from(meta.len()).unwrap_or(0));
    // The file may grow while it is read: never read more than the limit.
    file.take(MAX_FILE_BYTES + 1).read_to_end(&mut bytes).map_err(io_err)?;
    if bytes.len() as u64 > MAX_FILE_BYTES {
        return Err(too_big(bytes.len() as u64));
    }
    String::from_utf8(bytes).map_err(|e| {
        let at = e.utf8_error().valid_up_to();
        let line = e.as_bytes()[..at].iter().filter(|&&b| b == b'\n').count() + 1;
        ScenarioError::new("", format!("{name} is not UTF-8 text (a bad byte at offset {at})")).at_line(Some(line))
    })
}

/// Refuses what is not a regular file: a directory, a FIFO, a device or a socket.
fn check_regular(meta: &std::fs::Metadata, name: &str) -> Result<(), ScenarioError> {
    if meta.is_dir() {
        return Err(ScenarioError::unreadable(
            io::ErrorKind::IsADirectory,
            format!("cannot read {name}: it is a directory, not a scenario file"),
        ));
    }
    if !meta.is_file() {
        return Err(ScenarioError::unreadable(
            io::ErrorKind::InvalidInput,
            format!("cannot read {name}: not a regular file (a FIFO, a device or a socket); give a scenario file"),
        ));
    }
    Ok(())
}

/// Opens `path` for reading without waiting: a FIFO without a writer opens at once (and is
/// then refused by its metadata) instead of blocking; a terminal does not become the
/// process's controlling one. Reading a regular file is unchanged.
#[cfg(unix)]
fn open_nonblocking(path: &Path) -> io::Result<File> {
    use std::os::unix::fs::OpenOptionsExt as _;
    std::fs::OpenOptions::new().read(true).custom_flags(libc::O_NONBLOCK | libc::O_NOCTTY).open(path)
}

#[cfg(not(unix))]
fn open_nonblocking(path: &Path) -> io::Result<File> {
    File::open(path)
}

thread_local! {
    /// The files [`read_text`] read on this thread while [`recording`] runs.
    static RECORDED: RefCell<Option<Vec<PathBuf>>> = const { RefCell::new(None) };
}

fn record(path: &Path) {
    RECORDED.with(|r| {
        if let Some(list) = r.borrow_mut().as_mut() {
            list.push(path.to_path_buf());
        }
    });
}

/// Runs `f` and returns, beside its result, the files [`read_text`] read during it on this
/// thread (as the paths it was given, in order, repeats included). Calls nest: the outer
/// one sees the files of the inner one too.
pub(crate) fn recording<T>(f: impl FnOnce() -> T) -> (T, Vec<PathBuf>) {
    let outer = RECORDED.with(|r| r.borrow_mut().replace(Vec::new()));
    let result = f();
    let read = RECORDED.with(|r| {
        let mut r = r.borrow_mut();
        let read = r.take().unwrap_or_default();
        *r = outer.map(|mut o| {
            o.extend(read.iter().cloned());
            o
        });
        read
    });
    (result, read)
}

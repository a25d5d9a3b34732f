//! Where output goes and how it gets there (the README's rules):
//!
//! - OUT that is a regular file, or does not exist yet: written to a temporary file
//!   `.OUT.XXXXXX.tmp` beside it and renamed over OUT when complete, so an error, a
//!   signal or a full disk never leaves a half-written OUT nor destroys an existing one.
//!   A symbolic link OUT is followed: the file it points to is replaced, the link stays.
//! - OUT that is a character device (`/dev/null`, a terminal), a FIFO, or `-` (stdout):
//!   streamed to as it is produced; nothing is renamed or created.
//! - Refused as bad input (exit 2): OUT that is one of the command's input files (the
//!   scenario and every file it read: its robot preset, its reference CSVs; also through
//!   a link), a directory, a block device or a socket, or whose directory does
//!   not exist (wmr-cli creates files, never the directories above them).
//! - SIGINT, SIGTERM and SIGHUP: every temporary file in flight is removed, then the
//!   process ends as the signal would have ended it (a shell shows 130, 143, 129). In live
//!   view the first one stops the session, which removes its files and exits with 130,
//!   143 or 129; a second one ends it at once the same way.

use std::fs::{File, OpenOptions};
use std::io::{self, Seek, SeekFrom, Write};
use std::os::unix::fs::{FileTypeExt as _, MetadataExt as _};
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicI32, Ordering};

use anyhow::{Context as _, Result};
use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
use tempfile::NamedTempFile;
use wmr_scenario::shown;

use crate::errors::{bad_input, note};

/// The temporary files in flight, removed by the signal handler.
static IN_FLIGHT: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Folders this command created for its outputs: the signal handler removes each one it
/// leaves empty (`plot -o DIR`, `sweep --plots DIR`).
static NEW_DIRS: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Remembers `dir` as a folder this command created ([`NEW_DIRS`]).
pub fn register_new_dir(dir: &Path) {
    NEW_DIRS.lock().unwrap_or_else(|p| p.into_inner()).push(dir.to_path_buf());
}

/// Forgets `dir` ([`register_new_dir`]): the command is done with it.
pub fn forget_new_dir(dir: &Path) {
    NEW_DIRS.lock().unwrap_or_else(|p| p.into_inner()).retain(|d| d != dir);
}

/// The command's input files, as (device, inode, how messages name it): OUT must not be
/// one of them. The inode is the file's, links followed: a symbolic or hard link to an
/// input is that input.
static INPUTS: Mutex<Vec<(u64, u64, String)>> = Mutex::new(Vec::new());

/// Remembers `path` as an input: no output of this command may replace it.
pub fn register_input(path: &Path) {
    register_input_as(path, shown(path));
}

/// [`register_input`], named in messages as `described` (e.g. `ref.csv (reference.path
/// of trk.toml)`).
pub fn register_input_as(path: &Path, described: String) {
    if let Ok(m) = std::fs::metadata(path) {
        INPUTS.lock().unwrap_or_else(|p| p.into_inner()).push((m.dev(), m.ino(), described));
    }
}

/// The input file `meta` belongs to, if any, as messages name it.
fn input_of(meta: &std::fs::Metadata) -> Option<String> {
    let inputs = INPUTS.lock().unwrap_or_else(|p| p.into_inner());
    inputs.iter().find(|(dev, ino, _)| *dev == meta.dev() && *ino == meta.ino()).map(|(_, _, p)| p.clone())
}

/// Installs the handler of SIGINT, SIGTERM and SIGHUP: remove the temporary files,
/// then end the way the signal would have (its default action, re-raised).
///
/// With `stop_first` (live view), the first signal only stores its number there (the
/// session stops, cleans up and exits with 128 + it); a second one ends the process as
/// above, at once.
pub fn install_signal_handlers(stop_first: Option<&'static AtomicI32>) -> Result<()> {
    let mut signals = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP])
        .context("cannot install the handlers of SIGINT, SIGTERM and SIGHUP")?;
    std::thread::Builder::new()
        .name("signals".into())
        .spawn(move || {
            for sig in signals.forever() {
                if let Some(flag) = stop_first
                    && flag.compare_exchange(0, sig, Ordering::SeqCst, Ordering::SeqCst).is_ok()
                {
                    continue;
                }
                // Holding the lock until the end keeps `persist` from renaming meanwhile.
                let guard = IN_FLIGHT.lock().unwrap_or_else(|p| p.into_inner());
                for path in guard.iter() {
                    let _ = std::fs::remove_file(path);
                }
                // Then the folders created for the outputs, when nothing is left in them.
                for dir in NEW_DIRS.lock().unwrap_or_else(|p| p.into_inner()).iter() {
                    let _ = std::fs::remove_dir(dir);
                }
                let name = match sig {
                    SIGINT => "SIGINT",
                    SIGTERM => "SIGTERM",
                    _ => "SIGHUP",
                };
                let again = if stop_first.is_some() { " again" } else { "" };
                if guard.is_empty() {
                    note(&format!("wmr-cli: stopped by {name}{again}"));
                } else {
                    note(&format!("wmr-cli: stopped by {name}{again}; temporary files removed, OUT left as it was"));
                }
                let _ = signal_hook::low_level::emulate_default_handler(sig);
                // Not reached when the default action ran; the shell's code otherwise.
                std::process::exit(128 + sig);
            }
        })
        .context("cannot start the signal thread")?;
    Ok(())
}

/// What an output path names.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Target {
    /// `-`: the process's stdout.
    Stdout,
    /// A character device or a FIFO: written straight through.
    Stream(PathBuf),
    /// A regular file, existing or not (symbolic links resolved): written atomically.
    File(PathBuf),
}

/// Classifies `out` by the rules of the module doc; bad paths are [`bad_input`].
pub fn target_of(out: &Path) -> Result<Target> {
    if out.as_os_str() == "-" {
        return Ok(Target::Stdout);
    }
    let name = shown(out);
    match std::fs::metadata(out) {
        Ok(meta) => {
            if let Some(input) = input_of(&meta) {
                return Err(bad_input(format!(
                    "{name} is the input file {input}: refusing to overwrite it; choose another output"
                )));
            }
            let ft = meta.file_type();
            if ft.is_dir() {
                Err(bad_input(format!("{name} is a directory; give a file name")))
            } else if ft.is_file() {
                // A link is followed: the file it points to is the one replaced.
                let real = if out.is_symlink() {
                    std::fs::canonicalize(out).unwrap_or(out.to_path_buf())
                } else {
                    out.to_path_buf()
                };
                Ok(Target::File(real))
            } else if ft.is_char_device() || ft.is_fifo() {
                Ok(Target::Stream(out.to_path_buf()))
            } else if ft.is_block_device() {
                Err(bad_input(format!("{name} is a block device; wmr-cli does not write to disks directly")))
            } else {
                Err(bad_input(format!("{name} is a socket or another special file; give a file name")))
            }
        }
        Err(e) if e.kind() == io::ErrorKind::NotFound => {
            if out.is_symlink() {
                return Err(bad_input(format!("{name} is a symbolic link to a missing file")));
            }
            let dir = parent_dir(out);
            match std::fs::metadata(&dir) {
                Ok(m) if m.is_dir() => Ok(Target::File(out.to_path_buf())),
                Ok(_) => Err(bad_input(format!("cannot write {name}: {} is not a directory", shown(&dir)))),
                Err(_) => Err(bad_input(format!(
                    "cannot write {name}: the directory {} does not exist (wmr-cli creates files, not directories)",
                    shown(&dir)
                ))),
            }
        }
        Err(e) => {
            Err(bad_path(&name, &e).unwrap_or_else(|| anyhow::Error::new(e).context(format!("cannot write {name}"))))
        }
    }
}

/// A path the system refuses for what it is, not for a failure: a part of it that is a
/// file (ENOTDIR), a loop of symbolic links (ELOOP), a name too long (ENAMETOOLONG). Bad
/// input (exit 2) naming `name` and the reason; `None` for any other error.
pub fn bad_path(name: &str, e: &io::Error) -> Option<anyhow::Error> {
    use rustix::io::Errno;
    let why = match Errno::from_io_error(e)? {
        Errno::NOTDIR => "a part of the path above it is a file, not a directory",
        Errno::LOOP => "it goes through a loop of symbolic links",
        Errno::NAMETOOLONG => "a name in it is longer than the file system allows (255 bytes)",
        _ => return None,
    };
    Some(bad_input(format!("cannot use {name}: {why}")))
}

/// The directory `out` is created in.
pub fn parent_dir(out: &Path) -> PathBuf {
    match out.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// Free bytes for an unprivileged writer on the file system holding `dir`.
pub fn free_bytes(dir: &Path) -> Option<u64> {
    let st = rustix::fs::statvfs(dir).ok()?;
    st.f_bavail.checked_mul(st.f_frsize)
}

/// An output being written: atomically (a temporary file renamed at the end) or
/// streamed (device, FIFO, stdout).
pub struct Output {
    kind: Kind,
    shown: String,
}

enum Kind {
    Atomic(AtomicOut),
    Stream(File),
    Stdout,
}

impl Output {
    /// Opens `out` by the rules of the module doc.
    pub fn create(out: &Path) -> Result<Self> {
        let shown = if out.as_os_str() == "-" { "stdout".to_owned() } else { shown(out) };
        let kind = match target_of(out)? {
            Target::Stdout => Kind::Stdout,
            Target::Stream(path) => Kind::Stream(
                OpenOptions::new().write(true).open(&path).with_context(|| format!("cannot open {shown}"))?,
            ),
            Target::File(path) => Kind::Atomic(AtomicOut::create_at(&path)?),
        };
        Ok(Self { kind, shown })
    }

    /// OUT as shown in messages (`stdout` for `-`).
    pub fn shown(&self) -> &str {
        &self.shown
    }

    /// True for `-`.
    pub fn is_stdout(&self) -> bool {
        matches!(self.kind, Kind::Stdout)
    }

    /// Free space where the output is written, bytes; `None` for streams.
    pub fn free_bytes(&self) -> Option<u64> {
        match &self.kind {
            Kind::Atomic(a) => free_bytes(&a.dir),
            _ => None,
        }
    }

    /// A writer of the output (a regular file's is seekable; a stream's only reports
    /// its position).
    pub fn writer(&self) -> Result<OutWriter> {
        let inner = match &self.kind {
            Kind::Atomic(a) => Inner::File(a.file()?),
            Kind::Stream(f) => Inner::Stream(f.try_clone().context("cannot reopen the output")?),
            Kind::Stdout => Inner::Stdout(io::stdout()),
        };
        Ok(OutWriter { inner, pos: 0 })
    }

    /// Completes the output: renames the temporary file over OUT, or flushes a stream.
    pub fn finish(self) -> Result<()> {
        match self.kind {
            Kind::Atomic(a) => a.persist(),
            Kind::Stream(mut f) => f.flush().with_context(|| format!("cannot write {}", self.shown)),
            Kind::Stdout => io::stdout().flush().with_context(|| format!("cannot write {}", self.shown)),
        }
    }
}

/// The writer of an [`Output`].
pub struct OutWriter {
    inner: Inner,
    /// Bytes written, for a stream's [`Seek::stream_position`].
    pos: u64,
}

enum Inner {
    File(File),
    Stream(File),
    Stdout(io::Stdout),
}

impl OutWriter {
    /// True for a regular file, which may seek; false for a stream (device, FIFO, stdout).
    pub fn seekable(&self) -> bool {
        matches!(self.inner, Inner::File(_))
    }
}

impl Write for OutWriter {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let n = match &mut self.inner {
            Inner::File(f) | Inner::Stream(f) => f.write(buf)?,
            Inner::Stdout(s) => s.write(buf)?,
        };
        self.pos += n as u64;
        Ok(n)
    }

    fn flush(&mut self) -> io::Result<()> {
        match &mut self.inner {
            Inner::File(f) | Inner::Stream(f) => f.flush(),
            Inner::Stdout(s) => s.flush(),
        }
    }
}

impl Seek for OutWriter {
    /// A file seeks; a stream only answers where it is (what an MCAP writer with
    /// seeking disabled asks).
    fn seek(&mut self, to: SeekFrom) -> io::Result<u64> {
        match (&mut self.inner, to) {
            (Inner::File(f), to) => f.seek(to),
            (_, SeekFrom::Current(0)) => Ok(self.pos),
            (_, SeekFrom::Start(p)) if p == self.pos => Ok(p),
            _ => Err(io::Error::new(io::ErrorKind::Unsupported, "cannot seek in a stream")),
        }
    }
}

/// A temporary file in OUT's directory that becomes OUT on [`AtomicOut::persist`] and
/// is removed when dropped otherwise.
pub struct AtomicOut {
    /// `None` once persisted.
    temp: Option<NamedTempFile>,
    out: PathBuf,
    dir: PathBuf,
}

impl AtomicOut {
    /// Creates `.<OUT name>.<random>.tmp` beside `out`, which must name a regular file
    /// or a new one by the rules of [`target_of`] (a device, a FIFO or stdout is refused
    /// here: they take an [`Output`]).
    pub fn create(out: &Path) -> Result<Self> {
        match target_of(out)? {
            Target::File(real) => Self::create_at(&real),
            _ => Err(bad_input(format!("{} is not a regular file; give a file name", shown(out)))),
        }
    }

    /// [`AtomicOut::create`] for a path [`target_of`] has already classified as a file.
    fn create_at(out: &Path) -> Result<Self> {
        let dir = parent_dir(out);
        let name = out.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        // Registered under the lock before the file exists: a signal in between finds
        // nothing to remove, never a file it does not know.
        let mut guard = IN_FLIGHT.lock().unwrap_or_else(|p| p.into_inner());
        let temp = tempfile::Builder::new()
            .prefix(&format!(".{name}."))
            .suffix(".tmp")
            .tempfile_in(&dir)
            .with_context(|| format!("cannot create a temporary file in {}", shown(&dir)))?;
        guard.push(temp.path().to_path_buf());
        Ok(Self { temp: Some(temp), out: out.to_path_buf(), dir })
    }

    /// A second handle on the temporary file, for a writer that must own its file.
    pub fn file(&self) -> Result<File> {
        let temp = self.temp.as_ref().context("the output is already complete")?;
        temp.as_file().try_clone().context("cannot reopen the temporary output file")
    }

    /// Syncs the data and renames the temporary file to OUT (replacing it atomically).
    pub fn persist(mut self) -> Result<()> {
        let temp = self.temp.take().context("the output is already complete")?;
        let out = shown(&self.out);
        temp.as_file().sync_all().with_context(|| format!("cannot write {out}"))?;
        // The temporary file is private (0600); OUT gets the mode of the file it
        // replaces, or the usual 0644.
        {
            use std::os::unix::fs::PermissionsExt as _;
            let mode = std::fs::metadata(&self.out).map(|m| m.permissions().mode() & 0o7777).unwrap_or(0o644);
            temp.as_file()
                .set_permissions(std::fs::Permissions::from_mode(mode))
                .with_context(|| format!("cannot set the mode of {out}"))?;
        }
        let mut guard = IN_FLIGHT.lock().unwrap_or_else(|p| p.into_inner());
        let path = temp.path().to_path_buf();
        // On error `temp` comes back inside the error and is removed when it drops.
        let done = temp.persist(&self.out).map(drop).map_err(|e| e.error);
        guard.retain(|p| *p != path);
        drop(guard);
        done.with_context(|| format!("cannot write {out}"))
    }
}

impl Drop for AtomicOut {
    fn drop(&mut self) {
        // Removed and forgotten under the lock, so a signal meanwhile cannot miss it.
        if let Some(temp) = self.temp.take() {
            let mut guard = IN_FLIGHT.lock().unwrap_or_else(|p| p.into_inner());
            let path = temp.path().to_path_buf();
            drop(temp);
            guard.retain(|p| *p != path);
        }
    }
}

/// Writes a small text file by the same rules (atomically, or to a stream).
pub fn write_text(path: &Path, text: &str) -> Result<()> {
    let out = Output::create(path)?;
    let mut w = out.writer()?;
    w.write_all(text.as_bytes()).with_context(|| format!("cannot write {}", out.shown()))?;
    drop(w);
    out.finish()
}

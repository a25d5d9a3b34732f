//! Which files a scenario may name (issue 39 item 14): `[robot] from = "robots/NAME.toml"`,
//! `[reference] path = "ref.csv"` and a sweep's `references[i].path` are read from the
//! scenario's folder and below, and from the folders the user allows
//! ([`FileAccess::under`]: `wmr-cli --allow-files-under DIR`, Python's
//! `allow_files_under=[DIR]`), nowhere else. A scenario is often someone else's file: it
//! must not read `~/.ssh/id_rsa` or `/proc/self/environ` into an error message or a run.
//!
//! A name is judged by where it leads: `..` taken, links followed (a link inside the
//! folder to a file outside it is outside), and once more by the file actually opened
//! (the handle's own path), so a link swapped in between the check and the open cannot
//! lead outside either.

use std::fs::File;
use std::io;
use std::path::{Component, Path, PathBuf};

use crate::error::{ScenarioError, shown};

/// How the user of a surface allows another folder, for the error that refuses a file.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum AllowedBy {
    /// The library: both surfaces' ways are named.
    #[default]
    Library,
    /// `wmr-cli ... --allow-files-under DIR`.
    CommandLine,
    /// Python: `allow_files_under=[DIR]`.
    Python,
}

impl AllowedBy {
    fn hint(self, dir: &Path) -> String {
        let d = shown(dir);
        match self {
            Self::Library => {
                format!("allow it with wmr-cli --allow-files-under {d} (Python: allow_files_under=[\"{d}\"])")
            }
            Self::CommandLine => format!("pass --allow-files-under {d} to allow it"),
            Self::Python => format!("pass allow_files_under=[\"{d}\"] to allow it"),
        }
    }
}

/// Where the files a scenario names may be: its own folder and below (always), plus the
/// folders given to [`FileAccess::under`], or anywhere ([`FileAccess::anywhere`], for a
/// path the caller gives itself, such as Python's `Reference("file", path=...)`).
/// The default allows the scenario's folder only.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct FileAccess {
    /// The other folders allowed, canonical (links resolved).
    under: Vec<PathBuf>,
    anywhere: bool,
    by: AllowedBy,
}

impl FileAccess {
    /// The scenario's folder and below, and each folder of `dirs` and below; `by` names
    /// the flag in the error that refuses another file. A folder that cannot be resolved
    /// (missing, not a folder) is refused, naming it.
    pub fn under<P: AsRef<Path>>(dirs: &[P], by: AllowedBy) -> Result<Self, ScenarioError> {
        let flag = match by {
            AllowedBy::Python => "allow_files_under",
            _ => "--allow-files-under",
        };
        let under = dirs
            .iter()
            .map(|d| {
                let d = d.as_ref();
                let bad = |why: String| ScenarioError::new(flag, format!("{}: {why}", shown(d)));
                let canon = d.canonicalize().map_err(|e| bad(format!("cannot resolve it: {e}")))?;
                if !canon.is_dir() {
                    return Err(bad("not a folder".to_owned()));
                }
                Ok(canon)
            })
            .collect::<Result<_, _>>()?;
        Ok(Self { under, anywhere: false, by })
    }

    /// Any file: for a path the caller gives itself, not one written in a scenario.
    pub fn anywhere() -> Self {
        Self { anywhere: true, ..Self::default() }
    }

    /// The folders allowed besides the scenario's, canonical.
    pub fn allowed_folders(&self) -> &[PathBuf] {
        &self.under
    }

    fn allows(&self, root: &Path, path: &Path) -> bool {
        self.anywhere || path.starts_with(root) || self.under.iter().any(|u| path.starts_with(u))
    }
}

/// `path` with `.` and `..` taken by name (`a/b/../c` is `a/c`), links not followed.
fn lexical(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for c in path.components() {
        match c {
            Component::ParentDir => {
                out.pop();
            }
            Component::CurDir => {}
            other => out.push(other),
        }
    }
    out
}

/// The scenario's folder, canonical (`""` is the working directory).
fn root_of(dir: &Path, key: &str) -> Result<PathBuf, ScenarioError> {
    let d = if dir.as_os_str().is_empty() { Path::new(".") } else { dir };
    d.canonicalize()
        .map_err(|e| ScenarioError::new(key, format!("cannot resolve the scenario's folder {}: {e}", shown(d))))
}

/// A file named by `key` (written `name` in the scenario) that leads to `resolved`,
/// outside the scenario's folder `root` and every allowed one.
fn outside(key: &str, name: &str, resolved: &Path, root: &Path, by: AllowedBy) -> ScenarioError {
    let folder = resolved.parent().unwrap_or(resolved);
    let is = if Path::new(name) == resolved { String::new() } else { format!(" (it is {})", shown(resolved)) };
    ScenarioError::new(
        key,
        format!(
            "{}{is} is outside the scenario's folder {}: a scenario reads files in its folder and below; {}",
            crate::error::escape_controls(name),
            shown(root),
            by.hint(folder)
        ),
    )
}

/// Checks that `name` (the value of `key`), relative to the scenario's folder `dir`,
/// leads inside it or an allowed folder, by name and through links, before anything is
/// opened. Returns the path to open (`dir` joined with `name`, as written) and the
/// check to apply to the opened file.
pub(crate) fn check<'a>(
    key: &'a str,
    name: &'a str,
    dir: &Path,
    access: &'a FileAccess,
) -> Result<(PathBuf, Opened<'a>), ScenarioError> {
    let path = dir.join(name);
    if access.anywhere {
        return Ok((path, Opened { key, name, root: None, access }));
    }
    let root = root_of(dir, key)?;
    let joined = root.join(name);
    let by_name = lexical(&joined);
    if !access.allows(&root, &by_name) {
        return Err(outside(key, name, &by_name, &root, access.by));
    }
    // Links followed (a missing file is left to the read, which names it).
    if let Ok(real) = joined.canonicalize()
        && !access.allows(&root, &real)
    {
        return Err(outside(key, name, &real, &root, access.by));
    }
    Ok((path, Opened { key, name, root: Some(root), access }))
}

/// The check of a file once opened: its handle's own path must lead inside.
#[derive(Debug)]
pub(crate) struct Opened<'a> {
    key: &'a str,
    name: &'a str,
    root: Option<PathBuf>,
    access: &'a FileAccess,
}

impl Opened<'_> {
    /// Refuses `file` (opened from `path`) when the file it is lies outside.
    pub(crate) fn check(&self, file: &File, path: &Path) -> Result<(), ScenarioError> {
        let Some(root) = &self.root else { return Ok(()) };
        let real = real_path(file)
            .or_else(|_| path.canonicalize())
            .map_err(|e| ScenarioError::new(self.key, format!("cannot tell where {} leads: {e}", shown(path))))?;
        if self.access.allows(root, &real) {
            Ok(())
        } else {
            Err(outside(self.key, self.name, &real, root, self.access.by))
        }
    }
}

/// The path of the file an open handle is (Linux: its `/proc/self/fd` link).
#[cfg(target_os = "linux")]
fn real_path(file: &File) -> io::Result<PathBuf> {
    use std::os::fd::AsRawFd as _;
    std::fs::read_link(format!("/proc/self/fd/{}", file.as_raw_fd()))
}

#[cfg(not(target_os = "linux"))]
fn real_path(_file: &File) -> io::Result<PathBuf> {
    Err(io::Error::from(io::ErrorKind::Unsupported))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dot_dot_is_taken_by_name() {
        assert_eq!(lexical(Path::new("/a/b/../c/./d")), Path::new("/a/c/d"));
        assert_eq!(lexical(Path::new("/a/../../x")), Path::new("/x"));
        assert!(!lexical(Path::new("/a/b/../bc")).starts_with("/a/b"));
    }

    #[test]
    fn the_folder_and_below_are_allowed_and_nothing_else() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        std::fs::create_dir(d.join("sub")).unwrap();
        std::fs::write(d.join("sub/in.csv"), "").unwrap();
        let confined = FileAccess::default();
        assert!(check("reference.path", "sub/in.csv", d, &confined).is_ok());
        assert!(check("reference.path", "sub/../sub/in.csv", d, &confined).is_ok());
        let e = check("reference.path", "../x.csv", &d.join("sub"), &confined).unwrap_err();
        assert_eq!(e.key, "reference.path");
        assert!(e.message.contains("is outside the scenario's folder"), "{e}");
        assert!(check("robot.from", "/etc/hostname", d, &confined).is_err());
        // A link inside that leads outside is outside.
        std::os::unix::fs::symlink("/etc/hostname", d.join("link")).unwrap();
        let e = check("robot.from", "link", d, &confined).unwrap_err();
        assert!(e.message.contains("(it is /etc/hostname)"), "{e}");
        // Allowed by a folder given, or anywhere.
        let etc = FileAccess::under(&["/etc"], AllowedBy::CommandLine).unwrap();
        assert!(check("robot.from", "link", d, &etc).is_ok());
        assert!(check("robot.from", "/etc/hostname", d, &FileAccess::anywhere()).is_ok());
        let e = FileAccess::under(&[d.join("missing")], AllowedBy::CommandLine).unwrap_err();
        assert_eq!(e.key, "--allow-files-under");
    }
}

//! strider's one way in and out of files and stdout (DESIGN.md §7), for the command line, the
//! live view, the loading layer ([`crate::load`]) and snapshots: every input file is read through [`read_text`] or [`read_bytes`], which refuse files over
//! [`MAX_INPUT_BYTES`] at once (pipes and devices such as `/dev/zero` included) and name the
//! file in every error; outputs are written atomically ([`write_atomic`], [`replace_dir`]);
//! data goes to stdout through [`write_stdout`] (or the `outln!` macro), which returns the
//! error of a closed pipe instead of panicking, so `main` can treat it as success.
//!
//! Invariant: a temporary file or directory made here is removed on every way out of the
//! function that made it (error, panic or success), except when the process is killed.

use std::fmt;
use std::io::{self, Read, Write};
use std::path::{Path, PathBuf};

use crate::diagnostic::SourceError;

/// Largest input file strider reads, bytes (64 MiB): far above any map, rule set, FLL engine,
/// CSV, BVH clip or policy file it ships or reads, far below what would exhaust memory.
pub const MAX_INPUT_BYTES: u64 = 64 << 20;

/// The bytes of the file at `path`, at most [`MAX_INPUT_BYTES`] of them.
pub fn read_bytes(path: &Path) -> Result<Vec<u8>, SourceError> {
    let file = path.display().to_string();
    let fail = |message: String| SourceError::new(&file, 0, 0, message);
    let f = std::fs::File::open(path).map_err(|e| fail(format!("cannot read: {e}")))?;
    let meta = f.metadata().map_err(|e| fail(format!("cannot read: {e}")))?;
    if meta.is_dir() {
        return Err(fail("is a directory, not a file".into()));
    }
    let too_big = || fail(format!("larger than the input limit of {} MiB", MAX_INPUT_BYTES >> 20));
    if meta.len() > MAX_INPUT_BYTES {
        return Err(too_big());
    }
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    f.take(MAX_INPUT_BYTES + 1).read_to_end(&mut bytes).map_err(|e| fail(format!("cannot read: {e}")))?;
    if bytes.len() as u64 > MAX_INPUT_BYTES {
        return Err(too_big());
    }
    Ok(bytes)
}

/// The text of the file at `path` (see [`read_bytes`]): UTF-8, a leading byte-order mark
/// dropped; bytes that are not UTF-8 are an error naming their line and column.
pub fn read_text(path: &Path) -> Result<String, SourceError> {
    text_of(read_bytes(path)?, &path.display().to_string())
}

/// `bytes` as text (see [`read_text`]); `file` names it in errors.
pub fn text_of(mut bytes: Vec<u8>, file: &str) -> Result<String, SourceError> {
    if bytes.starts_with(b"\xEF\xBB\xBF") {
        bytes.drain(..3);
    }
    String::from_utf8(bytes).map_err(|e| {
        let valid = &e.as_bytes()[..e.utf8_error().valid_up_to()];
        // The prefix is valid UTF-8 by construction.
        let before = std::str::from_utf8(valid).unwrap_or_default();
        let line = before.matches('\n').count() + 1;
        let col = before.rsplit('\n').next().unwrap_or_default().chars().count() + 1;
        SourceError::new(file, line, col, "the file is not UTF-8 text")
    })
}

/// Writes formatted text to stdout and flushes it; a closed pipe comes back as an
/// [`io::ErrorKind::BrokenPipe`] error, never a panic.
pub fn write_stdout(args: fmt::Arguments) -> io::Result<()> {
    let mut out = io::stdout().lock();
    out.write_fmt(args)?;
    out.flush()
}

/// `println!` for data on stdout, returning an [`io::Result`] (see [`write_stdout`]).
macro_rules! outln {
    ($($arg:tt)*) => {
        $crate::files::write_stdout(format_args!("{}\n", format_args!($($arg)*)))
    };
}
pub(crate) use outln;

/// A temporary path that is removed (file or directory) when dropped, unless kept.
#[derive(Debug)]
pub struct TempPath {
    path: PathBuf,
    keep: bool,
}

impl TempPath {
    /// A hidden temporary name beside `target`: `.NAME.tmpPID` in the same directory, so that
    /// a rename onto `target` never crosses file systems.
    pub fn beside(target: &Path) -> TempPath {
        TempPath { path: temp_name(target, "tmp"), keep: false }
    }

    /// The temporary path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Renames the temporary onto `target`; from then on nothing is removed.
    pub fn persist(mut self, target: &Path) -> io::Result<()> {
        std::fs::rename(&self.path, target)?;
        self.keep = true;
        Ok(())
    }
}

impl Drop for TempPath {
    fn drop(&mut self) {
        if !self.keep {
            let _ = std::fs::remove_file(&self.path).or_else(|_| std::fs::remove_dir_all(&self.path));
        }
    }
}

fn temp_name(target: &Path, tag: &str) -> PathBuf {
    let dir = target.parent().filter(|p| !p.as_os_str().is_empty()).map(PathBuf::from).unwrap_or_else(|| ".".into());
    let name = target.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_else(|| "out".into());
    dir.join(format!(".{name}.{tag}{}", std::process::id()))
}

/// Writes `bytes` to `path` atomically: a temporary file in the same directory, synced, then
/// renamed over `path`. The temporary never outlives the call.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> io::Result<()> {
    let tmp = TempPath::beside(path);
    {
        let mut f = std::fs::File::create(tmp.path())?;
        f.write_all(bytes)?;
        f.sync_all()?;
    }
    tmp.persist(path)
}

/// Checks that a file can be written at `path` (its directory exists and is writable) by
/// creating and removing a temporary file beside it, so a long computation does not end in a
/// write error.
pub fn check_writable(path: &Path) -> Result<(), SourceError> {
    let tmp = TempPath::beside(path);
    std::fs::File::create(tmp.path())
        .map(drop)
        .map_err(|e| SourceError::new(&path.display().to_string(), 0, 0, format!("cannot write here: {e}")))
}

/// Fills a fresh temporary directory beside `dir` with `fill`, then puts it in place of `dir`
/// (which may exist): the old directory is moved aside, the new one renamed in, the old one
/// removed. If `fill` fails, `dir` is left as it was.
pub fn replace_dir<E: From<io::Error>>(dir: &Path, fill: impl FnOnce(&Path) -> Result<(), E>) -> Result<(), E> {
    let mut tmp = TempPath::beside(dir);
    let _ = std::fs::remove_dir_all(tmp.path());
    std::fs::create_dir_all(tmp.path())?;
    fill(tmp.path())?;
    if dir.exists() {
        let old = TempPath { path: temp_name(dir, "old"), keep: false };
        let _ = std::fs::remove_dir_all(old.path());
        std::fs::rename(dir, old.path())?;
        if let Err(e) = std::fs::rename(tmp.path(), dir) {
            let _ = std::fs::rename(old.path(), dir);
            return Err(e.into());
        }
        tmp.keep = true;
        drop(old);
        return Ok(());
    }
    tmp.persist(dir)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("strider-files-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn endless_inputs_are_refused_at_the_limit() {
        let err = read_text(Path::new("/dev/zero")).unwrap_err();
        assert_eq!(err.file, "/dev/zero");
        assert!(err.message.contains("64 MiB"), "{err}");
        let err = read_text(Path::new("/nonexistent/x.fll")).unwrap_err();
        assert!(err.to_string().starts_with("/nonexistent/x.fll: cannot read"), "{err}");
    }

    #[test]
    fn a_byte_order_mark_is_dropped_and_bad_bytes_are_located() {
        assert_eq!(text_of(b"\xEF\xBB\xBFEngine: x\n".to_vec(), "f").unwrap(), "Engine: x\n");
        let err = text_of(b"ab\ncd\xFFe".to_vec(), "f").unwrap_err();
        assert_eq!((err.line, err.col), (2, 3), "{err}");
    }

    #[test]
    fn temporaries_never_outlive_their_writes() {
        let dir = scratch("atomic");
        let target = dir.join("out.bin");
        write_atomic(&target, b"one").unwrap();
        write_atomic(&target, b"two").unwrap();
        assert_eq!(std::fs::read(&target).unwrap(), b"two");
        assert!(write_atomic(&dir.join("missing/out.bin"), b"x").is_err());
        let names: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name()).collect();
        assert_eq!(names.len(), 1, "{names:?}");
        assert!(check_writable(&target).is_ok());
        assert!(check_writable(&dir.join("missing/policy.bin")).is_err());

        let db = dir.join("db");
        replace_dir(&db, |d| std::fs::write(d.join("a"), "1")).unwrap();
        replace_dir(&db, |d| std::fs::write(d.join("b"), "2")).unwrap();
        assert!(!db.join("a").exists() && db.join("b").exists());
        let failed: Result<(), io::Error> = replace_dir(&db, |d| {
            std::fs::write(d.join("c"), "3")?;
            Err(io::Error::other("half-way"))
        });
        assert!(failed.is_err());
        assert!(db.join("b").exists() && !db.join("c").exists());
        let names: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name()).collect();
        assert_eq!(names.len(), 2, "{names:?}");
        let _ = std::fs::remove_dir_all(&dir);
    }
}

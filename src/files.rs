//! strider's one way in and out of files and stdout (DESIGN.md §7), for the command line, the
//! live view, the loading layer ([`crate::load`]) and snapshots: every input file is read through [`read_text`] or [`read_bytes`], which refuse files over
//! [`MAX_INPUT_BYTES`] at once (pipes and devices such as `/dev/zero` included) and name the
//! file in every error; outputs are written atomically ([`write_atomic`], [`replace_dir`]),
//! through symbolic links to the file they name, straight into FIFOs and character devices,
//! never over a directory, and a directory is replaced only when all it holds is strider's;
//! data goes to stdout through [`write_stdout`] (or the `outln!` macro), which returns the
//! error of a closed pipe instead of panicking, so `main` can treat it as success.
//!
//! Invariant: a temporary file or directory made here is removed on every way out of the
//! function that made it (error, panic or success), except when the process is killed; it is
//! always new (made where nothing was), so removing it never removes what strider did not
//! write. Nothing else is removed or renamed over but a regular file being replaced by
//! [`write_atomic`] and a directory whose every entry its writer claims ([`replace_dir`]).

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

/// Most symbolic links followed from one output path to the file it names (as Linux's
/// `MAXSYMLINKS`): more is a loop.
const MAX_LINKS: usize = 40;

/// Temporaries made by this process so far: each gets a name of its own.
static TEMPORARIES: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);

/// A temporary file or directory that strider made itself (never one that was there before),
/// removed when dropped unless kept.
#[derive(Debug)]
struct TempPath {
    path: PathBuf,
    keep: bool,
}

impl TempPath {
    /// A hidden name beside `target` (`.NAME.PID-N.tmp` in the same directory, so that a
    /// rename onto `target` never crosses file systems) that nothing holds yet: `make` creates
    /// the temporary there and fails with [`io::ErrorKind::AlreadyExists`] when something does.
    fn make_beside<T>(target: &Path, make: impl Fn(&Path) -> io::Result<T>) -> io::Result<(TempPath, T)> {
        let dir = parent_of(target);
        let name = target.file_name().map_or_else(|| "out".into(), |n| n.to_string_lossy().into_owned());
        loop {
            let n = TEMPORARIES.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            let path = dir.join(format!(".{name}.{}-{n}.tmp", std::process::id()));
            match make(&path) {
                Ok(made) => return Ok((TempPath { path, keep: false }, made)),
                Err(e) if e.kind() == io::ErrorKind::AlreadyExists => continue,
                Err(e) => return Err(e),
            }
        }
    }

    /// A new empty file beside `target`, open for writing.
    fn file_beside(target: &Path) -> io::Result<(TempPath, std::fs::File)> {
        TempPath::make_beside(target, |p| std::fs::OpenOptions::new().write(true).create_new(true).open(p))
    }

    /// A new empty directory beside `target`.
    fn dir_beside(target: &Path) -> io::Result<TempPath> {
        TempPath::make_beside(target, |p| std::fs::create_dir(p)).map(|(t, ())| t)
    }

    /// Renames the temporary onto `target`; from then on nothing is removed.
    fn persist(mut self, target: &Path) -> io::Result<()> {
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

/// The directory `path` is in (`.` for a bare name).
fn parent_of(path: &Path) -> PathBuf {
    path.parent().filter(|p| !p.as_os_str().is_empty()).map_or_else(|| ".".into(), Path::to_path_buf)
}

/// The path `path` names once every symbolic link at its end is followed (a chain of them,
/// relative ones read from the link's own directory); `path` itself when it is no link. The
/// file there may not exist (a dangling link names the file to create).
pub fn link_target(path: &Path) -> io::Result<PathBuf> {
    let mut at = path.to_path_buf();
    for _ in 0..=MAX_LINKS {
        match std::fs::symlink_metadata(&at) {
            Ok(m) if m.file_type().is_symlink() => {
                let next = std::fs::read_link(&at)?;
                at = if next.is_absolute() { next } else { parent_of(&at).join(next) };
            }
            _ => return Ok(at),
        }
    }
    Err(io::Error::other(format!("more than {MAX_LINKS} symbolic links from {}: a loop", path.display())))
}

/// What an output path holds, once its links are followed.
enum Target {
    /// Nothing yet, or a regular file (with its permissions): written through a temporary
    /// renamed onto it.
    File(Option<std::fs::Permissions>),
    /// A FIFO or a character device (a terminal, `/dev/null`): written straight into.
    Stream,
}

/// What `target` (a path with no link at its end) holds; an error for what strider never writes
/// over: a directory, a block device, a socket.
fn target_kind(target: &Path) -> io::Result<Target> {
    use std::os::unix::fs::FileTypeExt;
    let meta = match std::fs::metadata(target) {
        Ok(m) => m,
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(Target::File(None)),
        Err(e) => return Err(e),
    };
    let t = meta.file_type();
    if t.is_file() {
        Ok(Target::File(Some(meta.permissions())))
    } else if t.is_fifo() || t.is_char_device() {
        Ok(Target::Stream)
    } else if t.is_dir() {
        Err(io::Error::new(io::ErrorKind::IsADirectory, "is a directory, not a file"))
    } else {
        Err(io::Error::other("is a block device or a socket: strider writes only files, FIFOs and character devices"))
    }
}

/// Writes `bytes` to `path`. A symbolic link is followed to the file it names (which is
/// written, the link kept); a regular file (or none) is replaced atomically: a temporary file
/// in the same directory, synced, then renamed over it, with the old file's permissions; a
/// FIFO or a character device is written straight into; a directory, block device or socket
/// is an error, and is left as it was. The temporary never outlives the call.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> io::Result<()> {
    let target = link_target(path)?;
    match target_kind(&target)? {
        Target::Stream => std::fs::OpenOptions::new().write(true).open(&target)?.write_all(bytes),
        Target::File(permissions) => {
            let (tmp, mut f) = TempPath::file_beside(&target)?;
            f.write_all(bytes)?;
            if let Some(p) = permissions {
                f.set_permissions(p)?;
            }
            f.sync_all()?;
            drop(f);
            tmp.persist(&target)
        }
    }
}

/// Checks that a file can be written at `path` (see [`write_atomic`]: its directory exists and
/// is writable, it is no directory) by creating and removing a temporary file beside it, so a
/// long computation does not end in a write error.
pub fn check_writable(path: &Path) -> Result<(), SourceError> {
    let fail = |e: io::Error| SourceError::new(&path.display().to_string(), 0, 0, format!("cannot write here: {e}"));
    let target = link_target(path).map_err(fail)?;
    match target_kind(&target).map_err(fail)? {
        Target::Stream => Ok(()),
        Target::File(_) => TempPath::file_beside(&target).map(drop).map_err(fail),
    }
}

/// The first entry under `dir` (a path relative to it) that `owned` does not claim, depth
/// first in name order; links, and folders not claimed, are not looked into.
fn first_foreign(dir: &Path, rel: &Path, owned: &dyn Fn(&Path) -> bool) -> io::Result<Option<PathBuf>> {
    let mut entries: Vec<_> = std::fs::read_dir(dir.join(rel))?.collect::<Result<_, _>>()?;
    entries.sort_by_key(std::fs::DirEntry::file_name);
    for e in entries {
        let name = rel.join(e.file_name());
        let t = e.file_type()?;
        if !(t.is_file() || t.is_dir()) || !owned(&name) {
            return Ok(Some(name));
        }
        if t.is_dir()
            && let Some(f) = first_foreign(dir, &name, owned)?
        {
            return Ok(Some(f));
        }
    }
    Ok(None)
}

/// Puts every entry under `old` that `owned` does not claim at the same place under `new`:
/// a hard link to it (to the link itself for a symbolic link), folders made anew with their
/// permissions; claimed folders are looked into. An entry `new` already holds is an error.
fn keep_foreign(old: &Path, new: &Path, rel: &Path, owned: &dyn Fn(&Path) -> bool) -> io::Result<()> {
    for e in std::fs::read_dir(old.join(rel))? {
        let e = e?;
        let name = rel.join(e.file_name());
        let is_dir = e.file_type()?.is_dir();
        if owned(&name) {
            // A claimed folder the new set lacks is made for what it holds of the user's.
            let made = is_dir && !new.join(&name).is_dir() && std::fs::create_dir(new.join(&name)).is_ok();
            if is_dir {
                keep_foreign(old, new, &name, owned)?;
            }
            if made {
                let _ = std::fs::remove_dir(new.join(&name));
            }
            continue;
        }
        let at = new.join(&name);
        if std::fs::symlink_metadata(&at).is_ok() {
            return Err(io::Error::other(format!("cannot keep {}: strider writes one of that name", name.display())));
        }
        let keep = |e: io::Error| io::Error::other(format!("cannot keep {}: {e}", name.display()));
        if is_dir {
            std::fs::create_dir(&at).map_err(keep)?;
            std::fs::set_permissions(&at, e.metadata()?.permissions()).map_err(keep)?;
            keep_foreign(old, new, &name, &|_| false)?;
        } else {
            std::fs::hard_link(e.path(), &at).map_err(keep)?;
        }
    }
    Ok(())
}

/// Swaps the directories `a` and `b` in one step where the system can (Linux's
/// `renameat2(RENAME_EXCHANGE)`); `false` where it cannot.
fn exchange(a: &Path, b: &Path) -> io::Result<bool> {
    #[cfg(target_os = "linux")]
    {
        use rustix::fs::{CWD, RenameFlags, renameat_with};
        match renameat_with(CWD, a, CWD, b, RenameFlags::EXCHANGE) {
            Ok(()) => Ok(true),
            Err(e) if e == rustix::io::Errno::INVAL || e == rustix::io::Errno::NOSYS => Ok(false),
            Err(e) => Err(e.into()),
        }
    }
    #[cfg(not(target_os = "linux"))]
    {
        let _ = (a, b);
        Ok(false)
    }
}

/// What [`replace_dir`] does with the entries of the old directory that its writer does not
/// claim (the user's).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Others {
    /// Refuse to write: nothing happens, and the error names the first such entry.
    Refuse,
    /// Keep them: each goes into the new directory as it was (a hard link to the same file,
    /// folders made anew around them) before it takes the old one's place.
    Keep,
}

/// Writes the directory `dir` as a whole: `fill` fills a fresh temporary directory beside it,
/// which then takes `dir`'s place in one step (Linux swaps the two; elsewhere the old one is
/// moved aside first), and the old directory is removed. A link to a directory is followed
/// (the directory it names is replaced, the link kept).
///
/// What is replaced is only what `owned` claims (paths relative to `dir`; a claimed folder's
/// entries are asked about in turn); `others` says what becomes of the rest. A file where the
/// folder should be is an error. If `fill` fails, or an entry cannot be kept, `dir` is left
/// as it was. Every error names `dir`.
pub fn replace_dir<E: From<io::Error>>(
    dir: &Path,
    owned: &dyn Fn(&Path) -> bool,
    others: Others,
    fill: impl FnOnce(&Path) -> Result<(), E>,
) -> Result<(), E> {
    let named = |shown: &str, message: &dyn fmt::Display| io::Error::other(format!("{shown}: {message}"));
    let given = dir.display().to_string();
    let target = link_target(dir).map_err(|e| named(&given, &e))?;
    // `.`, `..` and the like have no name to rename: take the folder's own path.
    let target = match std::fs::canonicalize(&target) {
        Ok(t) => t,
        Err(e) if e.kind() == io::ErrorKind::NotFound => target,
        Err(e) => return Err(named(&given, &e).into()),
    };
    // A folder given as `.` or through a link is named both ways.
    let plain = dir.file_name().is_some() && link_target(dir).is_ok_and(|t| t == dir);
    let shown = if plain { given } else { format!("{given} ({})", target.display()) };
    let fail = |e: io::Error| named(&shown, &e);
    if target.file_name().is_none() {
        return Err(named(&shown, &"cannot replace the root folder").into());
    }
    // Replaced whole, the working folder would leave the shell in a removed one.
    if std::env::current_dir().and_then(std::fs::canonicalize).is_ok_and(|cwd| cwd == target) {
        return Err(named(
            &shown,
            &"is the current folder, which strider cannot replace whole: give a folder inside it",
        )
        .into());
    }
    let exists = match std::fs::symlink_metadata(&target) {
        Ok(m) if m.is_dir() => true,
        Ok(_) => return Err(named(&shown, &"exists and is not a folder: strider writes the folder itself").into()),
        Err(e) if e.kind() == io::ErrorKind::NotFound => false,
        Err(e) => return Err(fail(e).into()),
    };
    if exists
        && others == Others::Refuse
        && let Some(foreign) = first_foreign(&target, Path::new(""), owned).map_err(fail)?
    {
        let why = format!(
            "holds {}, which strider did not write: give a new or empty folder (strider replaces only what it wrote)",
            foreign.display()
        );
        return Err(named(&shown, &why).into());
    }
    std::fs::create_dir_all(parent_of(&target)).map_err(fail)?;
    let tmp = TempPath::dir_beside(&target).map_err(fail)?;
    fill(&tmp.path)?;
    if exists && others == Others::Keep {
        keep_foreign(&target, &tmp.path, Path::new(""), owned).map_err(fail)?;
    }
    if !exists {
        return Ok(tmp.persist(&target).map_err(fail)?);
    }
    // The old directory ends where the new one was made, and goes with it.
    if exchange(&tmp.path, &target).map_err(fail)? {
        return Ok(());
    }
    let old = TempPath::dir_beside(&target).map_err(fail)?;
    std::fs::rename(&target, &old.path).map_err(fail)?;
    if let Err(e) = std::fs::rename(&tmp.path, &target) {
        let _ = std::fs::rename(&old.path, &target);
        return Err(fail(e).into());
    }
    let mut tmp = tmp;
    tmp.keep = true;
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
        let all: &dyn Fn(&Path) -> bool = &|_| true;
        replace_dir(&db, all, Others::Refuse, |d| std::fs::write(d.join("a"), "1")).unwrap();
        replace_dir(&db, all, Others::Refuse, |d| std::fs::write(d.join("b"), "2")).unwrap();
        assert!(!db.join("a").exists() && db.join("b").exists());
        let failed: Result<(), io::Error> = replace_dir(&db, all, Others::Refuse, |d| {
            std::fs::write(d.join("c"), "3")?;
            Err(io::Error::other("half-way"))
        });
        assert!(failed.is_err());
        assert!(db.join("b").exists() && !db.join("c").exists());
        let names: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name()).collect();
        assert_eq!(names.len(), 2, "{names:?}");
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn outputs_go_through_links_into_fifos_and_never_over_directories() {
        use std::os::unix::fs::{FileTypeExt, symlink};
        let dir = scratch("special");
        // A chain of links, the second relative: the file at its end is written, the links kept.
        std::fs::create_dir_all(dir.join("sub")).unwrap();
        std::fs::write(dir.join("sub/t.png"), "old").unwrap();
        symlink("t.png", dir.join("sub/l1")).unwrap();
        symlink(dir.join("sub/l1"), dir.join("l2")).unwrap();
        write_atomic(&dir.join("l2"), b"new").unwrap();
        assert!(std::fs::symlink_metadata(dir.join("l2")).unwrap().file_type().is_symlink());
        assert!(std::fs::symlink_metadata(dir.join("sub/l1")).unwrap().file_type().is_symlink());
        assert_eq!(std::fs::read(dir.join("sub/t.png")).unwrap(), b"new");
        // A dangling link names the file to make.
        symlink("made.png", dir.join("dangling")).unwrap();
        write_atomic(&dir.join("dangling"), b"x").unwrap();
        assert_eq!(std::fs::read(dir.join("made.png")).unwrap(), b"x");
        symlink("loop_b", dir.join("loop_a")).unwrap();
        symlink("loop_a", dir.join("loop_b")).unwrap();
        assert!(write_atomic(&dir.join("loop_a"), b"x").unwrap_err().to_string().contains("loop"));
        // A directory is refused and left as it was.
        std::fs::create_dir(dir.join("d")).unwrap();
        std::fs::write(dir.join("d/keep"), "k").unwrap();
        let e = write_atomic(&dir.join("d"), b"x").unwrap_err();
        assert_eq!(e.kind(), io::ErrorKind::IsADirectory, "{e}");
        assert!(check_writable(&dir.join("d")).is_err());
        assert_eq!(std::fs::read(dir.join("d/keep")).unwrap(), b"k");
        // A character device is written into, not replaced.
        write_atomic(Path::new("/dev/null"), b"x").unwrap();
        assert!(std::fs::metadata("/dev/null").unwrap().file_type().is_char_device());
        // A FIFO is written into while a reader reads.
        let fifo = dir.join("fifo");
        assert!(std::process::Command::new("mkfifo").arg(&fifo).status().unwrap().success());
        let reader = {
            let fifo = fifo.clone();
            std::thread::spawn(move || std::fs::read(fifo).unwrap())
        };
        write_atomic(&fifo, b"through the pipe").unwrap();
        assert_eq!(reader.join().unwrap(), b"through the pipe");
        assert!(std::fs::metadata(&fifo).unwrap().file_type().is_fifo());
        check_writable(&fifo).unwrap();
        // A replaced file keeps its permissions.
        use std::os::unix::fs::PermissionsExt;
        let plain = dir.join("mode.txt");
        std::fs::write(&plain, "a").unwrap();
        std::fs::set_permissions(&plain, std::fs::Permissions::from_mode(0o640)).unwrap();
        write_atomic(&plain, b"b").unwrap();
        assert_eq!(std::fs::metadata(&plain).unwrap().permissions().mode() & 0o777, 0o640);
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn a_directory_is_replaced_only_when_all_it_holds_is_claimed() {
        use std::os::unix::fs::symlink;
        let dir = scratch("replace");
        let out = dir.join("out");
        let ours: &dyn Fn(&Path) -> bool = &|p| ["data", "data/x", "m"].iter().any(|o| p == Path::new(o));
        let fill = |d: &Path| -> io::Result<()> {
            std::fs::create_dir(d.join("data"))?;
            std::fs::write(d.join("data/x"), "new")?;
            std::fs::write(d.join("m"), "manifest")
        };
        // Empty: taken.
        std::fs::create_dir(&out).unwrap();
        replace_dir(&out, ours, Others::Refuse, fill).unwrap();
        assert_eq!(std::fs::read(out.join("data/x")).unwrap(), b"new");
        // Foreign entries, at the top or further in: refused, named, untouched.
        std::fs::write(out.join("precious.txt"), "mine").unwrap();
        let e = replace_dir(&out, ours, Others::Refuse, fill).unwrap_err().to_string();
        assert!(e.contains("precious.txt") && e.contains(&out.display().to_string()), "{e}");
        assert_eq!(std::fs::read(out.join("precious.txt")).unwrap(), b"mine");
        std::fs::remove_file(out.join("precious.txt")).unwrap();
        symlink("/etc", out.join("data/link")).unwrap();
        let e = replace_dir(&out, ours, Others::Refuse, fill).unwrap_err().to_string();
        assert!(e.contains("data/link"), "{e}");
        std::fs::remove_file(out.join("data/link")).unwrap();
        // Or kept: the same files, linked into the new folder.
        std::fs::create_dir_all(out.join("data/mine")).unwrap();
        std::fs::write(out.join("data/mine/a"), "a").unwrap();
        std::fs::write(out.join("notes"), "n").unwrap();
        symlink("/etc", out.join("data/link")).unwrap();
        std::fs::write(out.join("data/x"), "old").unwrap();
        replace_dir(&out, ours, Others::Keep, fill).unwrap();
        assert_eq!(std::fs::read(out.join("data/x")).unwrap(), b"new");
        assert_eq!(std::fs::read(out.join("data/mine/a")).unwrap(), b"a");
        assert_eq!(std::fs::read(out.join("notes")).unwrap(), b"n");
        assert_eq!(std::fs::read_link(out.join("data/link")).unwrap(), Path::new("/etc"));
        for p in ["data/mine", "notes", "data/link"] {
            let _ = std::fs::remove_file(out.join(p)).or_else(|_| std::fs::remove_dir_all(out.join(p)));
        }
        // A file is no folder.
        std::fs::write(dir.join("file"), "f").unwrap();
        assert!(replace_dir(&dir.join("file"), ours, Others::Refuse, fill).is_err());
        assert_eq!(std::fs::read(dir.join("file")).unwrap(), b"f");
        // A link to a folder: the folder is replaced, the link kept.
        std::fs::write(out.join("data/x"), "old").unwrap();
        symlink(&out, dir.join("link")).unwrap();
        replace_dir(&dir.join("link"), ours, Others::Refuse, fill).unwrap();
        assert!(std::fs::symlink_metadata(dir.join("link")).unwrap().file_type().is_symlink());
        assert_eq!(std::fs::read(out.join("data/x")).unwrap(), b"new");
        // Nothing left beside.
        let mut names: Vec<_> =
            std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).collect();
        names.sort();
        assert_eq!(names, ["file", "link", "out"]);
        let _ = std::fs::remove_dir_all(&dir);
    }
}

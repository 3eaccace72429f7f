//! What the integration tests share: running the real `strider` binary the way a user does.
//! Each test crate takes what it needs (`mod common;`), so not every helper is used by every crate.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Runs the `strider` binary built with these tests, from the repository root (where `maps/`
/// and `scripts/` are), with `args`, and waits for it.
pub fn strider(args: &[&str]) -> Output {
    strider_with_env(args, &[])
}

/// As [`strider`], with extra environment variables. The switch that writes snapshot goldens
/// is never inherited from the environment the tests run in.
pub fn strider_with_env(args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut command = strider_command(args);
    for (key, value) in env {
        command.env(key, value);
    }
    command.output().expect("run the strider binary")
}

/// As [`strider`], run from the folder `dir` instead of the repository root.
pub fn strider_in(dir: &Path, args: &[&str]) -> Output {
    strider_command(args).current_dir(dir).output().expect("run the strider binary")
}

/// The command [`strider`] runs, not started yet (to start it and act while it runs).
pub fn strider_command(args: &[&str]) -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_strider"));
    command.args(args).current_dir(env!("CARGO_MANIFEST_DIR")).env_remove("STRIDER_UPDATE_GOLDEN");
    command
}

/// The binary's standard output as text.
pub fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// The binary's standard error as text.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// As [`strider`], with the process's address space limited to `kib` KiB (`ulimit -v`), so a
/// run that would fill memory fails there instead of taking the machine's.
pub fn strider_in_address_space(args: &[&str], kib: u64) -> Output {
    Command::new("sh")
        .arg("-c")
        .arg(format!("ulimit -v {kib} && exec \"$0\" \"$@\""))
        .arg(env!("CARGO_BIN_EXE_strider"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .env_remove("STRIDER_UPDATE_GOLDEN")
        .output()
        .expect("run the strider binary")
}

/// A fresh, empty folder `name` for one test, under this test crate's folder in Cargo's
/// temporary directory.
pub fn temp_dir(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(env!("CARGO_CRATE_NAME")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Exit code 2 and a message on stderr containing every one of `needles`, no panic.
#[track_caller]
pub fn refused(o: &Output, needles: &[&str]) {
    let e = stderr(o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    for n in needles {
        assert!(e.contains(n), "'{n}' not in: {e}");
    }
    assert!(!e.contains("panicked"), "{e}");
}

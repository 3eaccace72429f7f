//! Where the live view's world and rules come from, and hot reload (DESIGN.md §6): maps and
//! rule scripts are loaded by the front-ends' loading layer ([`crate::load`]) with
//! their script output kept for the log panel (never printed: stdout and stderr belong to the
//! terminal UI), and files are watched by polling their modification time.
//!
//! Invariant: a failed load returns the error and changes nothing, so a broken edit leaves
//! the last good version running.

use std::path::{Path, PathBuf};
use std::time::SystemTime;

pub use crate::load::{Loaded, MapSpec, load_rules, load_scenario};

/// Watches one file by its modification time.
#[derive(Debug, Clone)]
pub struct Watched {
    path: PathBuf,
    stamp: Option<SystemTime>,
}

impl Watched {
    /// Starts watching `path` from its current state.
    pub fn new(path: &Path) -> Watched {
        Watched { path: path.to_path_buf(), stamp: mtime(path) }
    }

    /// The watched path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// True (once) when the file's modification time changed since the last call.
    pub fn changed(&mut self) -> bool {
        let now = mtime(&self.path);
        if now != self.stamp && now.is_some() {
            self.stamp = now;
            true
        } else {
            false
        }
    }
}

fn mtime(path: &Path) -> Option<SystemTime> {
    std::fs::metadata(path).and_then(|m| m.modified()).ok()
}

//! The architecture invariant of ARCHITECTURE.md, checked on the sources: the core does no IO,
//! reads no clock and owns no global random generator, and never calls into a script. A core
//! module that named a clock, the file system, the process environment, a thread-local or OS
//! random generator, the script engine, or printed, would fail here.

use std::path::{Path, PathBuf};

/// The core: every layer of ARCHITECTURE.md up to and including simulation.
const CORE: &[&str] = &[
    "rng",
    "diagnostic",
    "lex",
    "geom",
    "ground",
    "anim",
    "footstep",
    "world",
    "fuzzy",
    "plan",
    "upper",
    "scenario",
    "maps",
    "sim",
    "experiment",
    "baseline",
];

/// What the core may not name.
const FORBIDDEN: &[&str] = &[
    "std::fs",
    "std::env",
    "std::net",
    "std::process",
    "File::open",
    "Instant::now",
    "SystemTime",
    "thread_rng",
    "rand::random",
    "from_entropy",
    "OsRng",
    "println!",
    "eprintln!",
    "print!(",
    "stdout()",
    "stdin()",
    // Scripts only build plain data the core validates: the core never calls into one.
    "rhai::",
    "Engine::new_raw",
];

fn sources(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            sources(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

#[test]
fn the_core_does_no_io_reads_no_clock_and_owns_no_global_rng() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    for m in CORE {
        files.push(src.join(format!("{m}.rs")));
        let dir = src.join(m);
        if dir.is_dir() {
            sources(&dir, &mut files);
        }
    }
    let mut found = Vec::new();
    for f in &files {
        let text = std::fs::read_to_string(f).unwrap();
        // Unit tests may write temporary files; only the code before them counts.
        let code = text.split("#[cfg(test)]").next().unwrap_or("");
        for (n, line) in code.lines().enumerate() {
            let line = line.split("//").next().unwrap_or("");
            for bad in FORBIDDEN {
                if line.contains(bad) {
                    found.push(format!("{}:{}: {bad}", f.strip_prefix(&src).unwrap().display(), n + 1));
                }
            }
        }
    }
    assert!(found.is_empty(), "the core names IO, a clock or a global generator:\n{}", found.join("\n"));
}

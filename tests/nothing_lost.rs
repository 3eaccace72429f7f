//! Nothing lost: strider never destroys a user's files, never throws a run's results away, and
//! merges only what is exactly one run. Every file here is made by the test in a folder of its
//! own.

mod common;

use common::{stderr, stdout, strider, strider_command, strider_in};

use std::os::unix::fs::{FileTypeExt, symlink};
use std::path::{Path, PathBuf};

/// A fresh scratch folder of this test.
fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("nothing_lost").join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Every file under `dir` (relative paths) with its bytes, sorted; what vanishes while it is
/// read (a running strider renaming its temporaries) is left out.
fn contents(dir: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    fn walk(root: &Path, dir: &Path, out: &mut Vec<(PathBuf, Vec<u8>)>) {
        for p in std::fs::read_dir(dir).into_iter().flatten().flatten().map(|e| e.path()) {
            if p.is_dir() {
                walk(root, &p, out);
            } else if let Ok(bytes) = std::fs::read(&p) {
                out.push((p.strip_prefix(root).unwrap().to_path_buf(), bytes));
            }
        }
    }
    let mut out = Vec::new();
    walk(dir, dir, &mut out);
    out.sort();
    out
}

#[test]
fn a_database_is_written_only_where_nothing_of_the_users_would_go() {
    let dir = scratch("db");
    let d = dir.join("d");
    std::fs::create_dir_all(d.join("sub")).unwrap();
    std::fs::write(d.join("precious.txt"), "x").unwrap();
    std::fs::write(d.join("sub/k"), "y").unwrap();
    let before = contents(&d);
    let o = strider(&["db", "export", "--out", s(&d)]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("precious.txt") && stderr(&o).contains(s(&d)), "{}", stderr(&o));
    assert_eq!(contents(&d), before);
    // A new folder, then the same database replaced whole; a file added to it is the user's.
    let e = dir.join("e");
    for _ in 0..2 {
        let o = strider(&["db", "export", "--out", s(&e)]);
        assert!(o.status.success(), "{}", stderr(&o));
    }
    assert!(strider(&["db", "info", s(&e)]).status.success());
    let mut clips: Vec<PathBuf> = std::fs::read_dir(e.join("clips")).unwrap().map(|f| f.unwrap().path()).collect();
    clips.sort();
    let some = dir.join("some");
    std::fs::create_dir(&some).unwrap();
    for c in &clips[..8] {
        std::fs::copy(c, some.join(c.file_name().unwrap())).unwrap();
    }
    let mut build = vec!["db", "build", "--bvh"];
    build.extend(clips[..8].iter().map(|c| s(c)));
    build.extend(["--out", s(&e)]);
    std::fs::write(e.join("clips/notes.txt"), "mine").unwrap();
    let o = strider(&build);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("clips/notes.txt"), "{}", stderr(&o));
    assert_eq!(std::fs::read(e.join("clips/notes.txt")).unwrap(), b"mine");
    // Without it, the new database takes the old one's place whole.
    std::fs::remove_file(e.join("clips/notes.txt")).unwrap();
    let build: Vec<String> = build.iter().map(|a| a.replace(s(&e.join("clips")), s(&some))).collect();
    let o = strider(&build.iter().map(String::as_str).collect::<Vec<_>>());
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(std::fs::read_dir(e.join("clips")).unwrap().count(), 8);
    // The current folder is named, and kept.
    let o = strider_in(&d, &["db", "export", "--out", "."]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains(&format!(". ({})", d.canonicalize().unwrap().display())), "{}", stderr(&o));
    assert_eq!(contents(&d), before);
    // A file where the folder should be is no folder.
    let o = strider(&["db", "export", "--out", s(&d.join("precious.txt"))]);
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(contents(&d), before);
    // Nothing is left beside them.
    let mut names: Vec<String> =
        std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).collect();
    names.sort();
    assert_eq!(names, ["d", "e", "some"]);
}

#[test]
fn outputs_go_through_links_and_into_fifos() {
    let dir = scratch("special");
    let profile = "maps/profiles/stairs.profile";
    // A link: the file it names is written, the link kept.
    symlink("t.png", dir.join("l.png")).unwrap();
    let o = strider(&["steps", profile, "--png", s(&dir.join("l.png"))]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(std::fs::symlink_metadata(dir.join("l.png")).unwrap().file_type().is_symlink());
    assert!(std::fs::read(dir.join("t.png")).unwrap().starts_with(b"\x89PNG"));
    // A FIFO: written into while a reader reads, and still a FIFO.
    let fifo = dir.join("f.png");
    assert!(std::process::Command::new("mkfifo").arg(&fifo).status().unwrap().success());
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::read(fifo).unwrap())
    };
    let o = strider(&["steps", profile, "--png", s(&fifo)]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(reader.join().unwrap(), std::fs::read(dir.join("t.png")).unwrap());
    assert!(std::fs::metadata(&fifo).unwrap().file_type().is_fifo());
    // A folder: refused, named, kept.
    std::fs::create_dir(dir.join("d.png")).unwrap();
    std::fs::write(dir.join("d.png/keep"), "k").unwrap();
    let o = strider(&["steps", profile, "--png", s(&dir.join("d.png"))]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("d.png") && stderr(&o).contains("directory"), "{}", stderr(&o));
    assert_eq!(std::fs::read(dir.join("d.png/keep")).unwrap(), b"k");
    // A character device is written into (and left one).
    let o = strider(&["steps", profile, "--png", "/dev/null"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(std::fs::metadata("/dev/null").unwrap().file_type().is_char_device());
}

#[test]
fn a_motion_file_that_cannot_be_written_keeps_the_results() {
    let dir = scratch("bvh");
    std::fs::create_dir_all(dir.join("episode_1.bvh")).unwrap();
    let o = strider(&["run", "random:sparse", "--episodes", "3", "--bvh-out", s(&dir)]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let doc: serde_json::Value = serde_json::from_slice(&o.stdout).expect("the results on stdout");
    assert_eq!(doc["episodes"].as_array().unwrap().len(), 3);
    let err = stderr(&o);
    assert!(err.contains(s(&dir.join("episode_1.bvh"))) && err.contains("1 of 3 motion files"), "{err}");
    assert!(dir.join("episode_0.bvh").is_file() && dir.join("episode_2.bvh").is_file());
    assert!(dir.join("episode_1.bvh").is_dir());
}

#[test]
fn an_interrupted_snapshot_update_leaves_the_old_goldens_whole() {
    let dir = scratch("snapshot");
    let golden = dir.join("golden");
    let args = |size: &'static str| {
        ["snapshot", "maps/u_trap.rhai", "--every", "1", "--size", size, "--update", "--golden", s(&golden)]
            .map(String::from)
    };
    let old_args = args("64x64");
    let o = strider(&old_args.iter().map(String::as_str).collect::<Vec<_>>());
    assert!(o.status.success(), "{}", stderr(&o));
    let old = contents(&golden);
    // An update to other frames, killed as soon as it has written a new frame anywhere.
    let new_args = args("400x400");
    let mut child =
        strider_command(&new_args.iter().map(String::as_str).collect::<Vec<_>>()).spawn().expect("start strider");
    let changed = |old: &[(PathBuf, Vec<u8>)]| {
        contents(&dir).iter().any(|(p, b)| {
            p.extension().is_some_and(|e| e == "png")
                && old.iter().find(|(q, _)| golden.join(q) == dir.join(p)).is_none_or(|(_, a)| a != b)
        })
    };
    while !changed(&old) && child.try_wait().unwrap().is_none() {
        std::thread::yield_now();
    }
    child.kill().unwrap();
    child.wait().unwrap();
    assert_eq!(contents(&golden), old, "the killed update changed the goldens");
    // A finished update replaces them whole, the folder's other files kept as they were.
    std::fs::create_dir_all(golden.join("notes")).unwrap();
    std::fs::write(golden.join("notes/today.md"), "mine").unwrap();
    let o = strider(&new_args.iter().map(String::as_str).collect::<Vec<_>>());
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(contents(&golden).len(), old.len() + 1);
    assert_eq!(std::fs::read(golden.join("notes/today.md")).unwrap(), b"mine");
}

/// Runs `args` in `n` shards into files of `dir` named `NAME_I.EXT` and returns them.
fn shards(dir: &Path, name: &str, args: &[&str], n: usize, ext: &str) -> Vec<String> {
    (0..n)
        .map(|i| {
            let shard = format!("{i}/{n}");
            let mut a = args.to_vec();
            a.extend(["--shard", &shard]);
            let o = strider(&a);
            let file = dir.join(format!("{name}_{i}.{ext}"));
            std::fs::write(&file, &o.stdout).unwrap();
            file.display().to_string()
        })
        .collect()
}

/// `strider merge FILES` exits 2 with a message holding `needle`.
fn refused(files: &[&str], needle: &str) {
    let mut args = vec!["merge"];
    args.extend(files);
    let o = strider(&args);
    assert_eq!(o.status.code(), Some(2), "merge {files:?}: {}", stderr(&o));
    assert!(stderr(&o).contains(needle), "merge {files:?}: '{}' lacks '{needle}'", stderr(&o));
    assert!(o.stdout.is_empty());
}

#[test]
fn merge_refuses_what_is_not_exactly_one_whole_run() {
    let dir = scratch("merge");
    let run = ["run", "random:sparse", "--episodes", "5", "--body", "disc"];
    let json = shards(&dir, "a", &run, 3, "json");
    let j: Vec<&str> = json.iter().map(String::as_str).collect();
    refused(&j[..2], "shard 2/3 of the run is missing");
    refused(&j[1..2], "is missing");
    std::fs::write(dir.join("empty.json"), "").unwrap();
    refused(&[s(&dir.join("empty.json"))], "no run identity");
    // The whole run's own output is no shard.
    std::fs::write(dir.join("whole.json"), strider(&run).stdout).unwrap();
    refused(&[s(&dir.join("whole.json"))], "no run identity");
    // Shards of other runs: seed, body, rules, episode count, shard count, map contents.
    let other = |name: &str, extra: &[&str], shard: &str| {
        let mut a = run.to_vec();
        a.extend(extra);
        a.extend(["--shard", shard]);
        let file = dir.join(format!("{name}.json"));
        std::fs::write(&file, strider(&a).stdout).unwrap();
        file.display().to_string()
    };
    refused(&[j[0], j[1], &other("seed", &["--seed", "2"], "2/3")], "another seed");
    // Rules are what they do: a copy with a comment is the same rules, a changed term is not.
    let nav = std::fs::read_to_string("scripts/nav.rhai").unwrap();
    let (same, changed) = (dir.join("same.rhai"), dir.join("changed.rhai"));
    std::fs::write(&same, format!("// a copy\n{nav}")).unwrap();
    assert!(nav.contains(r#"tri(v, "zero", -10.0, 0.0, 10.0)"#));
    std::fs::write(&changed, nav.replace(r#"tri(v, "zero", -10.0, 0.0, 10.0)"#, r#"tri(v, "zero", -12.0, 0.0, 12.0)"#))
        .unwrap();
    let copy = other("same", &["--rules", s(&same)], "2/3");
    assert!(strider(&["merge", j[0], j[1], &copy]).status.success());
    refused(&[j[0], j[1], &other("rules", &["--rules", s(&changed)], "2/3")], "another rules");
    refused(&[j[0], j[1], &other("split", &[], "2/4")], "another shard count");
    for (name, args, needle) in [
        ("body", ["run", "random:sparse", "--episodes", "5", "--body", "animated"], "another body"),
        ("count", ["run", "random:sparse", "--episodes", "6", "--body", "disc"], "another episode count"),
    ] {
        let third = shards(&dir, name, &args, 3, "json");
        refused(&[j[0], j[1], &third[2]], needle);
    }
    // The same map name with other contents.
    let map = dir.join("m.txt");
    let world = |goal: &str| format!("start 0 0\ngoal {goal} 0\nstart 0 2\ngoal {goal} 2\n");
    std::fs::write(&map, world("5")).unwrap();
    let on_map = ["run", s(&map), "--body", "disc"];
    let first = shards(&dir, "m1", &on_map, 2, "json");
    std::fs::write(&map, world("6")).unwrap();
    let second = shards(&dir, "m2", &on_map, 2, "json");
    refused(&[&first[0], &second[1]], "another worlds");
    // Counts no run has are refused, not allocated.
    let text = std::fs::read_to_string(j[0]).unwrap();
    for (name, from, to, needle) in [
        ("huge_count.json", "\"shard\": \"0/3\"", "\"shard\": \"0/18446744073709551615\"", "not its"),
        ("huge_run.json", "\"episodes\": 5,", "\"episodes\": 18446744073709551615,", "strider runs 1 to"),
    ] {
        assert!(text.contains(from), "{from}");
        std::fs::write(dir.join(name), text.replace(from, to)).unwrap();
        refused(&[s(&dir.join(name))], needle);
    }
    // The whole set merges, in any order.
    let o = strider(&["merge", j[2], j[0], j[1]]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(stdout(&o), stdout(&strider(&run)));
}

#[test]
fn merge_refuses_cut_csv_shards() {
    let dir = scratch("merge_csv");
    let run = ["run", "random:sparse", "--episodes", "5", "--body", "disc", "--format", "csv"];
    let csv = shards(&dir, "c", &run, 2, "csv");
    let text = std::fs::read_to_string(&csv[0]).unwrap();
    let cut = |name: &str, text: &str| {
        let file = dir.join(name);
        std::fs::write(&file, text).unwrap();
        file.display().to_string()
    };
    // Cut inside a row, at a cell's end with the line ended, and a whole row off.
    let rows: Vec<&str> = text.lines().collect();
    let last = rows.last().unwrap();
    let cells = last.split(',').count();
    let shorter = last.split(',').take(cells - 20).collect::<Vec<_>>().join(",");
    let no_end = cut("no_end.csv", &text[..text.len() - 5]);
    let short_row = cut("short_row.csv", &format!("{}\n{shorter}\n", rows[..rows.len() - 1].join("\n")));
    let one_row_less = cut("one_row_less.csv", &format!("{}\n", rows[..rows.len() - 1].join("\n")));
    refused(&[&no_end, &csv[1]], "cut short");
    refused(&[&short_row, &csv[1]], "cells");
    refused(&[&one_row_less, &csv[1]], "cut short");
    let o = strider(&["merge", &csv[1], &csv[0]]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(stdout(&o), stdout(&strider(&run)));
}

#[test]
fn every_json_integer_survives_a_reader_of_doubles() {
    let o = strider(&["run", "random:sparse", "--episodes", "3", "--body", "disc", "--shard", "0/1"]);
    let doc: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    fn check(v: &serde_json::Value) {
        match v {
            serde_json::Value::Number(n) => {
                if let Some(i) = n.as_u64() {
                    assert!(i <= 1 << 53, "{i} is above 2^53");
                }
            }
            serde_json::Value::Array(a) => a.iter().for_each(check),
            serde_json::Value::Object(o) => o.values().for_each(check),
            _ => {}
        }
    }
    check(&doc);
    // The seeds are strings of their digits, the same as the CSV's cells.
    let seed = doc["episodes"][0]["seed"].as_str().expect("a string seed");
    let csv = stdout(&strider(&["run", "random:sparse", "--episodes", "1", "--body", "disc", "--format", "csv"]));
    assert_eq!(csv.lines().nth(1).unwrap().split(',').nth(3), Some(seed));
    assert!(seed.parse::<u64>().unwrap() > 1 << 53, "the test needs a seed beyond 2^53");
}

#[test]
fn an_empty_shard_has_a_plain_zero_stalled_share() {
    let o = strider(&["run", "random:sparse", "--episodes", "1", "--body", "disc", "--shard", "1/2"]);
    let doc: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(doc["summary"]["episodes"], 0);
    assert!(stdout(&o).contains("\"stalled_share\": 0.0"), "{}", stdout(&o));
}

#[test]
fn a_folder_of_worlds_runs_in_numeric_order_and_warnings_name_the_world() {
    let dir = scratch("folder");
    let names = ["world_100", "world_0010", "world_9", "a10b2", "a2b10"];
    for n in names {
        std::fs::write(dir.join(format!("{n}.txt")), "start 0 0\ngoal 3 0\n").unwrap();
    }
    // A BARN world with no reference path beside it.
    std::fs::write(
        dir.join("world_3.world"),
        "<sdf version='1.6'><world name='default'><model name='unit_cylinder_0'><pose frame=''>-1 6 0 0 0 0</pose>\
         <link name='link'><collision name='collision'><geometry><cylinder><radius>0.075</radius><length>1</length>\
         </cylinder></geometry></collision></link></model></world></sdf>\n",
    )
    .unwrap();
    let o = strider(&["run", s(&dir), "--body", "disc"]);
    let doc: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let order: Vec<&str> =
        doc["episodes"].as_array().unwrap().iter().map(|e| e["scenario"].as_str().unwrap()).collect();
    assert_eq!(order, ["a2b10", "a10b2", "world_3", "world_9", "world_0010", "world_100"]);
    let err = stderr(&o);
    assert!(err.contains(&format!("{}: no path_N.npy", s(&dir.join("world_3.world")))), "{err}");
}

#[test]
fn footstep_errors_name_what_the_map_says() {
    let dir = scratch("footsteps");
    let run = |name: &str, line: &str| {
        let map = dir.join(name);
        std::fs::write(&map, format!("start 0 0\ngoal 3 0\nfootsteps {line}\n")).unwrap();
        strider(&["run", s(&map), "--body", "disc"])
    };
    let o = run("again.txt", "foot_length_m 0 foot_length_m 0.24");
    assert!(o.status.success(), "{}", stderr(&o));
    let o = run("long.txt", "foot_length_m 2");
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("foot_length_m = 2 is out of range"), "{}", stderr(&o));
    let o = run("huge.txt", "step_max_m 1e300");
    assert!(stderr(&o).contains("step_max_m = 1e300 is out of range"), "{}", stderr(&o));
}

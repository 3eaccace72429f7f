//! `strider run --shard I/N` and `strider merge`: the shards of a run, merged, print exactly
//! what the whole run prints, in JSON and in CSV; a missing or repeated shard is an error
//! (`tests/nothing_lost.rs` holds the shards of other runs and cut outputs).

mod common;

use common::strider;

use std::path::PathBuf;
use std::process::Output;

fn stdout(o: &Output) -> String {
    String::from_utf8(o.stdout.clone()).unwrap()
}

/// A scratch directory of this test.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("strider-shard-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Runs `args` whole and in `n` shards written to files; returns the whole output and the files.
fn whole_and_shards(name: &str, args: &[&str], n: usize) -> (Output, Vec<String>) {
    let whole = strider(args);
    let dir = scratch(name);
    let files = (0..n)
        .map(|i| {
            let shard = format!("{i}/{n}");
            let mut a = args.to_vec();
            a.extend(["--shard", &shard]);
            let out = strider(&a);
            assert_eq!(out.status.code(), whole.status.code(), "{}", String::from_utf8_lossy(&out.stderr));
            let file = dir.join(format!("shard_{i}.out"));
            std::fs::write(&file, &out.stdout).unwrap();
            file.display().to_string()
        })
        .collect();
    (whole, files)
}

#[test]
fn merged_json_shards_print_the_whole_run() {
    let args = ["run", "random:semi", "--episodes", "7", "--body", "disc", "--seed", "5"];
    let (whole, mut files) = whole_and_shards("json", &args, 3);
    assert!(whole.status.success(), "{}", String::from_utf8_lossy(&whole.stderr));
    files.reverse(); // any order
    let mut merge = vec!["merge"];
    merge.extend(files.iter().map(String::as_str));
    let merged = strider(&merge);
    assert!(merged.status.success(), "{}", String::from_utf8_lossy(&merged.stderr));
    assert_eq!(stdout(&merged), stdout(&whole));
}

#[test]
fn merged_csv_shards_print_the_whole_run() {
    let args = ["run", "maps/semi_cluttered.rhai", "--episodes", "3", "--format", "csv"];
    let (whole, files) = whole_and_shards("csv", &args, 2);
    let mut merge = vec!["merge"];
    merge.extend(files.iter().map(String::as_str));
    let merged = strider(&merge);
    assert_eq!(merged.status.code(), whole.status.code());
    assert_eq!(stdout(&merged), stdout(&whole));
}

#[test]
fn a_shard_holds_every_nth_episode_numbered_as_in_the_whole_run() {
    let out = strider(&["run", "random:sparse", "--episodes", "5", "--body", "disc", "--shard", "1/2"]);
    let doc: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let episodes: Vec<u64> =
        doc["episodes"].as_array().unwrap().iter().map(|e| e["episode"].as_u64().unwrap()).collect();
    assert_eq!(episodes, [1, 3]);
    let whole = strider(&["run", "random:sparse", "--episodes", "5", "--body", "disc"]);
    let whole: serde_json::Value = serde_json::from_slice(&whole.stdout).unwrap();
    assert_eq!(doc["episodes"][1], whole["episodes"][3]);
}

#[test]
fn missing_or_repeated_shards_and_bad_shards_are_refused() {
    let args = ["run", "random:sparse", "--episodes", "4", "--body", "disc"];
    let (_, files) = whole_and_shards("missing", &args, 2);
    let missing = strider(&["merge", &files[1]]);
    assert_eq!(missing.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&missing.stderr).contains("shard 0/2 of the run is missing"));
    let twice = strider(&["merge", &files[0], &files[1], &files[0]]);
    assert_eq!(twice.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&twice.stderr).contains("give each shard once"));
    for bad in ["2/2", "1/0", "x/3", "1"] {
        let out = strider(&["run", "random:sparse", "--body", "disc", "--shard", bad]);
        assert_eq!(out.status.code(), Some(2), "--shard {bad}");
        assert!(String::from_utf8_lossy(&out.stderr).contains("shard"), "--shard {bad}");
    }
}

#[test]
fn merge_names_the_file_and_line_of_bad_input() {
    let dir = scratch("bad");
    let bad = dir.join("bad.json");
    std::fs::write(&bad, "{\"summary\": {},\n \"episodes\": [ {\"episode\": \"one\"} ]}\n").unwrap();
    let out = strider(&["merge", bad.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains(&format!("{}:2:", bad.display())), "{err}");
    let csv = dir.join("run.csv");
    let json = dir.join("run.json");
    std::fs::write(&csv, "episode,reached,collisions\n0,true,0\n").unwrap();
    std::fs::write(&json, stdout(&strider(&["run", "random:sparse", "--body", "disc"]))).unwrap();
    let mixed = strider(&["merge", json.to_str().unwrap(), csv.to_str().unwrap()]);
    assert_eq!(mixed.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&mixed.stderr).contains("one format"));
}

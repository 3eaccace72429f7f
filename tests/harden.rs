//! Hostile input through the real binary: every case is refused at once with a located error
//! (exit 2), never a stack overflow, a panic, a hang or unbounded memory; a closed stdout
//! pipe is not an error; outputs are written atomically.

mod common;

use common::{refused, stderr, stdout, strider, temp_dir};

use std::io::Read;
use std::path::Path;
use std::process::{Command, Stdio};

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

const NESTING: usize = 10_000;

fn deep_rule(var: &str, term: &str, out: &str, out_term: &str) -> String {
    format!("if {}{var} is {term}{} then {out} is {out_term}", "(".repeat(NESTING), ")".repeat(NESTING))
}

#[test]
fn deeply_nested_rules_are_located_errors_in_every_command() {
    let dir = temp_dir("nesting");
    let fll = dir.join("deep.fll");
    std::fs::write(
        &fll,
        format!(
            "Engine: e\nInputVariable: d\n  range: 0 1\n  term: a Triangle 0 0 1\nOutputVariable: o\n  range: 0 1\n  \
             defuzzifier: Centroid 100\n  aggregation: Maximum\n  term: b Triangle 0 0 1\nRuleBlock: r\n  \
             implication: Minimum\n  rule: {}\n",
            deep_rule("d", "a", "o", "b")
        ),
    )
    .unwrap();
    refused(&strider(&["fuzzy", "eval", s(&fll)]), &["deep.fll:12:76:", "nested deeper than 64"]);
    let out = dir.join("plots");
    refused(&strider(&["fuzzy", "plot", s(&fll), "--out", s(&out)]), &["deep.fll:12:76:"]);
    let rules = dir.join("deep.rhai");
    let nav = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("scripts/simple_nav.rhai")).unwrap();
    let marker = "if distance is near";
    assert!(nav.contains(marker));
    let deep = nav.replacen(marker, &format!("if {}distance is near{}", "(".repeat(NESTING), ")".repeat(NESTING)), 1);
    std::fs::write(&rules, deep).unwrap();
    refused(
        &strider(&["run", "maps/open_field.rhai", "--body", "disc", "--rules", s(&rules)]),
        &["deep.rhai:", "nested deeper than 64"],
    );
}

#[test]
fn endless_input_files_are_refused_at_the_size_limit() {
    refused(&strider(&["fuzzy", "eval", "/dev/zero"]), &["/dev/zero", "input limit of 64 MiB"]);
    refused(&strider(&["fuzzy", "bench", "/dev/zero"]), &["/dev/zero", "input limit"]);
    refused(&strider(&["run", "/dev/zero"]), &["/dev/zero"]);
}

#[test]
fn out_of_range_counts_are_refused_before_any_work() {
    refused(&strider(&["run", "maps/open_field.rhai", "--episodes", "300000000"]), &["--episodes", "1000000"]);
    refused(&strider(&["run", "random:cluttered", "--episodes", "10000000"]), &["--episodes"]);
    refused(&strider(&["run", "maps/open_field.rhai", "--threads", "100000"]), &["--threads"]);
    refused(&strider(&["run", "maps/open_field.rhai", "--threads", "0"]), &["--threads"]);
    refused(&strider(&["fuzzy", "bench", "scripts/simple_nav.rhai", "--check", "10000000"]), &["--check"]);
    let dir = temp_dir("counts");
    refused(&strider(&["db", "build", "--bvh", "assets/db/clips/idle.bvh", "--out", s(&dir), "--k", "0"]), &["--k"]);
    let policy = dir.join("p.policy");
    refused(&strider(&["train", "--episodes", "0", "--out", s(&policy)]), &["--episodes"]);
    assert!(!policy.exists());
}

#[test]
fn training_into_a_missing_directory_fails_before_training() {
    let dir = temp_dir("train_missing");
    let policy = dir.join("no/such/dir/p.policy");
    let o = strider(&["train", "--episodes", "100000000", "--out", s(&policy)]);
    refused(&o, &["p.policy", "cannot write here"]);
    assert!(stdout(&o).is_empty());
}

#[test]
fn a_policy_counted_to_the_limit_cannot_be_resumed() {
    let dir = temp_dir("resume");
    let policy = dir.join("p.policy");
    std::fs::copy(Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/default.policy"), &policy).unwrap();
    // The shipped policy holds 3,000,000 episodes: asking for fewer is an error, not NaN%.
    let o = strider(&["train", "--resume", "--episodes", "1000", "--out", s(&policy)]);
    refused(&o, &["already trained for 3000000 episodes"]);
    assert!(!stdout(&o).contains("NaN"));
}

#[test]
fn far_goals_huge_maps_and_wrong_scenarios_are_refused() {
    let dir = temp_dir("maps");
    let far = dir.join("far.rhai");
    std::fs::write(&far, "let m = world(\"far\");\nm.start(0.0, 0.0, 0.0);\nm.goal(1e9, 0.0, 0.5);\nm\n").unwrap();
    refused(&strider(&["run", s(&far), "--body", "disc"]), &["far.rhai", "farther than 100000 m"]);

    let big = dir.join("big.map");
    let mut text = String::from("type octile\nheight 1000\nwidth 1000\nmap\n");
    for _ in 0..1000 {
        text += &".".repeat(1000);
        text.push('\n');
    }
    std::fs::write(&big, text).unwrap();
    std::fs::write(dir.join("big.map.scen"), "version 1\n0\tbig.map\t1000\t1000\t0\t0\t5\t5\t7\n").unwrap();
    refused(&strider(&["run", s(&big), "--body", "disc"]), &["big.map:4:1:", "262144 cells"]);

    let tiny = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/maps/tiny.map");
    let scen = std::fs::read_to_string(tiny.with_extension("map.scen")).unwrap();
    let other = dir.join("other.scen");
    std::fs::write(&other, scen.replace("tiny.map", "maps/other.map")).unwrap();
    refused(&strider(&["run", s(&tiny), "--scen", s(&other), "--body", "disc"]), &["other.scen:2:", "maps/other.map"]);
    refused(&strider(&["run", s(&tiny), "--scen", "nope.scen"]), &["nope.scen"]);
}

#[test]
fn wrong_kinds_of_files_and_flags_get_clear_messages() {
    let o = strider(&["run", "maps/open_field.rhai", "--rules", "maps/open_field.rhai"]);
    refused(&o, &["open_field.rhai", "a world", "map given as rules"]);
    assert!(!stderr(&o).contains("::"), "{}", stderr(&o));

    let dir = temp_dir("flags");
    let out = dir.join("frames");
    let o = strider(&["render", "maps/open_field.rhai", "--poses", "--body", "disc", "--out", s(&out)]);
    refused(&o, &["--poses", "--body disc"]);
    assert!(!out.exists(), "the episode was run before the flags were checked");

    let script = dir.join("missing_map.rhai");
    std::fs::write(&script, "let m = load_map(\"no/such/map.rhai\");\n").unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_strider"))
        .args(["experiment", s(&script)])
        .env("RUST_BACKTRACE", "1")
        .output()
        .unwrap();
    refused(&o, &["missing_map.rhai:1:", "no/such/map.rhai: cannot read"]);
    assert!(!stderr(&o).contains("Input(") && !stderr(&o).contains("Stack backtrace"), "{}", stderr(&o));

    let batch = dir.join("batch.rhai");
    std::fs::write(
        &batch,
        "print(\"before\");\ndebug(\"log line\");\nrun_batch(\"semi\", 1000000000, 1, default_rules());\n",
    )
    .unwrap();
    let o = strider(&["experiment", s(&batch)]);
    refused(&o, &["batch.rhai:3:", "budget", "log line", "batch.rhai: before"]);
    // The log comes before the error and nothing goes to stdout.
    assert!(stderr(&o).find("before") < stderr(&o).find("budget"), "{}", stderr(&o));
    assert_eq!(stdout(&o), "");
}

#[test]
fn byte_order_marks_are_accepted() {
    let dir = temp_dir("bom");
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let fll = dir.join("tipper.fll");
    let mut bytes = b"\xEF\xBB\xBF".to_vec();
    bytes.extend(std::fs::read(root.join("tests/fixtures/fuzzy/tipper.fll")).unwrap());
    std::fs::write(&fll, bytes).unwrap();
    let csv = dir.join("in.csv");
    std::fs::write(&csv, "\u{feff}food,service\n0,0\n").unwrap();
    let o = strider(&["fuzzy", "eval", s(&fll), "--inputs", s(&csv)]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(stdout(&o).lines().count(), 2);

    let world = dir.join("w.txt");
    let o = strider(&["gen", "--kind", "sparse", "--seed", "3"]);
    assert!(o.status.success());
    let mut text = b"\xEF\xBB\xBF".to_vec();
    text.extend(&o.stdout);
    std::fs::write(&world, text).unwrap();
    let o = strider(&["run", s(&world), "--body", "disc", "--format", "csv"]);
    assert_ne!(o.status.code(), Some(2), "{}", stderr(&o));
}

/// Runs strider with its stdout a pipe whose reading end is closed at once.
fn with_closed_stdout(args: &[&str]) -> (Option<i32>, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_strider"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let mut err = String::new();
    child.stderr.take().unwrap().read_to_string(&mut err).unwrap();
    (child.wait().unwrap().code(), err)
}

#[test]
fn a_closed_pipe_is_not_an_error() {
    for args in [
        &["db", "info"][..],
        &["run", "maps/open_field.rhai", "--body", "disc"],
        &["fuzzy", "eval", "scripts/simple_nav.rhai"],
        &["fuzzy", "bench", "scripts/simple_nav.rhai", "--seconds", "0.1"],
        &["gen", "--kind", "sparse"],
    ] {
        let (code, err) = with_closed_stdout(args);
        assert_eq!(code, Some(0), "{args:?}: {err}");
        assert!(!err.contains("panicked") && !err.contains("error"), "{args:?}: {err}");
    }
}

#[test]
fn db_build_replaces_a_database_whole_or_not_at_all() {
    let dir = temp_dir("db_build");
    let db = dir.join("db");
    let clips = ["walk_straight", "idle", "jog_left15"].map(|c| format!("assets/db/clips/{c}.bvh"));
    let mut args = vec!["db", "build", "--out", s(&db), "--bvh"];
    args.extend(clips.iter().map(String::as_str));
    let o = strider(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    let manifest = std::fs::read(db.join("database.json")).unwrap();
    // A second build that fails half-way (a bad clip after good ones) leaves the first intact.
    let bad = dir.join("bad.bvh");
    std::fs::write(&bad, "HIERARCHY\nROOT x\n{\n").unwrap();
    args.push(s(&bad));
    refused(&strider(&args), &["bad.bvh"]);
    assert_eq!(std::fs::read(db.join("database.json")).unwrap(), manifest);
    let names: Vec<String> =
        std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    assert!(names.iter().all(|n| !n.contains(".tmp")), "{names:?}");
}

#[test]
fn a_far_episode_of_random_worlds_starts_at_once() {
    // Worlds are generated when their episode runs: episode 1,000,000 costs one world.
    let dir = temp_dir("far_episode");
    let o = strider(&[
        "render",
        "random:sparse",
        "--episode",
        "1000000",
        "--every",
        "0",
        "--body",
        "disc",
        "--size",
        "64x64",
        "--out",
        s(&dir),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(dir.join("final.png").exists());
}

#[test]
fn fuzzy_plot_refuses_an_engine_with_thousands_of_inputs() {
    let dir = temp_dir("plot_many");
    let mut text = String::from("Engine: big\n");
    for i in 0..2000 {
        text += &format!("InputVariable: i{i}\n  range: 0 1\n  term: a Triangle 0 0 1\n");
    }
    text += "OutputVariable: o\n  range: 0 1\n  defuzzifier: Centroid 100\n  aggregation: Maximum\n  \
             term: b Triangle 0 0 1\nRuleBlock: r\n  implication: Minimum\n  rule: if i0 is a then o is b\n";
    let fll = dir.join("big.fll");
    std::fs::write(&fll, text).unwrap();
    let out = dir.join("plots");
    refused(&strider(&["fuzzy", "plot", s(&fll), "--out", s(&out)]), &["2001 variables", "256"]);
    assert!(!out.exists());
}

#[test]
fn path_ratio_on_the_open_field_is_at_least_one_for_both_bodies() {
    for body in ["disc", "animated"] {
        let o = strider(&["run", "maps/open_field.rhai", "--body", body, "--format", "csv"]);
        assert!(o.status.success(), "{}", stderr(&o));
        let text = stdout(&o);
        let lines: Vec<&str> = text.lines().collect();
        let header: Vec<&str> = lines[0].split(',').collect();
        let row: Vec<&str> = lines[1].split(',').collect();
        let field = |name: &str| row[header.iter().position(|h| *h == name).unwrap()].parse::<f64>().unwrap();
        let ratio = field("path_ratio");
        assert!(ratio >= 1.0, "{body}: path ratio {ratio}");
        // The optimum ends on the goal circle, 0.5 m short of the goal point.
        assert!((field("optimal_length_m") - (325f64.sqrt() - 0.5)).abs() < 1e-9, "{body}: {text}");
    }
}

//! `strider snapshot`, `strider::snapshot::check` and the Rhai `snapshot` function: goldens
//! written and matched, a changed rule or seed caught with diff pictures and the right first
//! divergence, bit-identical pictures whatever the thread count, and bad input reported with
//! the file at fault.

mod common;

use common::strider_with_env as strider;

use std::path::{Path, PathBuf};
use std::process::Output;

use strider::sim::{Body, Simulation};
use strider::snapshot::{self, Episode, Settings, Spec};

fn manifest() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn text(o: &Output) -> (String, String) {
    (String::from_utf8_lossy(&o.stdout).into_owned(), String::from_utf8_lossy(&o.stderr).into_owned())
}

/// A fresh, empty directory for one test.
fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("snapshot").join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn names(dir: &Path) -> Vec<String> {
    let mut n: Vec<String> =
        std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    n.sort();
    n
}

/// The default rules with the speed engine's "fast" term moved down: the character is asked
/// for less speed on open ground.
fn slower_rules(dir: &Path) -> PathBuf {
    let rules = std::fs::read_to_string(manifest().join("scripts/nav.rhai")).unwrap();
    let old = r#"trap(speed, "fast", 0.9, 1.3, 1.5, 1.5);"#;
    assert!(rules.contains(old), "the default rules changed: pick another term to edit");
    let path = dir.join("slower.rhai");
    std::fs::write(&path, rules.replace(old, r#"trap(speed, "fast", 0.8, 1.2, 1.5, 1.5);"#)).unwrap();
    path
}

/// Steps two episodes side by side and returns the first step (and its time) where the
/// characters are more than 1 mm or 1 mrad apart or play different intervals.
fn first_parting(a: &Episode, b: &Episode) -> (usize, f64) {
    let start = |e: &Episode| {
        let mut sim = Simulation::new(e.scenario.world(), e.params.clone());
        sim.add_agent(e.scenario.tasks[e.task], &e.controller);
        sim
    };
    let (mut sa, mut sb) = (start(a), start(b));
    for step in 0.. {
        let (pa, pb) = (sa.agents[0].body.pose(), sb.agents[0].body.pose());
        let interval = |s: &Simulation| s.agents[0].body.animated().map(|x| x.player().interval());
        let turn = (pa.yaw - pb.yaw).rem_euclid(std::f64::consts::TAU);
        let turn = turn.min(std::f64::consts::TAU - turn);
        if pa.position.distance(pb.position) > 1e-3 || interval(&sa) != interval(&sb) || turn > 1e-3 {
            return (step, sa.time_s);
        }
        assert!(!sa.all_done() && !sb.all_done(), "the runs end together at step {step}");
        sa.step();
        sb.step();
    }
    unreachable!()
}

#[test]
fn update_then_check_passes_and_a_rule_change_fails_with_diffs_and_the_divergence() {
    let dir = scratch("rule_change");
    let golden = dir.join("golden");
    let g = golden.to_str().unwrap();
    let base = ["snapshot", "maps/u_trap.rhai", "--every", "60", "--size", "160x160", "--golden", g];
    let o = strider(&[&base[..], &["--update"]].concat(), &[]);
    assert_eq!(o.status.code(), Some(0), "{:?}", text(&o));
    let files = names(&golden);
    assert!(files.contains(&"frame_000000.png".to_string()) && files.contains(&"final.png".to_string()), "{files:?}");
    assert!(files.contains(&"trajectory.txt".to_string()));
    let o = strider(&base, &[]);
    let (out, err) = text(&o);
    assert_eq!(o.status.code(), Some(0), "{out}{err}");
    assert!(out.contains("match the goldens"), "{out}");

    let rules = slower_rules(&dir);
    let o = strider(&[&base[..], &["--rules", rules.to_str().unwrap()]].concat(), &[]);
    let (out, err) = text(&o);
    assert_eq!(o.status.code(), Some(1), "{out}{err}");
    assert!(err.contains("differ from the goldens"), "{err}");
    let files = names(&golden);
    let diffs: Vec<&String> = files.iter().filter(|n| n.ends_with(".diff.png")).collect();
    assert!(!diffs.is_empty(), "{files:?}");
    for d in &diffs {
        let actual = d.replace(".diff.png", ".actual.png");
        assert!(files.contains(&actual), "{actual} missing: {files:?}");
        assert!(out.contains(&format!("{}: ", d.replace(".diff.png", ".png"))), "{out}");
        let img = image::open(golden.join(d)).unwrap().to_rgba8();
        assert_eq!(img.dimensions(), (160, 160));
        assert!(img.pixels().any(|p| p.0 == snapshot::pixels::CHANGED), "{d} marks nothing");
    }
    assert!(out.contains("pixels changed") && out.contains("largest difference"), "{out}");
    assert!(files.contains(&snapshot::ACTUAL_TRAJECTORY_FILE.to_string()));
    // The reported first divergence is where the two runs really part.
    let spec = Spec::new(manifest().join("maps/u_trap.rhai").to_str().unwrap());
    let (step, time_s) = first_parting(&snapshot::load(&spec).unwrap(), &snapshot::load(&spec.rules(&rules)).unwrap());
    let expected = format!("the trajectories part at t = {time_s:.2} s (step {step})");
    assert!(out.contains(&expected), "expected '{expected}' in\n{out}");

    // Updating to the new behaviour clears the failure pictures and passes again.
    let with_rules = [&base[..], &["--rules", rules.to_str().unwrap()]].concat();
    assert_eq!(strider(&[&with_rules[..], &["--update"]].concat(), &[]).status.code(), Some(0));
    assert!(!names(&golden).iter().any(|n| n.contains(".actual.") || n.contains(".diff.")), "{:?}", names(&golden));
    assert_eq!(strider(&with_rules, &[]).status.code(), Some(0));
}

#[test]
fn a_changed_seed_fails() {
    let dir = scratch("seed");
    let g = dir.to_str().unwrap();
    let args = |seed: &'static str| {
        [
            "snapshot",
            "random:sparse",
            "--seed",
            seed,
            "--body",
            "disc",
            "--every",
            "0",
            "--size",
            "120x120",
            "--golden",
            g,
        ]
    };
    assert_eq!(strider(&[&args("3")[..], &["--update"]].concat(), &[]).status.code(), Some(0));
    assert_eq!(strider(&args("3"), &[]).status.code(), Some(0));
    let o = strider(&args("4"), &[]);
    let (out, err) = text(&o);
    assert_eq!(o.status.code(), Some(1), "{out}{err}");
    assert!(out.contains("final.png: ") && dir.join("final.diff.png").exists(), "{out}");
    assert!(out.contains("the trajectories part at t = 0.00 s (step 0)"), "{out}");
}

#[test]
fn pictures_are_bit_identical_whatever_the_thread_count() {
    let dir = scratch("threads");
    let mut runs = Vec::new();
    for threads in ["1", "3"] {
        let out = dir.join(threads);
        let o = strider(
            &["snapshot", "maps/sparse.rhai", "--every", "50", "--size", "200x150", "--golden", out.to_str().unwrap()],
            &[("RAYON_NUM_THREADS", threads), (snapshot::UPDATE_ENV, "1")],
        );
        assert_eq!(o.status.code(), Some(0), "{:?}", text(&o));
        let files: Vec<(String, Vec<u8>)> =
            names(&out).into_iter().map(|n| (n.clone(), std::fs::read(out.join(&n)).unwrap())).collect();
        assert!(files.len() > 5, "{:?}", names(&out));
        runs.push(files);
    }
    assert!(runs[0] == runs[1], "the two runs wrote different files");
    // Either set of goldens passes a check run with the other thread count.
    let o = strider(
        &[
            "snapshot",
            "maps/sparse.rhai",
            "--every",
            "50",
            "--size",
            "200x150",
            "--golden",
            dir.join("1").to_str().unwrap(),
        ],
        &[("RAYON_NUM_THREADS", "2")],
    );
    assert_eq!(o.status.code(), Some(0), "{:?}", text(&o));
}

#[test]
fn missing_goldens_say_how_to_create_them() {
    let dir = scratch("missing");
    let g = dir.join("none");
    let o = strider(&["snapshot", "maps/open_field.rhai", "--golden", g.to_str().unwrap()], &[]);
    let (out, err) = text(&o);
    assert_eq!(o.status.code(), Some(2), "{out}{err}");
    assert!(err.contains("no snapshot goldens") && err.contains(g.to_str().unwrap()), "{err}");
    assert!(err.contains("strider snapshot maps/open_field.rhai --golden") && err.contains("--update"), "{err}");
    assert!(!g.exists());
}

#[test]
fn bad_input_names_the_file() {
    let dir = scratch("bad");
    let g = dir.to_str().unwrap();
    let o = strider(&["snapshot", "maps/nowhere.rhai", "--golden", g], &[]);
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o).1.contains("maps/nowhere.rhai"), "{:?}", text(&o));

    let args = ["snapshot", "maps/open_field.rhai", "--body", "disc", "--every", "0", "--size", "64x64", "--golden", g];
    assert_eq!(strider(&[&args[..], &["--update"]].concat(), &[]).status.code(), Some(0));
    std::fs::write(dir.join("final.png"), b"not a png").unwrap();
    let o = strider(&args, &[]);
    let err = text(&o).1;
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("final.png") && err.contains("not a readable PNG"), "{err}");

    std::fs::write(dir.join("trajectory.txt"), "# strider snapshot trajectory 1\n0 0.000 zero 0 0 -\n").unwrap();
    let o = strider(&args, &[]);
    let err = text(&o).1;
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("trajectory.txt:2:9"), "{err}");

    let o = strider(&[&args[..], &["--tolerance", "256"]].concat(), &[]);
    assert_eq!(o.status.code(), Some(2));
}

/// `--side` pins the side views `render --side` draws where the map has them (on terrain, the
/// legs' `side.png`), and says so where it has none.
#[test]
fn side_views_are_pinned_where_the_map_has_them() {
    let dir = scratch("side");
    let g = dir.to_str().unwrap();
    let args = |map: &'static str| ["snapshot", map, "--every", "0", "--size", "64x64", "--side", "--golden", g];
    let o = strider(&[&args("maps/open_field.rhai")[..], &["--update"]].concat(), &[]);
    let out = text(&o).0;
    assert_eq!(o.status.code(), Some(0), "{out}");
    assert!(out.contains("no terrain or obstacles the upper body can touch"), "{out}");
    assert_eq!(names(&dir), ["final.png", "trajectory.txt"]);

    let o = strider(&[&args("maps/terrain_stairs.rhai")[..], &["--update"]].concat(), &[]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o).0);
    assert_eq!(names(&dir), ["final.png", "side.png", "trajectory.txt"]);
    let side = image::open(dir.join("side.png")).unwrap();
    assert!(side.width() > 64, "the side view is drawn at its own size");
    let o = strider(&args("maps/terrain_stairs.rhai"), &[]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o).0);
    // Checked without --side, the pinned side view is missing from the run.
    let without: Vec<&str> = args("maps/terrain_stairs.rhai").into_iter().filter(|a| *a != "--side").collect();
    let o = strider(&without, &[]);
    let out = text(&o).0;
    assert_eq!(o.status.code(), Some(1), "{out}");
    assert!(out.contains("side.png: not drawn (a side view: the goldens were written with --side)"), "{out}");
}

#[test]
fn an_update_removes_frames_a_shorter_run_no_longer_draws() {
    let dir = scratch("stale");
    let g = dir.to_str().unwrap();
    let every = |n: &'static str| ["snapshot", "maps/open_field.rhai", "--every", n, "--size", "64x64", "--golden", g];
    assert_eq!(strider(&[&every("40")[..], &["--update"]].concat(), &[]).status.code(), Some(0));
    assert!(dir.join("frame_000040.png").exists());
    std::fs::write(dir.join("notes.md"), "kept").unwrap();
    // Checked with other settings, the frames the goldens have and this run lacks are reported.
    let o = strider(&every("80"), &[]);
    assert_eq!(o.status.code(), Some(1));
    assert!(text(&o).0.contains("frame_000040.png: not drawn"), "{:?}", text(&o));
    let o = strider(&[&every("80")[..], &["--update"]].concat(), &[]);
    assert_eq!(o.status.code(), Some(0));
    assert!(text(&o).0.contains("stale file(s) removed"), "{:?}", text(&o));
    let files = names(&dir);
    assert!(!files.contains(&"frame_000040.png".to_string()) && files.contains(&"frame_000080.png".to_string()));
    assert!(files.contains(&"notes.md".to_string()));
    assert_eq!(strider(&every("80"), &[]).status.code(), Some(0));
}

#[test]
fn the_rust_api_checks_and_reports() {
    let dir = scratch("api");
    let map = manifest().join("maps/u_trap.rhai");
    let settings = Settings { every: 100, size: (96, 96), ..Settings::default() };
    let spec = Spec::new(map.to_str().unwrap()).settings(Settings { update: true, ..settings.clone() });
    let report = snapshot::check(&spec, &dir).unwrap();
    assert!(report.updated && report.passed(), "{report}");
    let spec = spec.settings(settings);
    let report = snapshot::check(&spec, &dir).unwrap();
    assert!(!report.updated && report.passed() && report.divergence.is_none(), "{report}");
    assert!(report.reached);

    let report = snapshot::check(&spec.rules(slower_rules(&dir)), &dir).unwrap();
    assert!(!report.passed(), "{report}");
    assert!(report.failures().count() > 0 && report.divergence.is_some(), "{report}");
    let e = snapshot::check(&Spec::new(map.to_str().unwrap()), dir.join("empty")).unwrap_err();
    assert!(matches!(e, snapshot::Error::MissingGoldens { .. }), "{e}");
}

#[test]
fn experiment_scripts_take_snapshots() {
    let dir = scratch("rhai");
    let golden = dir.join("golden");
    let script = |edit: &str, update: bool| {
        format!(
            r#"
let rules = default_rules();
{edit}
let s = snapshot(load_map("maps/u_trap.rhai"), rules, 1, "{}", #{{ every: 100, width: 96, height: 96, update: {update} }});
print(`passed=${{s.passed}} updated=${{s.updated}} frames=${{s.frames}} divergence=${{s.divergence_s}}`);
"#,
            golden.display()
        )
    };
    let run = |source: String| {
        let path = dir.join("exp.rhai");
        std::fs::write(&path, source).unwrap();
        strider(&["experiment", path.to_str().unwrap()], &[])
    };
    let o = run(script("", true));
    assert_eq!(o.status.code(), Some(0), "{:?}", text(&o));
    assert!(text(&o).1.contains("passed=true updated=true"), "{:?}", text(&o));
    let o = run(script("", false));
    assert_eq!(o.status.code(), Some(0), "{:?}", text(&o));
    assert!(text(&o).1.contains("passed=true updated=false"), "{:?}", text(&o));
    let edit = r#"for e in rules { if e.name() == "speed" { e.variable("speed").set_term("fast", "trapezoid", [0.8, 1.2, 1.5, 1.5]); } }"#;
    let o = run(script(edit, false));
    let (out, err) = text(&o);
    assert_eq!(o.status.code(), Some(1), "{out}{err}");
    assert!(out.is_empty() && err.contains("passed=false") && err.contains("snapshot(s) did not match"), "{out}{err}");
    assert!(err.contains("the trajectories part at t = "), "{err}");
    let o = run(r#"snapshot("maps/u_trap.rhai", default_rules(), 1, "nowhere", #{ colour: 1 });"#.to_string());
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o).1.contains("unknown snapshot option 'colour'"), "{:?}", text(&o));
}

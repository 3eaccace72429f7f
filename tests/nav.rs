//! Navigation end to end: the shipped maps, determinism, and the `run` / `render` / `gen`
//! commands through the real binary.

mod common;

use common::strider;

use strider::experiment::{self, Job};
use strider::maps::generate::{Density, random_world};
use strider::scenario::Scenario;
use strider::script::{Limits, ScriptLog, load_scenario};
use strider::sim::{LayeredController, Simulation, StepParameters};

fn controller() -> LayeredController {
    strider::builtin::controller().expect("built-in rules")
}

fn map(name: &str) -> Scenario {
    let path = format!("{}/maps/{name}.rhai", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap();
    load_scenario(&text, &path, Limits::default(), &ScriptLog::new()).unwrap()
}

#[test]
fn shipped_maps_are_solved_without_collisions() {
    let c = controller();
    for name in ["open_field", "sparse", "semi_cluttered", "cluttered", "u_trap", "corridor_dead_end"] {
        let s = map(name);
        let world = s.world();
        let e = experiment::run_episode(&s, &world, 0, &c, &StepParameters::default(), 0, 0);
        assert!(e.record.reached, "{name}: {:?}", e.record);
        assert_eq!(e.record.collisions, 0, "{name}");
        assert!(e.record.min_clearance_m >= 0.0, "{name}");
        if name == "u_trap" {
            assert!(e.record.path_ratio.unwrap() <= 2.0, "{:?}", e.record);
        }
    }
}

/// Both bodies: the disc and the animated character the papers are about.
fn bodies() -> [(&'static str, StepParameters); 2] {
    let anim = strider::builtin::animation().unwrap();
    let animated = StepParameters {
        animation: Some(strider::sim::animated::AnimationHandle(std::sync::Arc::new(anim))),
        ..StepParameters::default()
    };
    [("disc", StepParameters::default()), ("character", animated)]
}

#[test]
fn buildings_and_mazes_are_found_through_without_a_map() {
    // A chain of rooms whose doors force the long way round, a maze whose loop does not pass
    // the point where the agent first met a wall, and a spiral: reached by both bodies, with
    // room kept from the walls and no wandering.
    let c = controller();
    for (body, params) in bodies() {
        for (name, most_ratio) in [("rooms_chain", 2.0), ("maze_loop", 2.0), ("spiral", 2.0)] {
            let s = map(name);
            let e = experiment::run_episode(&s, &s.world(), 0, &c, &params, 0, 0);
            let r = &e.record;
            assert!(r.reached, "{body} {name}: {r:?}");
            assert_eq!(r.collisions, 0, "{body} {name}");
            assert!(r.min_clearance_m >= 0.02, "{body} {name}: {r:?}");
            assert!(r.path_ratio.unwrap() <= most_ratio, "{body} {name}: {r:?}");
        }
    }
}

#[test]
fn the_default_scenario_reaches_its_goal() {
    // `strider` with no command: the animated character on the built-in map.
    let out = strider(&[]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{text}{}", String::from_utf8_lossy(&out.stderr));
    assert!(text.contains("reached the goal:  yes"), "{text}");
}

#[test]
fn same_seed_same_trajectory_bit_for_bit() {
    let c = controller();
    let run = || {
        let s = random_world(Density::Cluttered, 7);
        let mut sim = Simulation::new(s.world(), StepParameters::default());
        sim.add_agent(s.tasks[0], &c);
        for _ in 0..400 {
            sim.step();
        }
        sim.agents[0].trail.iter().flat_map(|p| [p.x.to_bits(), p.y.to_bits()]).collect::<Vec<u64>>()
    };
    assert_eq!(run(), run());
    // Batches agree whatever the number of threads.
    let jobs: Vec<Job> = (0..4u64)
        .map(|i| Job { scenario: std::sync::Arc::new(random_world(Density::Sparse, i)), task: 0, seed: i })
        .collect();
    let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    let two = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
    let a = one.install(|| experiment::run_batch(&jobs, &c, &StepParameters::default(), &|| {}));
    let b = two.install(|| experiment::run_batch(&jobs, &c, &StepParameters::default(), &|| {}));
    assert_eq!(a, b);
}

#[test]
fn several_agents_share_a_world() {
    let c = controller();
    let s = map("open_field");
    let mut sim = Simulation::new(s.world(), StepParameters::default());
    let mut crossing = s.tasks[0];
    sim.add_agent(crossing, &c);
    crossing.start.position = s.tasks[0].goal;
    crossing.goal = s.tasks[0].start.position;
    sim.add_agent(crossing, &c);
    while !sim.all_done() {
        sim.step();
    }
    for a in &sim.agents {
        assert_eq!(a.metrics.collisions, 0);
        assert_eq!(a.outcome, Some(strider::sim::Outcome::Reached));
    }
}

#[test]
fn run_command_prints_json_and_csv() {
    let o = strider(&["run", "maps/u_trap.rhai", "--format", "json"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // The batch's throughput goes to stderr, never into the data.
    assert!(String::from_utf8_lossy(&o.stderr).contains("agent-steps/s"), "{}", String::from_utf8_lossy(&o.stderr));
    let doc: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let e = &doc["episodes"][0];
    for key in ["reached", "collisions", "time_s", "path_length_m", "optimal_length_m", "min_clearance_m", "seed"] {
        assert!(!e[key].is_null(), "{key} missing in {e}");
    }
    assert_eq!(doc["summary"]["success_rate"], 1.0);
    // Times are whole steps of 0.05 s, written without the rounding error of their sum.
    let t = e["time_s"].as_f64().unwrap();
    assert_eq!(t, (t * 20.0).round() / 20.0, "{e}");
    let a = strider(&["run", "random:sparse", "--episodes", "3", "--seed", "5", "--format", "csv"]);
    let b = strider(&["run", "random:sparse", "--episodes", "3", "--seed", "5", "--format", "csv", "--threads", "1"]);
    assert_eq!(a.stdout, b.stdout);
    assert_eq!(String::from_utf8_lossy(&a.stdout).lines().count(), 4);
}

#[test]
fn gen_prints_a_world_that_reads_back() {
    let o = strider(&["gen", "--density", "semi", "--seed", "3"]);
    assert!(o.status.success());
    let text = String::from_utf8(o.stdout).unwrap();
    let s = strider::maps::text::parse(&text, "gen.txt").unwrap();
    let body = |t: &str| t.lines().skip(1).collect::<Vec<_>>().join("\n");
    assert_eq!(body(&strider::maps::text::write(&s)), body(&text));
    assert_eq!(strider(&["gen", "--density", "thick"]).status.code(), Some(2));
}

#[test]
fn render_writes_frames() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("render_frames");
    let _ = std::fs::remove_dir_all(&dir);
    let o = strider(&[
        "render",
        "maps/open_field.rhai",
        "--out",
        dir.to_str().unwrap(),
        "--every",
        "100",
        "--size",
        "200x150",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let frames = std::fs::read_dir(&dir).unwrap().count();
    assert!(frames >= 3, "{frames}");
    let img = image::open(dir.join("final.png")).unwrap();
    assert_eq!((img.width(), img.height()), (200, 150));
}

/// `render --gif` writes the whole episode as one looping animation: a frame every `--every`
/// steps and the final one held, all the same size and showing the same region.
#[test]
fn render_writes_an_animated_gif() {
    use image::AnimationDecoder;
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("render_gif");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let gif = dir.join("u_trap.gif");
    let o = strider(&["render", "maps/u_trap.rhai", "--gif", gif.to_str().unwrap(), "--size", "320x320"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let file = std::io::BufReader::new(std::fs::File::open(&gif).unwrap());
    let frames = image::codecs::gif::GifDecoder::new(file).unwrap().into_frames().collect_frames().unwrap();
    // 16.6 s at 20 steps of 0.05 s a frame: 17 frames and the final one.
    assert_eq!(frames.len(), 18);
    assert!(frames.iter().all(|f| f.buffer().dimensions() == (320, 320)));
    assert_eq!(frames[0].delay().numer_denom_ms(), (250, 1));
    assert_eq!(frames[17].delay().numer_denom_ms(), (2000, 1));
    assert_ne!(frames[0].buffer(), frames[17].buffer());
    frames[17].buffer().save(dir.join("last.png")).unwrap();
    // Only a GIF asked for: no frame directory needed; a GIF of one frame is refused.
    let o = strider(&["render", "maps/u_trap.rhai", "--gif", gif.to_str().unwrap(), "--every", "0"]);
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn bad_maps_and_rules_are_located_errors() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("bad_maps");
    std::fs::create_dir_all(&dir).unwrap();
    let over = dir.join("over_start.rhai");
    std::fs::write(
        &over,
        "let m = world(\"x\");\nm.start(0.0, 0.0, 0.0);\nm.goal(5.0, 0.0, 0.5);\nm.cylinder(0.0, 0.0, 1.0);\nm\n",
    )
    .unwrap();
    let o = strider(&["run", over.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        String::from_utf8_lossy(&o.stderr).contains("start (0, 0) is inside obstacle 1"),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let nan = dir.join("nan.txt");
    std::fs::write(&nan, "start 0 0\ngoal nan 1\n").unwrap();
    let o = strider(&["run", nan.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("nan.txt:2:"), "{}", String::from_utf8_lossy(&o.stderr));
    let empty = dir.join("empty.txt");
    std::fs::write(&empty, "# nothing\n").unwrap();
    assert_eq!(strider(&["run", empty.to_str().unwrap()]).status.code(), Some(2));
    let syntax = dir.join("syntax.rhai");
    std::fs::write(&syntax, "let m = world(\"x\");\nm.box(1, 2, 3;\nm\n").unwrap();
    let o = strider(&["run", syntax.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("syntax.rhai:2:"), "{}", String::from_utf8_lossy(&o.stderr));
    let o = strider(&["run", "maps/open_field.rhai", "--rules", "scripts/simple_nav.rhai"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("does not provide"), "{}", String::from_utf8_lossy(&o.stderr));
}

#[test]
fn experiment_scripts_compare_rule_sets() {
    let o = strider(&["experiment", "scripts/compare_rules.rhai"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(o.stdout.is_empty(), "print goes to the log, not stdout");
    let text = String::from_utf8_lossy(&o.stderr);
    // The script prints its tables with `table`: aligned columns, rounded numbers.
    assert!(text.contains("rules on u_trap  reached  time (s)  path ratio"), "{text}");
    assert!(text.contains("cautious         true"), "{text}");
    let rows: Vec<&str> = text.lines().skip_while(|l| !l.contains("median ratio")).take(3).collect();
    assert_eq!(rows.len(), 3, "{text}");
    assert!(rows.iter().all(|r| r.chars().count() == rows[0].chars().count()), "the columns align: {text}");
    assert!(
        rows[1..].iter().all(|r| r
            .split_whitespace()
            .skip(2)
            .take(3)
            .all(|x| x.split('.').nth(1).is_some_and(|d| d.len() == 3))),
        "{text}"
    );
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("experiments");
    std::fs::create_dir_all(&dir).unwrap();
    let bad = dir.join("bad.rhai");
    std::fs::write(&bad, "let r = default_rules();\nlet s = run_batch(\"thick\", 3, 1, r);\n").unwrap();
    let o = strider(&["experiment", bad.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("bad.rhai:2:"), "{}", String::from_utf8_lossy(&o.stderr));
}

/// A MovingAI map of 24 × 24 cells with walls and posts, and six scenario lines across it,
/// written to a scratch folder; returns the map's path.
fn movingai_map(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("strider-nav-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut rows = Vec::new();
    for y in 0..24 {
        let row: String = (0..24)
            .map(|x| {
                let wall = (x == 8 && y < 18) || (x == 16 && y > 5) || (y == 12 && (3..6).contains(&x));
                let post = x % 5 == 2 && y % 7 == 3;
                if wall || post { '@' } else { '.' }
            })
            .collect();
        rows.push(row);
    }
    let map = dir.join(format!("{name}.map"));
    std::fs::write(&map, format!("type octile\nheight 24\nwidth 24\nmap\n{}\n", rows.join("\n"))).unwrap();
    let lines = [(1, 1, 22, 22), (22, 1, 1, 22), (4, 20, 20, 4), (12, 2, 12, 21), (1, 12, 22, 12), (10, 10, 13, 14)];
    let mut scen = String::from("version 1\n");
    for (sx, sy, gx, gy) in lines {
        scen.push_str(&format!("0\t{name}.map\t24\t24\t{sx}\t{sy}\t{gx}\t{gy}\t1\n"));
    }
    std::fs::write(dir.join(format!("{name}.map.scen")), scen).unwrap();
    map
}

fn json(o: &std::process::Output) -> serde_json::Value {
    serde_json::from_slice(&o.stdout).unwrap_or_else(|e| panic!("{e}: {}", String::from_utf8_lossy(&o.stderr)))
}

#[test]
fn optimum_off_leaves_the_optimum_and_nothing_else_out() {
    let map = movingai_map("off");
    let map = map.to_str().unwrap();
    let on = strider(&["run", map, "--body", "disc"]);
    let off = strider(&["run", map, "--body", "disc", "--optimum", "off"]);
    assert_eq!(on.status.code(), off.status.code());
    let (on, off) = (json(&on), json(&off));
    let (a, b) = (on["episodes"].as_array().unwrap(), off["episodes"].as_array().unwrap());
    assert_eq!(a.len(), 6);
    assert!(a.iter().all(|e| e["optimal_length_m"].is_f64()));
    assert!(a.iter().any(|e| e["path_ratio"].is_f64()));
    for (x, y) in a.iter().zip(b) {
        let (mut x, mut y) = (x.as_object().unwrap().clone(), y.as_object().unwrap().clone());
        for key in ["optimal_length_m", "path_ratio"] {
            assert!(y.remove(key).is_some_and(|v| v.is_null()), "{key}: {y:?}");
            x.remove(key);
        }
        assert_eq!(x, y);
    }
    let (mut s, mut t) = (on["summary"].as_object().unwrap().clone(), off["summary"].as_object().unwrap().clone());
    for key in ["median_path_ratio", "p90_path_ratio"] {
        assert!(s.remove(key).is_some_and(|v| v.is_f64()));
        assert!(t.remove(key).is_some_and(|v| v.is_null()));
    }
    assert_eq!(s, t);
    // In CSV, empty cells.
    let csv = strider(&["run", map, "--body", "disc", "--optimum", "off", "--format", "csv", "--episodes", "1"]);
    let text = String::from_utf8(csv.stdout).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let row: Vec<&str> = lines.next().unwrap().split(',').collect();
    for key in ["optimal_length_m", "path_ratio"] {
        let at = header.iter().position(|h| *h == key).unwrap();
        assert_eq!(row[at], "", "{key}");
    }
    let bad = strider(&["run", map, "--optimum", "maybe"]);
    assert_eq!(bad.status.code(), Some(2));
}

#[test]
fn the_lines_of_one_map_give_what_each_gives_alone() {
    // The lines of a map share its world and planner (and what earlier searches found of its
    // graph): each line run alone gives the same record.
    let map = movingai_map("alone");
    let map = map.to_str().unwrap();
    let whole = json(&strider(&["run", map, "--body", "disc", "--threads", "1"]));
    let whole = whole["episodes"].as_array().unwrap();
    for i in [5, 2, 0] {
        let shard = format!("{i}/6");
        let one = json(&strider(&["run", map, "--body", "disc", "--shard", &shard]));
        assert_eq!(one["episodes"][0], whole[i], "line {i}");
    }
}

#[test]
fn a_batch_reports_steps_as_they_are_taken_and_each_episode() {
    use experiment::Progress;
    use std::sync::Mutex;
    let c = controller();
    // 120 m with a box half way: close to 1,900 steps.
    let s = strider::maps::text::parse("start 0 0 0\ngoal 120 0\nbox 60 0 2 2 0\n", "long").unwrap();
    let s = std::sync::Arc::new(s);
    let make = |_| Job { scenario: s.clone(), task: 0, seed: 1 };
    let heard: Mutex<Vec<Progress>> = Mutex::new(Vec::new());
    let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    let records = one.install(|| {
        experiment::run_episodes_each(
            &[0, 1],
            &make,
            &c,
            &StepParameters::default(),
            experiment::Optimum::Off,
            &|p| heard.lock().unwrap().push(p),
            &|_| {},
        )
    });
    let heard = heard.into_inner().unwrap();
    let steps: u64 = records.iter().map(|r| u64::from(r.steps)).sum();
    assert!(records.iter().all(|r| r.steps > experiment::STEPS_PER_REPORT), "{records:?}");
    assert!(records.iter().all(|r| r.optimal_length_m.is_none() && r.path_ratio.is_none()));
    let reported: u64 = heard.iter().map(|p| if let Progress::Steps(n) = p { *n } else { 0 }).sum();
    assert_eq!(reported, steps);
    // Each episode's steps are heard in reports of at most STEPS_PER_REPORT, before its end.
    let ends: Vec<usize> = (0..heard.len()).filter(|&i| heard[i] == Progress::Episode).collect();
    assert_eq!(ends.len(), 2);
    assert!(ends[0] >= 2 && ends[1] >= ends[0] + 3, "{heard:?}");
    assert!(heard.iter().all(|p| !matches!(p, Progress::Steps(n) if *n > u64::from(experiment::STEPS_PER_REPORT))));
    // Without a terminal, `strider run` draws no progress: stderr holds the rate line only.
    let out = strider(&["run", "maps/u_trap.rhai", "--body", "disc"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("agent-steps/s") && !err.contains('\u{1b}'), "{err}");
}

/// A failed episode says on stderr which it was (and in a folder run, which world) and why:
/// here a disc walled in, which times out; the clean world of the same folder is not named.
#[test]
fn a_failed_episode_says_why_on_stderr() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("failure_reasons");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("a_open.txt"), "start 0 0\ngoal 3 0\n").unwrap();
    let walls = "box 0 1.2 3 0.2\nbox 0 -1.2 3 0.2\nbox 1.4 0 0.2 2.6\nbox -1.4 0 0.2 2.6\n";
    std::fs::write(dir.join("b_walled.txt"), format!("start 0 0\ngoal 4 0\ntime_limit 3\n{walls}")).unwrap();
    let o = strider(&["run", dir.to_str().unwrap(), "--body", "disc"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.contains("episode 1 (b_walled): timed out after 3.05 s (limit 3.00 s), ")
            && err.contains(" m from the goal circle"),
        "{err}"
    );
    assert!(!err.contains("a_open"), "{err}");
    assert!(err.contains("failed: 1 of 2 episodes"), "{err}");
}

/// The first step that ends overlapping something is kept, and the episode's failure names
/// it: when, where, how deep and into which obstacle.
#[test]
fn a_collision_is_described_by_its_first_contact() {
    use glam::DVec2;
    use strider::sim::failure::Touched;
    use strider::world::{Obstacle, ObstacleShape, Pose, Task, World};
    let wall = ObstacleShape::Box { center: DVec2::new(0.2, 0.0), width: 0.2, height: 2.0, yaw: 0.0 };
    let world = World::new(vec![Obstacle::build(wall, 0.0, 2.0).unwrap()]);
    let mut sim = Simulation::new(world, StepParameters::default());
    // Started overlapping the wall (a scenario would refuse this; the simulation measures it).
    let task = Task::new(Pose { position: DVec2::ZERO, yaw: std::f64::consts::PI }, DVec2::new(-5.0, 0.0));
    sim.add_agent(task, &controller());
    sim.step();
    let contact = sim.agents[0].metrics.first_collision.expect("the first step overlaps the wall");
    assert_eq!(contact.with, Touched::Obstacle(0));
    assert!((contact.time_s - 0.05).abs() < 1e-12 && contact.depth_m > 0.0, "{contact:?}");
    while !sim.all_done() {
        sim.step();
    }
    let why = sim.failure(0).expect("a collision is a failure");
    assert!(
        why.contains("first at 0.05 s") && why.contains("into the obstacle at (0.20, 0.00), 0.20 × 2.00 m"),
        "{why}"
    );
}

/// Every command's help speaks of the papers by name (no internal numbers), `run --help` names
/// every kind of world it takes, `tui --help` lists the keys and `experiment --help` the
/// functions a script can call.
#[test]
fn help_names_what_a_user_can_give() {
    let commands: &[&[&str]] = &[
        &[],
        &["run"],
        &["merge"],
        &["gen"],
        &["render"],
        &["snapshot"],
        &["experiment"],
        &["tui"],
        &["db", "build"],
        &["db", "info"],
        &["db", "track"],
        &["db", "export"],
        &["train"],
        &["reproduce", "table1"],
        &["steps"],
        &["fuzzy", "eval"],
        &["fuzzy", "export"],
        &["fuzzy", "plot"],
        &["fuzzy", "bench"],
    ];
    let help = |command: &[&str]| {
        let mut args = command.to_vec();
        args.push("--help");
        let o = strider(&args);
        assert!(o.status.success(), "{args:?}");
        String::from_utf8_lossy(&o.stdout).into_owned()
    };
    for command in commands {
        let text = help(command).to_lowercase();
        assert!(!text.contains("seed 00") && !text.contains("seed paper"), "{command:?}: {text}");
    }
    let run = help(&["run"]);
    for form in ["world_N.world", "path_files/", "folder of worlds", "movingai:NAME", "barn:NAME", "$STRIDER_DATA"] {
        assert!(run.contains(form), "run --help does not name {form}: {run}");
    }
    let tui = help(&["tui"]);
    assert!(tui.contains("random:KIND") && tui.contains("Keys") && tui.contains("Ctrl-C"), "{tui}");
    let experiment = help(&["experiment"]);
    for f in ["load_map(", "run_episode(", "run_batch(", "snapshot(", "table("] {
        assert!(experiment.contains(f), "{experiment}");
    }
}

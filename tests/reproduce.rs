//! Seed 000 Table 1 reproduced: the pure-RL baseline and `strider reproduce table1`.

mod common;

use common::strider;

use glam::DVec2;
use strider::baseline::{Ending, PureRl, PureRlParams};
use strider::maps::generate::Density;
use strider::world::{Obstacle, ObstacleShape, Pose, Task, World};

#[test]
fn the_pure_rl_state_grows_with_density_as_in_table_1() {
    let counts: Vec<usize> = Density::ALL.iter().map(|&d| PureRlParams::for_density(d).state_parameters()).collect();
    assert_eq!(counts, vec![4, 10, 16]);
    let sizes: Vec<f64> = Density::ALL.iter().map(|&d| PureRlParams::for_density(d).state_cells(100)).collect();
    assert!(sizes[0] < sizes[1] && sizes[1] < sizes[2], "{sizes:?}");
}

/// Success of greedy play on `tasks`.
fn success(rl: &mut PureRl, db: &strider::anim::Database, world: &World, tasks: &[Task]) -> f64 {
    let reached = tasks
        .iter()
        .enumerate()
        .filter(|(i, t)| rl.episode(db, world, t, false, 9, *i as u64).0 == Ending::Reached)
        .count();
    reached as f64 / tasks.len() as f64
}

#[test]
fn the_pure_rl_planner_learns_deterministically_to_reach_goals_past_an_obstacle() {
    let db = strider::builtin::database().expect("built-in database");
    let wall = ObstacleShape::Box { center: DVec2::new(5.0, 5.0), width: 0.6, height: 3.0, yaw: 0.0 };
    let world = World::new(vec![Obstacle::build(wall, 0.0, 2.0).unwrap()]);
    let area = (DVec2::new(0.0, 0.0), DVec2::new(10.0, 10.0));
    let held_out: Vec<Task> = (0..30).map(|i| strider::reproduce::random_task(&world, area, 0.3, 5, i, 2)).collect();
    let params = PureRlParams { obstacles: 1, ..PureRlParams::default() };
    let train = |episodes: u64| {
        let mut rl = PureRl::new(params);
        for e in 0..episodes {
            let task = strider::reproduce::random_task(&world, area, 0.3, 5, e, 1);
            rl.episode(&db, &world, &task, true, 5, e);
        }
        rl
    };
    let mut untrained = PureRl::new(params);
    let before = success(&mut untrained, &db, &world, &held_out);
    let mut a = train(6000);
    let mut b = train(6000);
    assert_eq!(a.stored_entries(), b.stored_entries());
    let after = success(&mut a, &db, &world, &held_out);
    assert_eq!(after, success(&mut b, &db, &world, &held_out), "same seed, same policy");
    assert!(after > before + 0.2 && after >= 0.6, "success {before} -> {after}");
    // A start facing a wall it is about to touch, for the record of endings.
    let t = Task::new(Pose { position: DVec2::new(4.3, 5.0), yaw: 0.0 }, DVec2::new(9.0, 5.0));
    assert!(matches!(a.episode(&db, &world, &t, false, 1, 0).0, Ending::Reached | Ending::Collided | Ending::TimedOut));
}

#[test]
fn reproduce_table1_prints_the_extended_table_as_json() {
    let out = strider(&[
        "reproduce",
        "table1",
        "--format",
        "json",
        "--max-episodes",
        "3000",
        "--held-out",
        "4",
        "--unseen",
        "2",
        "--fuzzy-episodes",
        "3000",
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    let envs = v["environments"].as_array().expect("environments");
    let names: Vec<&str> = envs.iter().map(|e| e["name"].as_str().unwrap()).collect();
    assert_eq!(names, vec!["sparse", "semi_cluttered", "cluttered"]);
    let mut pure = Vec::new();
    for e in envs {
        for planner in ["pure_rl", "fuzzy_rl"] {
            let p = &e[planner];
            for key in [
                "state_parameters",
                "table_entries",
                "training_episodes",
                "training_s",
                "success_rate",
                "success_rate_unseen",
            ] {
                assert!(p[key].is_number(), "{planner}.{key} in {p}");
            }
            let rate = p["success_rate"].as_f64().unwrap();
            assert!((0.0..=1.0).contains(&rate));
        }
        assert_eq!(e["fuzzy_rl"]["state_parameters"], 3);
        assert_eq!(e["fuzzy_rl"]["training_episodes"], 3000, "one policy, trained once");
        pure.push(e["pure_rl"]["state_parameters"].as_u64().unwrap());
    }
    assert_eq!(pure, vec![4, 10, 16]);
    // Bad options are refused before any work.
    let bad = strider(&["reproduce", "table1", "--held-out", "0"]);
    assert_eq!(bad.status.code(), Some(2));
}

#[test]
fn the_experiment_api_runs_table_1_with_environments_of_its_own() {
    let dir = std::env::temp_dir().join(format!("strider-table1-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let script = dir.join("t1.rhai");
    std::fs::write(
        &script,
        r#"
let envs = [#{ name: "mine", map: load_map("maps/sparse.rhai"), density: "sparse", obstacles: 1 }];
let t = reproduce_table1(envs, #{ seed: 3, held_out: 3, unseen: 1, max_episodes: 1000, fuzzy_episodes: 1000 }, default_rules());
print(`${t.environments[0].name} ${t.environments[0].pure_rl.state_parameters} ${t.environments[0].fuzzy_rl.state_parameters}`);
"#,
    )
    .unwrap();
    let out = strider(&["experiment", script.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let all = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    assert!(all.contains("mine 7 3"), "{all}");
    let _ = std::fs::remove_dir_all(&dir);
}

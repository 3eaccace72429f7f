//! The seeded world generators of every kind (open clutter, buildings, mazes, grid maps) and
//! the hand-made maze-like maps: solvable for the 0.3 m disc, deterministic, sizes measured on
//! the built geometry, and reachable from every front door (`run`, `gen`, `render`, the live
//! view, experiment scripts).

mod common;

use common::strider;

use std::time::Instant;

use glam::DVec2;
use strider::maps::building::{self, DOOR_WIDTH_M};
use strider::maps::generate::connected;
use strider::maps::grid::{self, GRID_CELLS};
use strider::maps::kind::{self, WorldKind};
use strider::maps::maze::{self, CORRIDOR_WIDTH_M};
use strider::maps::text;
use strider::scenario::Scenario;
use strider::script::{Limits, ScriptLog, load_scenario};
use strider::tui::MapSpec;
use strider::world::World;

const SEEDS: u64 = 200;

fn map(name: &str) -> Scenario {
    let path = format!("{}/maps/{name}.rhai", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap();
    load_scenario(&text, &path, Limits::default(), &ScriptLog::new()).unwrap()
}

/// Whether every task's start and goal are joined for the agent's disc, checked by the flood
/// fill over the bounding box of the obstacles, starts and goals grown by a metre.
fn joined(s: &Scenario) -> bool {
    let w = s.world();
    let b = w.bounds().unwrap();
    let ends = s.tasks.iter().flat_map(|t| [t.start.position, t.goal]);
    let (min, max) = ends.fold((b.min, b.max), |(lo, hi), p| (lo.min(p), hi.max(p)));
    let (min, max) = (min - DVec2::ONE, max + DVec2::ONE);
    s.tasks.iter().all(|t| connected(&w, min, max, t.start.position, t.goal, s.agent_radius))
}

/// Free width of the gap through `p` along the unit direction `dir`: the distances to the
/// first obstacle both ways.
fn free_width(w: &World, p: DVec2, dir: DVec2, max: f64) -> f64 {
    let mut scratch = Vec::new();
    let a = w.ray_cast(p, dir, max, &mut scratch).unwrap_or(max);
    let b = w.ray_cast(p, -dir, max, &mut scratch).unwrap_or(max);
    a + b
}

#[test]
fn every_kind_is_solvable_and_valid() {
    for k in WorldKind::ALL {
        let mut scratch = Vec::new();
        for seed in 0..SEEDS {
            let s = kind::generate(k, seed);
            s.validate().unwrap_or_else(|e| panic!("{k} seed {seed}: {e}"));
            assert_eq!(s.tasks.len(), 1);
            assert_eq!(s.agent_radius, 0.3);
            assert!(joined(&s), "{k} seed {seed}: start and goal not joined for the disc");
            let w = s.world();
            let t = s.tasks[0];
            for p in [t.start.position, t.goal] {
                assert!(w.clearance(p, 1.0, &mut scratch) >= s.agent_radius, "{k} seed {seed}: {p} too near");
            }
            // Closed worlds: no ray from the start leaves the walls.
            for i in 0..16 {
                let a = i as f64 * std::f64::consts::TAU / 16.0;
                let dir = DVec2::new(a.cos(), a.sin());
                assert!(w.ray_cast(t.start.position, dir, 100.0, &mut scratch).is_some(), "{k} seed {seed}: open");
            }
        }
    }
}

#[test]
fn generators_are_deterministic() {
    for k in WorldKind::ALL {
        for seed in [0, 1, 42, u64::MAX] {
            let a = text::write(&kind::generate(k, seed));
            assert_eq!(a, text::write(&kind::generate(k, seed)), "{k} seed {seed}");
            let other = text::write(&kind::generate(k, seed.wrapping_add(1)));
            assert_ne!(a, other, "{k}: seeds {seed} and the next give the same world");
            assert_eq!(kind::generate(k, seed).name, format!("random-{}-{seed}", k.name()));
        }
    }
}

#[test]
fn written_worlds_read_back() {
    for k in [WorldKind::Rooms, WorldKind::Maze, WorldKind::Grid] {
        let s = kind::generate(k, 5);
        let back = text::parse(&text::write(&s), "w.txt").unwrap();
        assert_eq!(back.obstacles, s.obstacles, "{k}");
        assert_eq!(back.tasks, s.tasks, "{k}");
    }
}

#[test]
fn rooms_doors_measure_within_range() {
    let mut doors = 0;
    let mut rooms_apart = Vec::new();
    for seed in 0..SEEDS {
        let b = building::building(seed);
        let s = b.scenario("b");
        let w = s.world();
        let mut scratch = Vec::new();
        for d in &b.doors {
            let along = if d.along_y { DVec2::Y } else { DVec2::X };
            let across = along.perp();
            // The opening along the wall's centre line, and on both of its faces.
            for off in [0.0, 0.49, -0.49] {
                let p = d.center + across * off * b.wall_thickness;
                let width = free_width(&w, p, along, 10.0);
                assert!(
                    width >= DOOR_WIDTH_M.0 - 1e-9 && width <= DOOR_WIDTH_M.1 + 1e-9,
                    "seed {seed}: door at {} is {width} m wide",
                    d.center
                );
                assert!((width - d.width).abs() < 1e-9);
            }
            // The wall really is there beside the door, one thickness deep.
            let beside = d.center + along * (0.5 * d.width + 0.1);
            let mut near_face =
                |side: f64| w.ray_cast(beside + across * side, -across * side, 2.0, &mut scratch).unwrap_or(2.0);
            let depth = 2.0 - near_face(1.0) - near_face(-1.0);
            assert!((depth - b.wall_thickness).abs() < 1e-9, "seed {seed}: wall {depth} m thick");
            assert!((0.15..=0.25).contains(&depth));
            doors += 1;
        }
        // Start and goal keep 0.8 m from every wall and lie several doors apart.
        for p in [b.start.position, b.goal] {
            assert!(w.clearance(p, 1.0, &mut scratch) >= building::WALL_CLEARANCE_M - 1e-9, "seed {seed}");
        }
        assert_ne!(b.room_at(b.start.position), b.room_at(b.goal));
        rooms_apart.push(b.route.len() - 1);
    }
    rooms_apart.sort();
    println!(
        "{doors} doors measured; start and goal rooms apart: min {}, median {}, max {} doors",
        rooms_apart[0],
        rooms_apart[rooms_apart.len() / 2],
        rooms_apart[rooms_apart.len() - 1]
    );
    assert!(rooms_apart[0] >= 3, "start and goal only {} doors apart", rooms_apart[0]);
    assert!(rooms_apart[rooms_apart.len() / 2] >= 6, "median {} doors apart", rooms_apart[rooms_apart.len() / 2]);
}

#[test]
fn maze_corridors_measure_within_range() {
    for seed in 0..SEEDS {
        let m = maze::maze(seed);
        let s = m.scenario("m");
        let w = s.world();
        let (c, half) = (m.cols, 0.5 * m.corridor_width);
        let mut scratch = Vec::new();
        for k in 0..c * m.rows {
            let (i, j) = (k % c, k / c);
            let p = m.cell_center(k);
            let west = i == 0 || !m.open_east[k - 1];
            let east = i + 1 == c || !m.open_east[k];
            let south = j == 0 || !m.open_north[k - c];
            let north = j + 1 == m.rows || !m.open_north[k];
            for (dir, wall) in [(DVec2::NEG_X, west), (DVec2::X, east), (DVec2::NEG_Y, south), (DVec2::Y, north)] {
                let hit = w.ray_cast(p, dir, 50.0, &mut scratch).unwrap_or(50.0);
                if wall {
                    assert!((hit - half).abs() < 1e-9, "seed {seed} cell {k}: wall at {hit} m, corridor {half} × 2");
                } else {
                    assert!(hit > half + m.wall_thickness + 1.0, "seed {seed} cell {k}: opening blocked at {hit} m");
                }
            }
            for (dir, both) in [(DVec2::X, west && east), (DVec2::Y, south && north)] {
                if both {
                    let width = free_width(&w, p, dir, 50.0);
                    assert!(
                        width >= CORRIDOR_WIDTH_M.0 - 1e-9 && width <= CORRIDOR_WIDTH_M.1 + 1e-9,
                        "seed {seed} cell {k}: corridor {width} m wide"
                    );
                }
            }
            // Nowhere narrower than the corridor: a disc of the corridor width fits at every
            // cell centre.
            assert!(w.clearance(p, 5.0, &mut scratch) >= half - 1e-9, "seed {seed} cell {k}");
        }
        assert!((0.15..=0.25).contains(&m.wall_thickness));
        // Far apart: at least as many moves as the maze is wide.
        assert!(m.route.len() > c, "seed {seed}: {} moves", m.route.len() - 1);
    }
}

#[test]
fn grid_connectivity_matches_the_disc() {
    for seed in 0..50 {
        let g = grid::random_grid(seed);
        let s = g.scenario("g");
        let w = s.world();
        let label = grid::free_components(&g.grid);
        let free: Vec<usize> = (0..label.len()).filter(|&k| label[k].is_some()).collect();
        let cell = |k: usize| (k % GRID_CELLS, k / GRID_CELLS);
        let start = g.grid.cell_center(g.start.0, g.start.1);
        let side = GRID_CELLS as f64;
        // Joined cells (by shared sides) are exactly the cells the disc can reach.
        for &k in free.iter().step_by(17) {
            let (x, y) = cell(k);
            let same = label[k] == label[g.start.1 * GRID_CELLS + g.start.0];
            let reach = connected(&w, DVec2::ZERO, DVec2::splat(side), start, g.grid.cell_center(x, y), 0.3);
            assert_eq!(same, reach, "seed {seed}: cell ({x}, {y})");
        }
        // Every blocked cell is covered by an obstacle, every free one is not.
        let mut scratch = Vec::new();
        for (k, l) in label.iter().enumerate() {
            let (x, y) = cell(k);
            let inside = w.clearance(g.grid.cell_center(x, y), 0.4, &mut scratch) == 0.0;
            assert_eq!(inside, l.is_none(), "seed {seed}: cell ({x}, {y})");
        }
        let share = g.grid.blocked_count() as f64 / (side * side);
        assert!((0.0975..=0.2525).contains(&share), "seed {seed}: {share} blocked");
        assert!(start.distance(g.grid.cell_center(g.goal.0, g.goal.1)) >= 8.0, "seed {seed}: too near");
    }
}

#[test]
fn generation_is_fast() {
    let bound_ms = if cfg!(debug_assertions) { 500.0 } else { 50.0 };
    for k in WorldKind::ALL {
        let n = 20;
        let t = Instant::now();
        for seed in 0..n {
            std::hint::black_box(kind::generate(k, seed));
        }
        let ms = t.elapsed().as_secs_f64() * 1000.0 / n as f64;
        println!("{k}: {ms:.2} ms per world");
        assert!(ms < bound_ms, "{k}: {ms:.1} ms per world");
    }
}

#[test]
fn rooms_chain_goes_the_long_way() {
    let s = map("rooms_chain");
    assert!(joined(&s));
    let t = s.tasks[0];
    let w = s.world();
    let mut scratch = Vec::new();
    // One wall between start and goal, 4 m apart.
    let gap = t.goal - t.start.position;
    let hit = w.ray_cast(t.start.position, gap.normalize(), gap.length(), &mut scratch);
    assert!(hit.is_some_and(|h| h < gap.length()));
    let path = strider::plan::shortest_path(&w, t.start.position, t.goal, s.agent_radius).unwrap();
    println!("rooms_chain: shortest way {:.2} m for a {:.2} m gap", path.length, gap.length());
    assert!(path.length > 5.0 * gap.length(), "{}", path.length);
}

#[test]
fn maze_loop_is_solvable_and_its_loop_is_away_from_the_first_hit() {
    let s = map("maze_loop");
    assert!(joined(&s));
    let t = s.tasks[0];
    let w = s.world();
    let mut scratch = Vec::new();
    let gap = t.goal - t.start.position;
    let dir = gap.normalize();
    let hit = w.ray_cast(t.start.position, dir, gap.length(), &mut scratch).unwrap();
    let hit_point = t.start.position + dir * hit;
    // Group the walls into pieces that touch; the island is the piece away from the outer
    // walls, and the first wall hit belongs to the outer piece.
    let boxes: Vec<_> = s.obstacles.iter().map(|o| o.hull.aabb()).collect();
    let mut group: Vec<usize> = (0..boxes.len()).collect();
    let touch = |a: usize, b: usize| {
        boxes[a].min.x <= boxes[b].max.x + 1e-9
            && boxes[b].min.x <= boxes[a].max.x + 1e-9
            && boxes[a].min.y <= boxes[b].max.y + 1e-9
            && boxes[b].min.y <= boxes[a].max.y + 1e-9
    };
    for _ in 0..boxes.len() {
        for a in 0..boxes.len() {
            for b in 0..boxes.len() {
                if touch(a, b) {
                    let g = group[a].min(group[b]);
                    group[a] = g;
                    group[b] = g;
                }
            }
        }
    }
    let island: Vec<usize> = (0..boxes.len()).filter(|&i| group[i] != group[0]).collect();
    assert!(!island.is_empty(), "no free-standing wall, so no loop");
    let hit_obstacle = (0..boxes.len()).find(|&i| s.obstacles[i].parts[0].distance(hit_point) < 1e-6).unwrap();
    assert_eq!(group[hit_obstacle], group[0], "the first wall hit is the island");
    let away = island.iter().map(|&i| s.obstacles[i].parts[0].distance(hit_point)).fold(f64::INFINITY, f64::min);
    assert!(away > 2.0, "the island is {away} m from the first hit");
    // The disc can go round the island: its ring of corridor is free all the way.
    let ring = [DVec2::new(3.0, 7.0), DVec2::new(5.0, 9.0), DVec2::new(7.0, 7.0), DVec2::new(5.0, 5.0)];
    for p in ring {
        assert!(w.clearance(p, 1.0, &mut scratch) >= 0.8, "{p}");
        assert!(connected(&w, DVec2::ZERO, DVec2::splat(10.0), t.start.position, p, s.agent_radius));
    }
}

#[test]
fn spiral_goal_is_enclosed_and_reachable() {
    let s = map("spiral");
    assert!(joined(&s));
    let t = s.tasks[0];
    let w = s.world();
    let mut scratch = Vec::new();
    let mut open_from_start = 0;
    for i in 0..32 {
        let a = i as f64 * std::f64::consts::TAU / 32.0;
        let dir = DVec2::new(a.cos(), a.sin());
        assert!(w.ray_cast(t.goal, dir, 50.0, &mut scratch).is_some(), "the goal sees out along {dir}");
        if w.ray_cast(t.start.position, dir, 50.0, &mut scratch).is_none() {
            open_from_start += 1;
        }
    }
    assert!(open_from_start > 8, "the start is not outside");
    let path = strider::plan::shortest_path(&w, t.start.position, t.goal, s.agent_radius).unwrap();
    let gap = t.start.position.distance(t.goal);
    println!("spiral: shortest way {:.2} m for a {gap:.2} m gap", path.length);
    assert!(path.length > 4.0 * gap, "{}", path.length);
}

#[test]
fn run_accepts_every_new_kind() {
    for k in ["maze", "rooms", "grid"] {
        let map = format!("random:{k}");
        let o = strider(&["run", &map, "--episodes", "2", "--body", "disc", "--format", "json"]);
        // Exit 1 when an episode misses its goal; the report is printed either way.
        assert!(matches!(o.status.code(), Some(0 | 1)), "{k}: {}", String::from_utf8_lossy(&o.stderr));
        let doc: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        let episodes = doc["episodes"].as_array().unwrap();
        assert_eq!(episodes.len(), 2, "{k}");
        assert_eq!(doc["summary"]["episodes"], 2);
        for e in episodes {
            assert!(e["scenario"].as_str().unwrap().starts_with(&format!("random-{k}-")), "{e}");
            assert!(e["optimal_length_m"].as_f64().is_some(), "{k}: no shortest path in {e}");
        }
    }
    let o = strider(&["run", "random:castle", "--episodes", "1", "--body", "disc"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("castle"));
}

#[test]
fn gen_takes_a_kind_or_a_density() {
    for k in WorldKind::ALL {
        let o = strider(&["gen", "--kind", k.name(), "--seed", "9"]);
        assert!(o.status.success(), "{k}");
        let s = text::parse(&String::from_utf8(o.stdout).unwrap(), "gen.txt").unwrap();
        assert_eq!(s.obstacles, kind::generate(k, 9).obstacles, "{k}");
    }
    let a = strider(&["gen", "--density", "maze", "--seed", "4"]);
    let b = strider(&["gen", "--kind", "maze", "--seed", "4"]);
    assert!(a.status.success());
    assert_eq!(a.stdout, b.stdout);
    assert_eq!(strider(&["gen", "--kind", "castle"]).status.code(), Some(2));
}

#[test]
fn render_draws_a_building() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("render_rooms");
    let _ = std::fs::remove_dir_all(&dir);
    let out = dir.to_string_lossy();
    let o = strider(&["render", "random:rooms", "--episode", "1", "--every", "0", "--out", &out, "--body", "disc"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(dir.join("final.png").exists());
}

#[test]
fn live_view_and_experiments_take_the_kinds() {
    for k in WorldKind::ALL {
        let spec = MapSpec::parse(Some(&format!("random:{}", k.name()))).unwrap();
        assert_eq!(spec, MapSpec::Random(k));
        let loaded = strider::tui::source::load_scenario(&spec, 3);
        let s = loaded.result.unwrap();
        assert!(s.name.starts_with(&format!("random-{}-", k.name())));
    }
    assert!(MapSpec::parse(Some("random:castle")).unwrap_err().to_string().contains("castle"));

    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"));
    let script = dir.join("generators_experiment.rhai");
    std::fs::write(
        &script,
        r#"
let w = random_world("rooms", 3);
print(`name ${w.name()} tasks ${w.tasks()}`);
let s = run_batch("grid", 2, 1, default_rules());
print(`episodes ${s.episodes}`);
"#,
    )
    .unwrap();
    let o = strider(&["experiment", &script.to_string_lossy()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // `print` goes to the log, stderr; stdout stays empty.
    assert!(o.stdout.is_empty());
    let out = String::from_utf8_lossy(&o.stderr);
    assert!(out.contains("name random-rooms-3 tasks 1"), "{out}");
    assert!(out.contains("episodes 2"), "{out}");
}

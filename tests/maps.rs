//! Map importers and generators: text worlds, MovingAI grids, seeded random worlds.

use glam::DVec2;
use strider::maps::generate::{self, AREA_SIZE_M, Density, random_world};
use strider::maps::{movingai, text};
use strider::scenario::Scenario;
use strider::world::ObstacleShape;

const TINY_MAP: &str = include_str!("fixtures/maps/tiny.map");
const TINY_SCEN: &str = include_str!("fixtures/maps/tiny.map.scen");
const EVERY_ITEM: &str = include_str!("fixtures/maps/every_item.txt");
const BAD_WORD: &str = include_str!("fixtures/maps/bad_word.txt");

/// Parses `src` expecting an error; returns `(line, col, message)`.
fn text_err(src: &str) -> (usize, usize, String) {
    match text::parse(src, "w.txt") {
        Ok(s) => panic!("expected an error, parsed {} obstacles", s.obstacles.len()),
        Err(e) => {
            assert_eq!(e.file, "w.txt");
            (e.line, e.col, e.message)
        }
    }
}

fn is_connected(s: &Scenario) -> bool {
    let w = s.world();
    s.tasks.iter().all(|t| {
        generate::connected(&w, DVec2::ZERO, DVec2::splat(AREA_SIZE_M), t.start.position, t.goal, s.agent_radius)
    })
}

#[test]
fn text_world_with_every_item() {
    let (s, extras) = text::parse_with_extras(EVERY_ITEM, "fixtures/every_item.txt").unwrap();
    assert_eq!(s.name, "every_item");
    assert_eq!(s.agent_radius, 0.25);
    assert_eq!(s.tasks.len(), 2);
    let t0 = s.tasks[0];
    assert_eq!(t0.start.position, DVec2::new(0.0, 0.0));
    assert_eq!(t0.start.yaw, 1.5);
    assert_eq!(t0.goal, DVec2::new(10.0, 0.0));
    assert_eq!(t0.goal_radius, 0.8);
    assert_eq!(t0.time_limit_s, 120.0);
    let t1 = s.tasks[1];
    assert_eq!(t1.start.yaw, 0.0);
    assert_eq!(t1.goal_radius, strider::world::Task::DEFAULT_GOAL_RADIUS);
    assert_eq!(extras.ref_path_length_m, Some(10.5));
    assert_eq!(extras.optimal_time_at_2mps_s, Some(5.25));

    let kinds: Vec<&str> = s
        .obstacles
        .iter()
        .map(|o| match o.shape {
            ObstacleShape::Box { .. } => "box",
            ObstacleShape::Cylinder { .. } => "cyl",
            ObstacleShape::Convex { .. } => "convex",
            ObstacleShape::Polygon { .. } => "poly",
        })
        .collect();
    assert_eq!(kinds, ["cyl", "box", "box", "convex", "poly"]);
    assert!(matches!(s.obstacles[1].shape, ObstacleShape::Box { yaw, .. } if yaw == 0.3));
    // The U-shaped polygon is split into several convex parts; z_extent applies to it only.
    assert!(s.obstacles[4].parts.len() >= 2);
    assert_eq!((s.obstacles[4].z_min, s.obstacles[4].z_max), (0.0, 0.3));
    assert_eq!((s.obstacles[3].z_min, s.obstacles[3].z_max), strider::world::obstacle::DEFAULT_Z);
    // Plain `parse` accepts the BARN extras too.
    assert_eq!(text::parse(EVERY_ITEM, "x.txt").unwrap().tasks.len(), 2);
}

#[test]
fn text_round_trip() {
    let s = text::parse(EVERY_ITEM, "every_item.txt").unwrap();
    let written = text::write(&s);
    let back = text::parse(&written, "every_item.txt").unwrap();
    assert_eq!(back.obstacles, s.obstacles);
    assert_eq!(back.tasks, s.tasks);
    assert_eq!(back.agent_radius, s.agent_radius);
    assert_eq!(text::write(&back), written);

    for density in Density::ALL {
        let g = random_world(density, 11);
        let back = text::parse(&text::write(&g), "gen.txt").unwrap();
        assert_eq!(back.obstacles, g.obstacles, "{density}");
        assert_eq!(back.tasks, g.tasks, "{density}");
    }
}

#[test]
fn unknown_keyword_is_located() {
    let e = text::parse(BAD_WORD, "bad_word.txt").unwrap_err();
    assert_eq!((e.file.as_str(), e.line, e.col), ("bad_word.txt", 4, 1), "{e}");
    assert!(e.message.contains("unknown item `cylinder`"), "{e}");
    assert!(e.to_string().starts_with("bad_word.txt:4:1: "), "{e}");
}

#[test]
fn malformed_lines_are_located() {
    let ok = "start 0 0\ngoal 5 5\n";
    // Wrong number of numbers: too few points past the end, too many at the extra token.
    let (l, c, m) = text_err(&format!("{ok}cyl 1 2\n"));
    assert_eq!((l, c), (3, 8), "{m}");
    assert!(m.contains("needs 3"), "{m}");
    let (l, c, m) = text_err(&format!("{ok}cyl 1 2 0.5 9\n"));
    assert_eq!((l, c), (3, 13), "{m}");
    assert!(m.contains("unexpected `9`"), "{m}");
    // Not a number.
    let (l, c, m) = text_err(&format!("{ok}box 1 2 x 1\n"));
    assert_eq!((l, c), (3, 9), "{m}");
    assert!(m.contains("expected a number, found `x`"), "{m}");
    // NaN and infinity.
    let (l, c, m) = text_err("start 0 NaN\ngoal 5 5\n");
    assert_eq!((l, c), (1, 9), "{m}");
    assert!(m.contains("not a finite number"), "{m}");
    let (l, c, _) = text_err(&format!("{ok}\n  cyl 1 inf 0.5\n"));
    assert_eq!((l, c), (4, 9));
    // Negative radius and size.
    let (l, c, m) = text_err(&format!("{ok}cyl 1 1 -0.5\n"));
    assert_eq!((l, c), (3, 9), "{m}");
    assert!(m.contains("radius must be positive"), "{m}");
    let (l, c, m) = text_err(&format!("{ok}box 1 1 2 -1\n"));
    assert_eq!((l, c), (3, 11), "{m}");
    assert!(m.contains("height must be positive"), "{m}");
    let (l, c, _) = text_err("agent_radius -1\nstart 0 0\ngoal 5 5\n");
    assert_eq!((l, c), (1, 14));
    // A goal without a start, a start without a goal.
    let (l, c, m) = text_err("goal 5 5\nstart 0 0\n");
    assert_eq!((l, c), (1, 1), "{m}");
    assert!(m.contains("without a `start`"), "{m}");
    let (l, c, m) = text_err("start 0 0\ngoal 5 5\nstart 1 1\n");
    assert_eq!((l, c), (3, 7), "{m}");
    assert!(m.contains("no matching `goal`"), "{m}");
    // Odd number of polygon coordinates, and a degenerate hull (GeomError message).
    let (l, c, m) = text_err(&format!("{ok}convex 1 1 2 2 3\n"));
    assert_eq!((l, c), (3, 17), "{m}");
    assert!(m.contains("at least 6"), "{m}");
    let (l, c, m) = text_err(&format!("{ok}convex 1 1 2 2 3 3 4\n"));
    assert_eq!((l, c), (3, 20), "{m}");
    assert!(m.contains("no partner"), "{m}");
    let (l, c, m) = text_err(&format!("{ok}convex 1 1 2 2 3 3\n"));
    assert_eq!((l, c), (3, 1), "{m}");
    assert!(m.contains("collinear"), "{m}");
    let (l, _, m) = text_err(&format!("{ok}poly 0 0 2 2 2 0 0 2\n"));
    assert_eq!(l, 3, "{m}");
    assert!(m.contains("invalid `poly` obstacle"), "{m}");
}

#[test]
fn obstacle_over_start_or_goal_is_rejected() {
    let (l, c, m) = text_err("start 1 1\ngoal 9 9\ncyl 1.2 1 0.5\n");
    assert_eq!((l, c), (1, 7), "{m}");
    assert!(m.contains("the start (1, 1) of task 1 is inside the obstacle on line 3"), "{m}");
    // Grown by the agent radius: the goal is 0.2 m from the box, the agent radius 0.3 m.
    let (l, c, m) = text_err("start 1 1\n\ngoal  9 9\nbox 9 9.7 2 1\n");
    assert_eq!((l, c), (3, 7), "{m}");
    assert!(m.contains("goal"), "{m}");
}

#[test]
fn empty_world_is_rejected_clearly() {
    for src in ["", "# nothing\n\n", "cyl 1 1 1\n"] {
        let e = text::parse(src, "empty.txt").unwrap_err();
        assert_eq!(e.file, "empty.txt");
        assert!(e.message.contains("no task"), "{e}");
        assert!(e.message.contains("start"), "{e}");
    }
}

#[test]
fn movingai_tiny_map() {
    let grid = movingai::parse_map(TINY_MAP, "tiny.map").unwrap();
    assert_eq!((grid.width(), grid.height()), (6, 5));
    assert_eq!(grid.blocked_count(), 7);
    assert!(grid.is_blocked(1, 1) && grid.is_blocked(4, 2) && grid.is_blocked(0, 4));
    assert!(!grid.is_blocked(0, 0) && !grid.is_blocked(5, 4));
    let lines = movingai::parse_scen(TINY_SCEN, "tiny.map.scen").unwrap();
    assert_eq!(lines.len(), 2);
    assert_eq!(lines[1].bucket, 1);
    assert_eq!(lines[1].map, "tiny.map");
    assert_eq!((lines[1].start, lines[1].goal), ((3, 1), (0, 3)));
    assert_eq!(lines[0].optimal_length, 6.41421356);

    let s = movingai::load(TINY_MAP, "tiny.map", TINY_SCEN, "tiny.map.scen").unwrap();
    assert_eq!(s.name, "tiny");
    assert_eq!(s.agent_radius, 0.3);
    // Three merged rectangles plus four walls.
    assert_eq!(s.obstacles.len(), 3 + 4);
    assert_eq!(grid.merged_rects().len(), 3);
    // Cell (0, 0) is the top-left cell: its centre is (0.5, 4.5).
    assert_eq!(s.tasks[0].start.position, DVec2::new(0.5, 4.5));
    assert_eq!(s.tasks[0].goal, DVec2::new(5.5, 0.5));
    assert_eq!(s.tasks[1].start.position, DVec2::new(3.5, 3.5));
    assert_eq!(s.tasks[0].time_limit_s, 20.0 * 6.41421356);
    let short = movingai::scenario_from(&grid, &[movingai::ScenLine { optimal_length: 1.0, ..lines[1].clone() }], "t");
    assert_eq!(short.tasks[0].time_limit_s, 60.0);
    // The 2×2 block of cells (1..3, 1..3) is the box [1, 3] × [2, 4].
    let ObstacleShape::Box { center, width, height, .. } = s.obstacles[0].shape else { panic!("not a box") };
    assert_eq!((center, width, height), (DVec2::new(2.0, 3.0), 2.0, 2.0));
    // Agents cannot leave: the walls enclose the map.
    let w = s.world();
    let mut scratch = Vec::new();
    for p in [DVec2::new(-0.5, 2.0), DVec2::new(6.5, 2.0), DVec2::new(3.0, -0.5), DVec2::new(3.0, 5.5)] {
        assert_eq!(w.clearance(p, 1.0, &mut scratch), 0.0, "{p}");
    }
    // Every blocked cell centre is inside an obstacle, every free one is not.
    for y in 0..5 {
        for x in 0..6 {
            let c = w.clearance(grid.cell_center(x, y), 0.4, &mut scratch);
            assert_eq!(c == 0.0, grid.is_blocked(x, y), "cell ({x}, {y})");
        }
    }
}

#[test]
fn movingai_32x32_merges_into_few_boxes() {
    // A deterministic 32×32 map with about 20 % blocked cells in blobs and a wall.
    let mut rows = vec![vec!['.'; 32]; 32];
    let mut state = 12345u64;
    for _ in 0..40 {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        let (x, y) = ((state >> 33) as usize % 29, (state >> 45) as usize % 29);
        for row in rows.iter_mut().skip(y).take(3) {
            for cell in row.iter_mut().skip(x).take(3) {
                *cell = '@';
            }
        }
    }
    for row in rows.iter_mut().take(28) {
        row[16] = 'T';
    }
    let mut map = String::from("type octile\nheight 32\nwidth 32\nmap\n");
    for row in &rows {
        map.extend(row.iter());
        map.push('\n');
    }
    let grid = movingai::parse_map(&map, "gen.map").unwrap();
    let cells = grid.blocked_count();
    let rects = grid.merged_rects();
    let covered: usize = rects.iter().map(|r| (r.x1 - r.x0) * (r.y1 - r.y0)).sum();
    assert_eq!(covered, cells, "rectangles cover each blocked cell once");
    for r in &rects {
        for y in r.y0..r.y1 {
            for x in r.x0..r.x1 {
                assert!(grid.is_blocked(x, y));
            }
        }
    }
    let s = movingai::scenario_from(&grid, &[], "gen");
    println!("32×32 map: {cells} blocked cells → {} boxes (+4 walls)", rects.len());
    assert_eq!(s.obstacles.len(), rects.len() + 4);
    assert!(rects.len() * 4 < cells, "{} boxes for {cells} cells", rects.len());
}

#[test]
fn movingai_errors_are_located() {
    let err = |map: &str| movingai::parse_map(map, "m.map").unwrap_err();
    let e = err("type octile\nheight 2\nwidth 3\nmap\n...\n..\n");
    assert_eq!((e.line, e.col), (6, 3), "{e}");
    let e = err("type octile\nheight 2\nwidth 3\nmap\n....\n...\n");
    assert_eq!((e.line, e.col), (5, 4), "{e}");
    let e = err("type octile\nheight 3\nwidth 3\nmap\n...\n...\n");
    assert_eq!(e.line, 7, "{e}");
    assert!(e.message.contains("2 rows, expected 3"), "{e}");
    let e = err("type octile\nheight two\nwidth 3\nmap\n");
    assert_eq!((e.line, e.col), (2, 8), "{e}");
    let e = err("type octile\nwidth 3\nmap\n...\n");
    assert!(e.message.contains("missing `height`"), "{e}");
    let e = err("type octile\nheight 1\nwidth 3\nmap\n...\nxyz\n");
    assert_eq!((e.line, e.col), (6, 1), "{e}");

    let scen = |s: &str| movingai::parse_scen(s, "s.scen");
    assert!(scen("version 1.0\n0 tiny.map 6 5 0 0 5 4 6.4\n").is_ok());
    let e = scen("version 2\n").unwrap_err();
    assert_eq!((e.line, e.col), (1, 9), "{e}");
    let e = scen("0\ttiny.map\n").unwrap_err();
    assert_eq!((e.line, e.col), (1, 1), "{e}");
    let e = scen("version 1\n0\ttiny.map\t6\t5\t0\t0\t5\t4\n").unwrap_err();
    assert_eq!(e.line, 2, "{e}");
    assert!(e.message.contains("expected 9 fields"), "{e}");
    let e = scen("version 1\n0\ttiny.map\t6\t5\t-1\t0\t5\t4\t6.4\n").unwrap_err();
    assert_eq!((e.line, e.col), (2, 16), "{e}");
    let e = scen("version 1\n0\ttiny.map\t6\t5\t0\t0\t5\t4\tnan\n").unwrap_err();
    assert_eq!((e.line, e.col), (2, 24), "{e}");

    // A blocked start, a goal outside, a size mismatch.
    let load = |s: &str| movingai::load(TINY_MAP, "tiny.map", s, "t.scen").unwrap_err();
    let e = load("version 1\n0\ttiny.map\t6\t5\t1\t1\t5\t4\t6.4\n");
    assert_eq!((e.file.as_str(), e.line, e.col), ("t.scen", 2, 16), "{e}");
    assert!(e.message.contains("blocked"), "{e}");
    let e = load("version 1\n0\ttiny.map\t6\t5\t0\t0\t6\t4\t6.4\n");
    assert_eq!((e.line, e.col), (2, 20), "{e}");
    let e = load("version 1\n0\ttiny.map\t7\t5\t0\t0\t5\t4\t6.4\n");
    assert_eq!((e.line, e.col), (2, 12), "{e}");
}

#[test]
fn generator_is_deterministic() {
    for density in Density::ALL {
        let a = text::write(&random_world(density, 42));
        let b = text::write(&random_world(density, 42));
        assert_eq!(a, b, "{density}");
        let c = text::write(&random_world(density, 43));
        assert_ne!(a, c, "{density}");
    }
}

#[test]
fn generated_worlds_are_valid_and_connected() {
    for density in Density::ALL {
        for seed in 0..4 {
            let s = random_world(density, seed);
            s.validate().unwrap();
            assert!(is_connected(&s), "{density} seed {seed}");
            let t = s.tasks[0];
            assert!(t.start.position.x < 3.0 && t.start.position.y < 3.0);
            assert!(t.goal.x > 17.0 && t.goal.y > 17.0);
            let placed = s.obstacles.len() - 4;
            assert!(placed <= density.obstacle_count(), "{density}: {placed}");
            assert!(placed + 4 >= density.obstacle_count() / 2, "{density} seed {seed}: {placed} obstacles");
            let w = s.world();
            let mut scratch = Vec::new();
            for p in [t.start.position, t.goal] {
                assert!(w.clearance(p, 1.0, &mut scratch) >= s.agent_radius + 0.5 - 1e-9);
            }
        }
    }
}

#[test]
fn connectivity_check_sees_a_closed_wall() {
    let src = "start 2 2\ngoal 18 18\nbox 10 10 1 40\n";
    let s = text::parse(src, "wall.txt").unwrap();
    assert!(!is_connected(&s));
    let open = text::parse("start 2 2\ngoal 18 18\nbox 10 5 1 10\n", "open.txt").unwrap();
    assert!(is_connected(&open));
}

#[test]
fn density_names() {
    for d in Density::ALL {
        assert_eq!(d.to_string().parse::<Density>(), Ok(d));
    }
    assert_eq!("semi".parse::<Density>(), Ok(Density::Semi));
    assert!("dense".parse::<Density>().unwrap_err().to_string().contains("dense"));
}

/// A BARN world file of the challenge's own format with `cylinders` (x, y), and its path file.
fn barn_files(dir: &std::path::Path, n: usize, cylinders: &[(f64, f64)], path_in_subfolder: bool) {
    let models: String = cylinders
        .iter()
        .enumerate()
        .map(|(i, (x, y))| {
            format!(
                "<model name='unit_cylinder_{i}'><pose frame=''>{x} {y} 0 0 0 0</pose><link name='link'><collision \
                 name='collision'><geometry><cylinder><radius>0.075</radius><length>1</length></cylinder></geometry>\
                 </collision></link></model>\n"
            )
        })
        .collect();
    let world = format!("<sdf version='1.6'><world name='default'>\n{models}<state>{models}</state></world></sdf>\n");
    std::fs::write(dir.join(format!("world_{n}.world")), world).unwrap();
    // Two cells straight up the middle: (15, 0) and (15, 1).
    let header = "{'descr': '<i8', 'fortran_order': False, 'shape': (2, 2), }";
    let pad = 64 - (10 + header.len() + 1) % 64;
    let mut npy = b"\x93NUMPY\x01\x00".to_vec();
    npy.extend(((header.len() + pad + 1) as u16).to_le_bytes());
    npy.extend(header.bytes());
    npy.extend(std::iter::repeat_n(b' ', pad));
    npy.push(b'\n');
    for v in [15i64, 0, 15, 1] {
        npy.extend(v.to_le_bytes());
    }
    let at = if path_in_subfolder { dir.join("path_files") } else { dir.to_path_buf() };
    std::fs::create_dir_all(&at).unwrap();
    std::fs::write(at.join(format!("path_{n}.npy")), npy).unwrap();
}

#[test]
fn barn_worlds_and_folders_of_them_run_as_batches() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("barn_folder");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    // A wall of cylinders with a gap, in world 10, and an open world 2 (its path in path_files/).
    let wall: Vec<(f64, f64)> =
        (0..30).map(|i| (-4.5 + 0.15 * i as f64, 8.0)).filter(|p| (p.0 + 2.25).abs() > 0.6).collect();
    barn_files(&dir, 10, &wall, false);
    barn_files(&dir, 2, &[(-0.3, 6.0)], true);
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_strider"))
        .args(["run", dir.to_str().unwrap(), "--body", "disc", "--format", "json"])
        .output()
        .unwrap();
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let json: serde_json::Value = serde_json::from_slice(&run.stdout).unwrap();
    let episodes = json["episodes"].as_array().unwrap();
    assert_eq!(episodes.len(), 2);
    // world_2 before world_10; both reached with a BARN score; the reference runs start →
    // (−2.325, 5.075) → (−2.325, 5.225) → goal, so OT is known and the score is at most 0.5.
    for e in episodes {
        assert_eq!(e["reached"], true, "{e}");
        assert_eq!(e["collisions"], 0, "{e}");
        let score = e["barn_score"].as_f64().unwrap();
        assert!(score > 0.0 && score <= 0.5, "{e}");
    }
    assert!(json["summary"]["barn_score"].as_f64().unwrap() > 0.0);
    // Without its path file a world still runs, with no score, and says why.
    std::fs::remove_file(dir.join("path_10.npy")).unwrap();
    let one = std::process::Command::new(env!("CARGO_BIN_EXE_strider"))
        .args(["run", dir.join("world_10.world").to_str().unwrap(), "--body", "disc", "--format", "json"])
        .output()
        .unwrap();
    assert!(String::from_utf8_lossy(&one.stderr).contains("no path_N.npy"), "{}", String::from_utf8_lossy(&one.stderr));
    let json: serde_json::Value = serde_json::from_slice(&one.stdout).unwrap();
    assert!(json["episodes"][0]["barn_score"].is_null(), "{}", json["episodes"][0]);
}

/// Benchmark data is named by set (`movingai:NAME`, `barn:NAME`, `barn:` for the folder) and
/// read from the folder `$STRIDER_DATA` names: the same runs as the files' own paths give.
#[test]
fn benchmark_data_is_read_from_the_data_folder() {
    let root = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("benchmark_data");
    let _ = std::fs::remove_dir_all(&root);
    let fixtures = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/maps");
    std::fs::create_dir_all(root.join("movingai")).unwrap();
    for f in ["tiny.map", "tiny.map.scen"] {
        std::fs::copy(fixtures.join(f), root.join("movingai").join(f)).unwrap();
    }
    std::fs::copy(fixtures.join("tiny.map.scen"), root.join("movingai/other.scen")).unwrap();
    std::fs::create_dir_all(root.join("barn")).unwrap();
    barn_files(&root.join("barn"), 2, &[(-0.3, 6.0)], true);
    let run = |args: &[&str]| {
        std::process::Command::new(env!("CARGO_BIN_EXE_strider"))
            .args(args)
            .env("STRIDER_DATA", &root)
            .output()
            .unwrap()
    };
    let path = |p: &str| root.join(p).to_str().unwrap().to_string();
    for (named, direct) in [
        (vec!["run", "movingai:tiny", "--body", "disc"], vec!["run".to_string(), path("movingai/tiny.map")]),
        (
            vec!["run", "movingai:tiny.map", "--scen", "movingai:other.scen", "--body", "disc"],
            vec!["run".to_string(), path("movingai/tiny.map"), "--scen".into(), path("movingai/other.scen")],
        ),
        (vec!["run", "barn:world_2", "--body", "disc"], vec!["run".to_string(), path("barn/world_2.world")]),
        (vec!["run", "barn:", "--body", "disc"], vec!["run".to_string(), path("barn")]),
    ] {
        let a = run(&named);
        let mut direct = direct;
        direct.extend(["--body".to_string(), "disc".to_string()]);
        let b = run(&direct.iter().map(String::as_str).collect::<Vec<_>>());
        assert!(a.status.success(), "{named:?}: {}", String::from_utf8_lossy(&a.stderr));
        assert_eq!(a.stdout, b.stdout, "{named:?}");
    }
    let missing = run(&["run", "movingai:absent"]);
    let err = String::from_utf8_lossy(&missing.stderr);
    assert_eq!(missing.status.code(), Some(2), "{err}");
    assert!(err.contains("movingai/absent.map") && err.contains("$STRIDER_DATA"), "{err}");
}

//! The live terminal view rendered into ratatui's `TestBackend` (DESIGN.md §6): layout at
//! common sizes, the panels, the help overlay, the too-small notice, goal setting by mouse,
//! hot reload of a broken rule script, and the same run as headless `strider run`.

use std::path::PathBuf;

use crossterm::event::{KeyCode, KeyEvent, KeyModifiers, MouseButton, MouseEvent, MouseEventKind};
use ratatui::Terminal;
use ratatui::backend::TestBackend;
use strider::sim::Body;
use strider::tui::{App, Config, MapSpec, ui};

fn u_trap() -> App {
    App::load(Config { map: MapSpec::file("maps/u_trap.rhai"), rules: None, seed: 1, animation: None }).unwrap()
}

/// Renders `app` on a `w`×`h` screen and returns the screen's text, one string per row.
fn screen(app: &mut App, w: u16, h: u16) -> Vec<String> {
    let mut t = Terminal::new(TestBackend::new(w, h)).unwrap();
    t.draw(|f| ui::draw(f, app)).unwrap();
    let buf = t.backend().buffer();
    (0..h).map(|y| (0..w).map(|x| buf[(x, y)].symbol().to_string()).collect()).collect()
}

fn contains(rows: &[String], s: &str) -> bool {
    rows.iter().any(|r| r.contains(s))
}

fn key(c: char) -> KeyEvent {
    KeyEvent::new(KeyCode::Char(c), KeyModifiers::NONE)
}

#[test]
fn readable_at_80_by_24() {
    let mut app = u_trap();
    app.advance(0.5);
    let rows = screen(&mut app, 80, 24);
    let text = rows.join("\n");
    for want in ["strider", "u_trap", "Agent 1/1", "Fuzzy inputs", "Fuzzy outputs", "Rules fired", "Log", "? help"] {
        assert!(text.contains(want), "missing {want:?} in\n{text}");
    }
    for var in ["goal_angle", "front", "left", "right", "turn", "speed", "follow_turn"] {
        assert!(text.contains(var), "missing variable {var} in\n{text}");
    }
    // The world view shows braille dots (obstacles, sectors, trail) and its scale bar.
    assert!(text.chars().any(|c| ('\u{2801}'..='\u{28ff}').contains(&c)));
    assert!(text.contains(" m"), "no scale bar label in\n{text}");
    assert!(app.canvas_view.is_some());
}

#[test]
fn wide_screen_shows_rule_texts_and_metrics() {
    let mut app = u_trap();
    app.advance(0.25);
    let rows = screen(&mut app, 200, 60);
    let text = rows.join("\n");
    for want in ["goal_angle is", "then goal_turn is", "clearance", "collisions 0", "path", "seek"] {
        assert!(text.contains(want), "missing {want:?} in\n{text}");
    }
}

#[test]
fn too_small_terminal_shows_a_notice() {
    let mut app = u_trap();
    for (w, h) in [(50, 15), (79, 10), (20, 5), (1, 1)] {
        let rows = screen(&mut app, w, h);
        if w >= 20 {
            assert!(contains(&rows, "too small"), "{w}×{h}: {rows:?}");
        }
        assert!(app.canvas_view.is_none());
    }
}

#[test]
fn help_overlay_and_pause() {
    let mut app = u_trap();
    app.on_key(key('?'));
    let rows = screen(&mut app, 80, 24);
    assert!(contains(&rows, "Help"));
    assert!(contains(&rows, "pause / resume"));
    app.on_key(key('?'));
    app.on_key(key(' '));
    let rows = screen(&mut app, 80, 24);
    assert!(!contains(&rows, "pause / resume"));
    assert!(contains(&rows, "paused"));
    app.on_key(key('.'));
    let rows = screen(&mut app, 80, 24);
    assert!(contains(&rows, "t 0.05 s"), "{}", rows.join("\n"));
}

#[test]
fn click_sets_the_goal_where_the_mouse_is() {
    let mut app = u_trap();
    screen(&mut app, 100, 30);
    let (area, _) = app.canvas_view.unwrap();
    // Somewhere left of the start, in open space.
    let (col, row) = (area.x + 2, area.y + area.height / 2);
    let p = app.world_at(col, row).unwrap();
    for kind in [MouseEventKind::Down(MouseButton::Left), MouseEventKind::Up(MouseButton::Left)] {
        app.on_mouse(MouseEvent { kind, column: col, row, modifiers: KeyModifiers::NONE });
    }
    assert_eq!(app.sim.agents[0].task.goal, p);
    assert!(p.x < 0.0, "{p}");
}

#[test]
fn manual_drag_drives_forward() {
    let mut app = u_trap();
    app.on_key(key('m'));
    screen(&mut app, 100, 30);
    let (area, _) = app.canvas_view.unwrap();
    let (col, row) = (area.x + area.width / 2, area.y + area.height - 2);
    let ev = |kind, column, row| MouseEvent { kind, column, row, modifiers: KeyModifiers::NONE };
    app.on_mouse(ev(MouseEventKind::Down(MouseButton::Left), col, row));
    app.on_mouse(ev(MouseEventKind::Drag(MouseButton::Left), col, row - area.height / 2));
    assert!(app.manual_command.speed > 1.0 && app.manual_command.turn_rate == 0.0, "{:?}", app.manual_command);
    let yaw = app.sim.agents[0].body.pose().yaw;
    for _ in 0..20 {
        app.step();
    }
    assert!(app.sim.agents[0].metrics.path_length_m > 0.5);
    assert_eq!(app.sim.agents[0].body.pose().yaw, yaw);
    let rows = screen(&mut app, 100, 30);
    assert!(contains(&rows, "MANUAL"));
}

#[test]
fn broken_rule_edit_keeps_the_last_good_rules_and_logs_the_place() {
    let dir = std::env::temp_dir().join(format!("strider-tui-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let rules: PathBuf = dir.join("nav.rhai");
    std::fs::copy("scripts/nav.rhai", &rules).unwrap();
    let mut app = App::load(Config {
        map: MapSpec::file("maps/u_trap.rhai"),
        rules: Some(rules.clone()),
        seed: 1,
        animation: None,
    })
    .unwrap();
    app.advance(0.5);
    let stages = app.sim.agents[0].controller.network().stages().len();
    std::fs::write(&rules, "let e = fuzzy_engine(\"x\");\nlet v = e.input(\"front\", 0.0, 5.0;\ne\n").unwrap();
    app.reload_rules();
    let errors: Vec<_> = app.log.iter().filter(|l| l.level == strider::tui::app::LogLevel::Error).collect();
    assert_eq!(errors.len(), 1, "{:?}", app.log);
    let place = format!("{}:2:", rules.display());
    assert!(errors[0].text.contains(&place), "{:?}", errors[0]);
    // Still running on the old rules.
    let t = app.sim.time_s;
    app.advance(0.5);
    assert!(app.sim.time_s > t);
    assert_eq!(app.sim.agents[0].controller.network().stages().len(), stages);
    let rows = screen(&mut app, 120, 40);
    assert!(contains(&rows, "keeping the previous rules"), "{}", rows.join("\n"));
    // A good edit is picked up.
    let good = std::fs::read_to_string("scripts/nav.rhai").unwrap() + "\n// edited\n";
    std::fs::write(&rules, good).unwrap();
    app.reload_rules();
    assert!(app.log.back().unwrap().text.ends_with("reloaded"), "{:?}", app.log.back());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn same_run_as_headless() {
    let mut app = u_trap();
    for _ in 0..30 {
        app.on_key(key('+'));
    }
    while !app.finished() {
        app.advance(0.25);
    }
    let world = app.scenario.world();
    let mut params = strider::sim::StepParameters::default();
    params.limits.radius = app.scenario.agent_radius;
    let e = strider::experiment::run_episode(&app.scenario, &world, 0, &app.controller, &params, 0, 0);
    assert_eq!(app.sim.agents[0].trail, e.trail);
}

#[test]
fn a_character_on_terrain_shows_its_footstep_window() {
    use std::sync::Arc;
    use strider::sim::AnimationHandle;
    let animation = Some(AnimationHandle(Arc::new(strider::builtin::animation().unwrap())));
    let config = Config { map: MapSpec::file("maps/terrain_fig8_trap.rhai"), rules: None, seed: 1, animation };
    let mut app = App::load(config).unwrap();
    // Walk until a few steps have been planned and one is playing.
    let planned = |app: &App| {
        let f = app.sim.agents[0].body.animated().unwrap().footing().unwrap();
        f.played().is_some() && f.plans() >= 3
    };
    for _ in 0..2000 {
        if planned(&app) {
            break;
        }
        app.sim.step();
    }
    assert!(planned(&app));
    let f = app.sim.agents[0].body.animated().unwrap().footing().unwrap();
    let n = f.params().window_steps;
    let rows = screen(&mut app, 120, 40);
    let title = rows.iter().position(|r| r.contains("Footsteps · n = 3")).expect("the footstep panel");
    let panel: Vec<Vec<char>> = rows[title + 1..title + 8].iter().map(|r| r.chars().collect()).collect();
    let side_x = 120 - 48; // the side column: two fifths of the width
    // The supporting foot and each planned foothold stand on the ground, left to right.
    let mut columns = Vec::new();
    for mark in
        std::iter::once('L').chain(std::iter::once('R')).chain((1..=n).map(|k| char::from_digit(k as u32, 10).unwrap()))
    {
        for (y, row) in panel.iter().enumerate().take(6) {
            for (x, &c) in row.iter().enumerate().skip(side_x) {
                if c == mark {
                    assert_eq!(
                        panel[y + 1][x],
                        '█',
                        "{mark} stands on the ground:\n{}",
                        rows[title..title + 8].join("\n")
                    );
                    if mark.is_ascii_digit() {
                        columns.push(x);
                    }
                }
            }
        }
    }
    assert_eq!(columns.len(), n, "{}", rows[title..title + 8].join("\n"));
    assert!(columns.windows(2).all(|w| w[0] < w[1]), "{columns:?}");
    assert!(panel[6].iter().collect::<String>().contains("steps "));
}

#[test]
fn a_character_under_a_bar_shows_its_upper_body() {
    use std::sync::Arc;
    use strider::sim::AnimationHandle;
    let animation = Some(AnimationHandle(Arc::new(strider::builtin::animation().unwrap())));
    let config = Config { map: MapSpec::file("maps/upper_overhead_bar.rhai"), rules: None, seed: 1, animation };
    let mut app = App::load(config).unwrap();
    // Walk until the waist bends for the first bar.
    let bend = |app: &App| app.sim.agents[0].body.animated().unwrap().upper_offsets().waist[0].to_degrees();
    for _ in 0..2000 {
        if bend(&app) > 30.0 {
            break;
        }
        app.sim.step();
    }
    assert!(bend(&app) > 30.0);
    let rows = screen(&mut app, 120, 40);
    let line = rows.iter().find(|r| r.contains("upper bend")).expect("the upper body's line");
    let shown: f64 = line.split("upper bend").nth(1).unwrap().trim_start().split('°').next().unwrap().parse().unwrap();
    assert!((shown - bend(&app)).abs() < 0.5, "{line}");
}

//! The screen of the live view (DESIGN.md §6): a title line, the world drawn by
//! [`draw_scene`] on a [`TermCanvas`], the log under it, the side panels (agent metrics and
//! mode; fuzzy inputs with their term memberships, outputs, and the rules that fired, seed 000
//! §3.1, Fig 1), a line of key hints, and the help overlay.
//!
//! Drawing is a function of the [`App`] and the area only, so ratatui's `TestBackend` can
//! check any screen size. Below [`MIN_WIDTH`]×[`MIN_HEIGHT`] cells only a "too small" notice
//! is drawn. When the selected agent is a character on uneven terrain, the side column also
//! shows its footstep window (seed 002 §4.2): the ground profile ahead in characters, the
//! supporting foot and the n planned footholds.

use ratatui::Frame;
use ratatui::buffer::Buffer;
use ratatui::layout::{Alignment, Constraint, Layout, Rect};
use ratatui::style::{Color, Modifier, Style};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, Clear, Paragraph, Widget, Wrap};

use super::app::{App, LogLevel};
use super::canvas::TermCanvas;
use crate::footstep::Foot;
use crate::render::scene::{Painter, ViewTransform, draw_scene, scene_transform};
use crate::sim::footing::{Footing, PlayedStep};
use crate::sim::{Body, Mode, Outcome, Side};

/// Narrowest terminal the view is drawn in, cells.
pub const MIN_WIDTH: u16 = 60;
/// Shortest terminal the view is drawn in, cells.
pub const MIN_HEIGHT: u16 = 18;

/// Where each part of the screen goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Areas {
    /// Title line.
    pub title: Rect,
    /// The world view.
    pub world: Rect,
    /// Log panel (under the world).
    pub log: Rect,
    /// Side column (agent, fuzzy inputs, outputs, rules).
    pub side: Rect,
    /// Key hints line.
    pub footer: Rect,
}

/// The layout of a screen of `area`, or `None` when it is smaller than
/// [`MIN_WIDTH`]×[`MIN_HEIGHT`].
pub fn areas(area: Rect) -> Option<Areas> {
    if area.width < MIN_WIDTH || area.height < MIN_HEIGHT {
        return None;
    }
    let [title, body, footer] =
        Layout::vertical([Constraint::Length(1), Constraint::Min(1), Constraint::Length(1)]).areas(area);
    let side_w = (area.width * 2 / 5).clamp(34, 72);
    let [left, side] = Layout::horizontal([Constraint::Min(1), Constraint::Length(side_w)]).areas(body);
    let log_h = (body.height / 4).clamp(4, 12);
    let [world, log] = Layout::vertical([Constraint::Min(1), Constraint::Length(log_h)]).areas(left);
    Some(Areas { title, world, log, side, footer })
}

/// Draws the whole screen into `frame` and records in `app` where the world went (for the
/// mouse), reusing the app's canvas from frame to frame.
pub fn draw(frame: &mut Frame, app: &mut App) {
    let area = frame.area();
    let mut canvas = std::mem::replace(&mut app.canvas, TermCanvas::new(0, 0));
    let view = render(app, &mut canvas, area, frame.buffer_mut());
    app.canvas = canvas;
    app.canvas_view = view;
}

/// Draws the whole screen of `app` into `buf` over `area`, the world through `canvas` (scratch
/// space, overwritten). Reads the app only; returns where the world was drawn and with which
/// transform (`None` when the terminal is too small).
pub fn render(app: &App, canvas: &mut TermCanvas, area: Rect, buf: &mut Buffer) -> Option<(Rect, ViewTransform)> {
    let Some(a) = areas(area) else {
        too_small(area, buf);
        return None;
    };
    title(app, a.title, buf);
    let view = world(app, canvas, a.world, buf);
    log(app, a.log, buf);
    side(app, a.side, buf);
    footer(app, a.footer, buf);
    if app.show_help {
        help(area, buf);
    }
    Some(view)
}

const ACCENT: Color = Color::Cyan;
const DIM: Style = Style::new().add_modifier(Modifier::DIM);

fn section(title: String) -> Block<'static> {
    Block::new()
        .borders(Borders::TOP)
        .border_style(DIM)
        .title(Span::styled(format!(" {title} "), Style::new().fg(ACCENT).add_modifier(Modifier::BOLD)))
}

fn too_small(area: Rect, buf: &mut Buffer) {
    Clear.render(area, buf);
    let lines = vec![
        Line::from("terminal too small"),
        Line::from(format!("{}×{}, need {MIN_WIDTH}×{MIN_HEIGHT}", area.width, area.height)),
        Line::from("q quits"),
    ];
    let top = area.height.saturating_sub(3) / 2;
    let r = Rect { y: area.y + top, height: area.height.saturating_sub(top), ..area };
    Paragraph::new(lines).alignment(Alignment::Center).wrap(Wrap { trim: true }).render(r, buf);
}

fn title(app: &App, area: Rect, buf: &mut Buffer) {
    let state = if app.finished() {
        Span::styled("■ finished", Style::new().fg(Color::Yellow))
    } else if app.paused {
        Span::styled("❚❚ paused", Style::new().fg(Color::Yellow))
    } else if app.behind {
        Span::styled(format!("▶ {}× (behind)", speed_text(app.speed())), Style::new().fg(Color::Red))
    } else {
        Span::styled(format!("▶ {}×", speed_text(app.speed())), Style::new().fg(Color::Green))
    };
    let mode = if app.manual {
        Span::styled("MANUAL", Style::new().fg(Color::Magenta).add_modifier(Modifier::BOLD))
    } else {
        Span::styled("autopilot", Style::new().fg(ACCENT))
    };
    let line = Line::from(vec![
        Span::styled(" strider ", Style::new().add_modifier(Modifier::BOLD | Modifier::REVERSED)),
        Span::raw(format!(" {} · seed {} · ", app.map_name(), app.config.seed)),
        state,
        Span::raw(" · "),
        mode,
        Span::raw(format!(" · t {:.2} s", app.sim.time_s)),
    ]);
    Paragraph::new(line).render(area, buf);
}

fn speed_text(s: f64) -> String {
    if s >= 1.0 { format!("{s:.0}") } else { format!("{s}") }
}

fn world(app: &App, canvas: &mut TermCanvas, area: Rect, buf: &mut Buffer) -> (Rect, ViewTransform) {
    canvas.reset(area.width, area.height);
    let scene = app.scene();
    draw_scene(&scene, canvas);
    let tf = scene_transform(&scene, canvas.size(), canvas.text_size("M").y);
    (&*canvas).render(area, buf);
    (area, tf)
}

fn log(app: &App, area: Rect, buf: &mut Buffer) {
    let block = section("Log".into());
    let inner = block.inner(area);
    block.render(area, buf);
    // The newest lines that fit, long ones wrapped at the panel's width.
    let (w, n) = (usize::from(inner.width).max(1), usize::from(inner.height));
    let mut lines: Vec<Line> = Vec::new();
    for l in app.log.iter().rev() {
        if lines.len() >= n {
            break;
        }
        let style = match l.level {
            LogLevel::Info => Style::new(),
            LogLevel::Error => Style::new().fg(Color::Red),
        };
        let chars: Vec<char> = l.text.chars().collect();
        for chunk in chars.chunks(w).rev() {
            lines.push(Line::styled(chunk.iter().collect::<String>(), style));
        }
    }
    lines.truncate(n);
    lines.reverse();
    Paragraph::new(lines).render(inner, buf);
}

fn side(app: &App, area: Rect, buf: &mut Buffer) {
    let Some(agent) = app.sim.agents.get(app.selected) else {
        Paragraph::new("no agent").block(section("Agent".into())).render(area, buf);
        return;
    };
    let net = agent.controller.network();
    let n_in = net.input_names().count() as u16;
    let n_out = net.output_names().count() as u16;
    // On short screens the agent panel drops its command line (the outputs show it).
    let agent_h = if area.height < 30 { 3 } else { 4 };
    // A character among obstacles its upper body can touch gets a line for it (seed 002 §5).
    let upper = app.sim.agents.get(app.selected).and_then(|a| a.body.animated()).and_then(|b| b.upper_body());
    let agent_h = agent_h + u16::from(upper.is_some());
    // A character on uneven terrain also gets the footstep window (seed 002 §4.2).
    let steps_h = if footing_of(app).is_some() { FOOTSTEP_PANEL_H } else { 0 };
    let [a_area, i_area, o_area, f_area, r_area] = Layout::vertical([
        Constraint::Length(agent_h),
        Constraint::Length(n_in + 1),
        Constraint::Length(n_out + 1),
        Constraint::Length(steps_h),
        Constraint::Min(2),
    ])
    .areas(area);
    // Left border separates the column from the world view.
    let sep = Block::new().borders(Borders::LEFT).border_style(DIM);
    let inner_of = |r: Rect| Rect { x: r.x + 1, width: r.width.saturating_sub(1), ..r };
    sep.render(area, buf);
    agent_panel(app, inner_of(a_area), buf);
    inputs_panel(app, inner_of(i_area), buf);
    outputs_panel(app, inner_of(o_area), buf);
    if steps_h > 0 {
        footstep_panel(app, inner_of(f_area), buf);
    }
    rules_panel(app, inner_of(r_area), buf);
}

/// Rows of the footstep panel: its title, the side view and a line of step lengths.
const FOOTSTEP_PANEL_H: u16 = 8;

/// Colour of a foot's marks in the footstep panel (left blue, right red, as in the PNG side view).
fn foot_colour(foot: Foot) -> Color {
    match foot {
        Foot::Left => Color::Blue,
        Foot::Right => Color::Red,
    }
}

/// The selected agent's footing, when it is a character on uneven terrain.
fn footing_of(app: &App) -> Option<&Footing> {
    app.sim.agents.get(app.selected)?.body.animated()?.footing()
}

/// One cell of the footstep panel's side view.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Cell {
    symbol: char,
    style: Style,
}

/// The footstep window in characters (seed 002 §4.2): the ground profile ahead of the
/// supporting foot in a `cols`×`rows` grid (solid ground `█`, gaps empty), the supporting foot
/// as `L`/`R` and the n planned footholds as `1`…`n` standing on the ground, in their feet's
/// colours.
fn footstep_grid(step: &PlayedStep, swinging: Foot, cols: usize, rows: usize) -> Vec<Vec<Cell>> {
    let blank = Cell { symbol: ' ', style: Style::new() };
    let mut grid = vec![vec![blank; cols]; rows];
    if cols == 0 || rows == 0 {
        return grid;
    }
    let profile = &step.profile;
    let stance = step.swing.stance;
    let mut marks = vec![(stance.x_m, swinging.other(), None)];
    let (mut x, mut foot) = (stance.x_m, swinging);
    for (i, s) in step.window_m.iter().enumerate() {
        x += s;
        marks.push((x, foot, Some(i + 1)));
        foot = foot.other();
    }
    let x_lo = stance.x_m - 0.4;
    let x_hi = x + 0.4;
    let dx = (x_hi - x_lo) / cols as f64;
    let column = |x: f64| ((x - x_lo) / dx).floor();
    let heights: Vec<Option<f64>> = (0..cols).map(|c| profile.height_at(x_lo + (c as f64 + 0.5) * dx)).collect();
    let known = || heights.iter().flatten().copied();
    let (z_lo, z_hi) = (known().fold(f64::INFINITY, f64::min), known().fold(f64::NEG_INFINITY, f64::max));
    if !z_lo.is_finite() {
        return grid;
    }
    // One row above the highest ground for the marks, at least one row of ground everywhere.
    let span = (z_hi - z_lo).max(0.1 * (rows as f64 - 2.0).max(1.0));
    let dz = span / (rows as f64 - 2.0).max(1.0);
    let ground = Style::new().fg(Color::Yellow).add_modifier(Modifier::DIM);
    let mut top = vec![None; cols];
    for (c, h) in heights.iter().enumerate() {
        let Some(h) = h else { continue };
        // Row 0 is the top; the ground surface is in row `rows − 1 − (h − z_lo) / dz − 1`.
        let above = ((h - z_lo) / dz).round() as usize;
        let surface = rows.saturating_sub(2 + above.min(rows - 2)) + 1;
        for row in grid.iter_mut().skip(surface) {
            row[c] = Cell { symbol: '█', style: ground };
        }
        top[c] = Some(surface);
    }
    for (x, foot, n) in marks {
        let c = column(x);
        if !(c >= 0.0 && c < cols as f64) {
            continue;
        }
        let c = c as usize;
        let Some(surface) = top[c] else { continue };
        let symbol = match (n, foot) {
            (Some(n), _) => char::from_digit(n as u32 % 10, 10).unwrap_or('#'),
            (None, Foot::Left) => 'L',
            (None, Foot::Right) => 'R',
        };
        grid[surface.saturating_sub(1)][c] =
            Cell { symbol, style: Style::new().fg(foot_colour(foot)).add_modifier(Modifier::BOLD) };
    }
    grid
}

fn footstep_panel(app: &App, area: Rect, buf: &mut Buffer) {
    let Some(f) = footing_of(app) else { return };
    let block = section(format!("Footsteps · n = {}", f.params().window_steps));
    let inner = block.inner(area);
    block.render(area, buf);
    if let Some(reason) = f.stopped() {
        let line = Line::styled(format!("stopped: {reason}"), Style::new().fg(Color::Red));
        Paragraph::new(line).wrap(Wrap { trim: true }).render(inner, buf);
        return;
    }
    let (Some(step), Some(last)) = (f.played(), f.footholds().last()) else {
        Paragraph::new(Line::styled("standing: no step planned", DIM)).render(inner, buf);
        return;
    };
    let rows = usize::from(inner.height.saturating_sub(1));
    let grid = footstep_grid(step, last.foot, usize::from(inner.width), rows);
    let mut lines: Vec<Line> = grid
        .into_iter()
        .map(|row| Line::from(row.into_iter().map(|c| Span::styled(c.symbol.to_string(), c.style)).collect::<Vec<_>>()))
        .collect();
    let lengths: Vec<String> = step.window_m.iter().map(|s| format!("{s:.2}")).collect();
    lines.push(Line::raw(format!("steps {} m · {}", lengths.join(" "), step.swing.kind.name())));
    Paragraph::new(lines).render(inner, buf);
}

fn mode_text(m: Mode) -> String {
    match m {
        Mode::Seek => "seek".into(),
        Mode::Follow(f) if f.side == Side::Left => "follow, wall left".into(),
        Mode::Follow(_) => "follow, wall right".into(),
    }
}

fn agent_panel(app: &App, area: Rect, buf: &mut Buffer) {
    let agent = &app.sim.agents[app.selected];
    let m = agent.metrics;
    let status = match agent.outcome {
        Some(Outcome::Reached) => " · reached",
        Some(Outcome::TimedOut) => " · timed out",
        Some(Outcome::Refused) => " · no way round",
        None => "",
    };
    let title =
        format!("Agent {}/{} · {}{status}", app.selected + 1, app.sim.agents.len(), mode_text(agent.controller.mode()));
    let block = section(title);
    let inner = block.inner(area);
    block.render(area, buf);
    let cmd = |label: &str, c: crate::sim::Command| {
        format!("{label} {:+5.0}°/s {:4.2} m/s", c.turn_rate.to_degrees(), c.speed)
    };
    let mut lines = vec![
        Line::raw(format!("t {:.1} s  path {:.1} m  v {:.2} m/s", m.time_s, m.path_length_m, agent.body.speed())),
        Line::raw(format!(
            "clearance {:.2} m  collisions {}  stalls {}",
            m.min_clearance_m, m.collisions, m.stalled_steps
        )),
    ];
    if let Some(b) = agent.body.animated() {
        // The RL controller's state (seed 000 §3.2.2): interval playing, errors, best value.
        let a = b.animation();
        let iv = b.player().interval();
        let e = b.errors();
        let best = a.policy.values(iv, e).iter().cloned().fold(f32::NEG_INFINITY, f32::max);
        lines.push(Line::raw(format!(
            "anim {} #{iv}  e_v {:+.2}  e_θ {:+.0}°  Q {best:.2}",
            a.db.clips[a.db.intervals[iv].clip].name,
            e.speed,
            e.direction.to_degrees()
        )));
        // The upper body (seed 002 §5): the offsets the planner adds now, and its refusals.
        if let Some(u) = b.upper_body() {
            let c = b.upper_offsets();
            let mut spans = vec![Span::raw(format!(
                "upper bend {:+.0}° twist {:+.0}°  refused {}",
                c.waist[0].to_degrees(),
                c.waist[1].to_degrees(),
                u.figures().refused_steps
            ))];
            if let Some(r) = u.refusal() {
                spans.push(Span::styled(format!(" · {r}"), Style::new().fg(Color::Red)));
            }
            lines.push(Line::from(spans));
        }
    }
    if app.manual {
        let you = Span::styled(cmd("you", app.manual_command), Style::new().fg(Color::Magenta));
        lines.push(Line::from(vec![you, Span::styled(format!("  {}", cmd("auto", app.autopilot_command)), DIM)]));
    } else {
        lines.push(Line::raw(cmd("command", agent.command)));
    }
    Paragraph::new(lines).render(inner, buf);
}

/// A one-cell bar for a degree in [0, 1].
fn level_glyph(d: f64) -> char {
    const LEVELS: [char; 9] = [' ', '▁', '▂', '▃', '▄', '▅', '▆', '▇', '█'];
    if !(d > 0.0) { ' ' } else { LEVELS[((d.min(1.0) * 8.0).round() as usize).max(1)] }
}

/// A horizontal bar of `width` cells for a degree in [0, 1], in eighths.
fn bar(d: f64, width: usize) -> String {
    const PARTS: [char; 8] = [' ', '▏', '▎', '▍', '▌', '▋', '▊', '▉'];
    let d = if d.is_finite() { d.clamp(0.0, 1.0) } else { 0.0 };
    let eighths = (d * (width * 8) as f64).round() as usize;
    let mut s = "█".repeat(eighths / 8);
    if !eighths.is_multiple_of(8) && s.chars().count() < width {
        s.push(PARTS[eighths % 8]);
    }
    while s.chars().count() < width {
        s.push(' ');
    }
    s
}

fn number(v: f64) -> String {
    if !v.is_finite() {
        "   nan".into()
    } else if v.abs() >= 100.0 {
        format!("{v:+6.0}")
    } else {
        format!("{v:+6.2}")
    }
}

fn inputs_panel(app: &App, area: Rect, buf: &mut Buffer) {
    let agent = &app.sim.agents[app.selected];
    let net = agent.controller.network();
    let block = section("Fuzzy inputs".into());
    let inner = block.inner(area);
    block.render(area, buf);
    let mut lines = Vec::new();
    for name in net.input_names() {
        let found = net.stages().iter().find_map(|s| s.engine().input_index(name).map(|i| (s, i)));
        let Some((stage, i)) = found else { continue };
        let var = &stage.engine().inputs[i];
        let degrees = stage.input_memberships(i);
        let best = degrees.iter().copied().fold(0.0, f64::max);
        let mut spans = vec![Span::raw(format!("{name:<12.12} ")), Span::raw(number(stage.inputs()[i]))];
        for (t, &d) in var.terms.iter().zip(&degrees) {
            if d > 0.0 {
                let style = if d == best { Style::new().fg(ACCENT).add_modifier(Modifier::BOLD) } else { Style::new() };
                spans.push(Span::styled(format!(" {}", t.name), style));
                spans.push(Span::styled(level_glyph(d).to_string(), Style::new().fg(ACCENT)));
            }
        }
        lines.push(Line::from(spans));
    }
    Paragraph::new(lines).render(inner, buf);
}

fn outputs_panel(app: &App, area: Rect, buf: &mut Buffer) {
    let agent = &app.sim.agents[app.selected];
    let net = agent.controller.network();
    let block = section("Fuzzy outputs".into());
    let inner = block.inner(area);
    block.render(area, buf);
    let track_w = usize::from(inner.width).saturating_sub(21).max(3);
    let mut lines = Vec::new();
    for stage in net.stages() {
        for (o, var) in stage.engine().outputs.iter().enumerate() {
            let v = stage.outputs()[o];
            let span = var.maximum - var.minimum;
            let pos = |x: f64| (((x - var.minimum) / span).clamp(0.0, 1.0) * (track_w - 1) as f64).round() as usize;
            let mut track: Vec<char> = vec!['─'; track_w];
            if var.minimum < 0.0 && var.maximum > 0.0 {
                track[pos(0.0)] = '┼';
            }
            let marker = v.is_finite() && span > 0.0;
            if marker {
                track[pos(v)] = '●';
            }
            let (before, rest): (String, String) = {
                let k = if marker { pos(v) } else { track_w };
                (track[..k].iter().collect(), track[k..].iter().collect())
            };
            let mut rest = rest.chars();
            let dot = rest.next().map(String::from).unwrap_or_default();
            lines.push(Line::from(vec![
                Span::raw(format!("{:<12.12} ", var.name)),
                Span::raw(number(v)),
                Span::raw(" "),
                Span::styled(before, DIM),
                Span::styled(dot, Style::new().fg(Color::Yellow).add_modifier(Modifier::BOLD)),
                Span::styled(rest.collect::<String>(), DIM),
            ]));
        }
    }
    Paragraph::new(lines).render(inner, buf);
}

fn rules_panel(app: &App, area: Rect, buf: &mut Buffer) {
    let agent = &app.sim.agents[app.selected];
    let net = agent.controller.network();
    let mut fired = Vec::new();
    let mut total = 0;
    for stage in net.stages() {
        let e = stage.engine();
        for ra in stage.rule_activations() {
            total += 1;
            if ra.fired {
                fired.push((ra.degree, e, ra.block, ra.rule));
            }
        }
    }
    fired.sort_by(|a, b| b.0.total_cmp(&a.0));
    let block = section(format!("Rules fired {}/{total}", fired.len()));
    let inner = block.inner(area);
    block.render(area, buf);
    let lines: Vec<Line> = fired
        .iter()
        .take(usize::from(inner.height))
        .map(|&(d, e, b, r)| {
            let text = e.rule_blocks[b].rules[r].to_text(&e.inputs, &e.outputs);
            let text = text.strip_prefix("if ").unwrap_or(&text).to_string();
            Line::from(vec![
                Span::styled(bar(d, 5), Style::new().fg(Color::Green)),
                Span::raw(format!(" {d:.2} ")),
                Span::raw(text),
            ])
        })
        .collect();
    Paragraph::new(lines).render(inner, buf);
}

fn footer(app: &App, area: Rect, buf: &mut Buffer) {
    let keys: &[(&str, &str)] = if app.manual {
        &[
            ("↑↓/ws", "speed"),
            ("←→/ad", "turn"),
            ("drag", "drive"),
            ("m", "autopilot"),
            ("?", "help"),
            ("q", "quit"),
            ("␣", "pause"),
        ]
    } else {
        &[
            ("␣", "pause"),
            (".", "step"),
            ("+/-", "speed"),
            ("m", "manual"),
            ("?", "help"),
            ("q", "quit"),
            ("r", "reset"),
            ("n", "new world"),
            ("Tab", "agent"),
            ("z/x", "zoom"),
        ]
    };
    let mut spans = Vec::new();
    for (k, what) in keys {
        spans.push(Span::styled(format!(" {k}"), Style::new().fg(ACCENT).add_modifier(Modifier::BOLD)));
        spans.push(Span::raw(format!(" {what} ")));
    }
    Paragraph::new(Line::from(spans)).style(Style::new().add_modifier(Modifier::REVERSED)).render(area, buf);
}

/// The controls, as shown by the help overlay.
pub const HELP: &[(&str, &str)] = &[
    ("Space", "pause / resume"),
    (".", "one step (pauses)"),
    ("+  -", "simulation speed"),
    ("r", "reset the run"),
    ("n", "new random world (next seed)"),
    ("Tab", "next agent"),
    ("m", "manual / autopilot"),
    ("↑↓ w s", "manual: forward speed"),
    ("←→ a d", "manual: turn"),
    ("drag", "manual: up = speed, side = turn"),
    ("click", "set the goal"),
    ("arrows", "pan (Shift+arrows in manual)"),
    ("z x wheel", "zoom in / out"),
    ("0  f", "fit view / follow agent"),
    ("?  Esc", "help on / off"),
    ("q  Ctrl-C", "quit"),
];

fn help(area: Rect, buf: &mut Buffer) {
    let w = 48.min(area.width);
    let h = (HELP.len() as u16 + 4).min(area.height);
    let r = Rect { x: area.x + (area.width - w) / 2, y: area.y + (area.height - h) / 2, width: w, height: h };
    Clear.render(r, buf);
    let mut lines: Vec<Line> = HELP
        .iter()
        .map(|(k, what)| {
            Line::from(vec![
                Span::styled(format!(" {k:<10}"), Style::new().fg(ACCENT).add_modifier(Modifier::BOLD)),
                Span::raw(*what),
            ])
        })
        .collect();
    lines.push(Line::styled(" Saving the map or rule file reloads it.", DIM));
    let block = Block::bordered()
        .title(Span::styled(" Help ", Style::new().add_modifier(Modifier::BOLD)))
        .title_alignment(Alignment::Center);
    Paragraph::new(lines).block(block).render(r, buf);
}

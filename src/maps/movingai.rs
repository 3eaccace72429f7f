//! MovingAI grid benchmarks (Sturtevant 2012): `.map` grids and `.scen` problem lists, turned
//! into a [`Scenario`].
//!
//! A `.map` file is `type octile`, `height H`, `width W`, `map`, then `H` rows of `W`
//! characters; `.`, `G` and `S` are passable, every other character is blocked. A `.scen` file
//! starts with `version 1` and has one problem per line, nine tab- or space-separated fields:
//! `bucket map width height start_x start_y goal_x goal_y optimal_length`.
//!
//! World frame: one cell is 1 m; cell `(x, y)`, with `(0, 0)` the top-left cell, occupies
//! `[x, x+1] × [H−1−y, H−y]` metres (world y points up), so starts and goals are cell centres.
//! Blocked cells are merged greedily into maximal axis-aligned rectangles (a run of blocked
//! cells along a row, grown downwards while the whole run below is blocked), each one box
//! obstacle; four 1 m thick walls just outside the map keep agents inside.

use std::path::Path;

use glam::DVec2;

use super::{TaskEnd, first_blocked_task};
use crate::diagnostic::SourceError;
use crate::scenario::{DEFAULT_AGENT_RADIUS, Scenario};
use crate::world::obstacle::DEFAULT_Z;
use crate::world::{Obstacle, ObstacleShape, Pose, Task, World};

/// Thickness of the boundary walls added around a map, metres.
pub const WALL_THICKNESS_M: f64 = 1.0;

/// Shortest time limit given to a MovingAI task, seconds.
pub const MIN_TIME_LIMIT_S: f64 = 60.0;

/// Time allowed per metre of the scenario's optimal length, seconds per metre.
pub const TIME_PER_METRE_S: f64 = 20.0;

/// Largest map accepted, cells (512 × 512, the largest maps of the MovingAI maze and room
/// sets): every blocked run becomes an obstacle, and the reference optimum's visibility graph
/// grows with their corners.
pub const MAX_CELLS: usize = 512 * 512;

/// A grid of passable and blocked cells, row 0 at the top.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Grid {
    width: usize,
    height: usize,
    blocked: Vec<bool>,
}

/// An axis-aligned rectangle of grid cells: columns `x0..x1`, rows `y0..y1` (exclusive ends).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CellRect {
    /// First column.
    pub x0: usize,
    /// First row (counted from the top).
    pub y0: usize,
    /// One past the last column.
    pub x1: usize,
    /// One past the last row.
    pub y1: usize,
}

impl Grid {
    /// A grid from row-major `blocked` flags (row 0 at the top); `None` when the length is not
    /// `width · height` or a side is zero.
    pub fn new(width: usize, height: usize, blocked: Vec<bool>) -> Option<Grid> {
        (width > 0 && height > 0 && width.checked_mul(height) == Some(blocked.len())).then_some(Grid {
            width,
            height,
            blocked,
        })
    }

    /// Number of columns (metres along x).
    pub fn width(&self) -> usize {
        self.width
    }

    /// Number of rows (metres along y).
    pub fn height(&self) -> usize {
        self.height
    }

    /// Whether cell `(x, y)` is blocked; cells outside the grid count as blocked.
    pub fn is_blocked(&self, x: usize, y: usize) -> bool {
        x >= self.width || y >= self.height || self.blocked[y * self.width + x]
    }

    /// Number of blocked cells.
    pub fn blocked_count(&self) -> usize {
        self.blocked.iter().filter(|&&b| b).count()
    }

    /// Centre of cell `(x, y)` in world metres (y up).
    pub fn cell_center(&self, x: usize, y: usize) -> DVec2 {
        DVec2::new(x as f64 + 0.5, self.height as f64 - y as f64 - 0.5)
    }

    /// The blocked cells as disjoint rectangles that cover them exactly: scanning rows from the
    /// top and columns from the left, each uncovered blocked cell starts a run extended to the
    /// right, then grown downwards while every cell under the run is blocked and uncovered.
    pub fn merged_rects(&self) -> Vec<CellRect> {
        let (w, h) = (self.width, self.height);
        let mut covered = vec![false; self.blocked.len()];
        let free = |covered: &[bool], x: usize, y: usize| self.blocked[y * w + x] && !covered[y * w + x];
        let mut rects = Vec::new();
        for y0 in 0..h {
            for x0 in 0..w {
                if !free(&covered, x0, y0) {
                    continue;
                }
                let mut x1 = x0 + 1;
                while x1 < w && free(&covered, x1, y0) {
                    x1 += 1;
                }
                let mut y1 = y0 + 1;
                while y1 < h && (x0..x1).all(|x| free(&covered, x, y1)) {
                    y1 += 1;
                }
                for y in y0..y1 {
                    covered[y * w + x0..y * w + x1].fill(true);
                }
                rects.push(CellRect { x0, y0, x1, y1 });
            }
        }
        rects
    }
}

/// One problem of a `.scen` file.
#[derive(Debug, Clone, PartialEq)]
pub struct ScenLine {
    /// 1-based line in the `.scen` file (0 when built by hand).
    pub line: usize,
    /// 1-based column of each of the nine fields (0 when unknown).
    pub cols: [usize; 9],
    /// Difficulty bucket.
    pub bucket: u32,
    /// Map file named by the line.
    pub map: String,
    /// Map width the line was made for, cells.
    pub map_width: usize,
    /// Map height the line was made for, cells.
    pub map_height: usize,
    /// Start cell `(x, y)`, row 0 at the top.
    pub start: (usize, usize),
    /// Goal cell `(x, y)`, row 0 at the top.
    pub goal: (usize, usize),
    /// 8-connected grid path length (diagonal √2, no corner cutting), metres.
    pub optimal_length: f64,
}

/// Reads a `.map` file; `file` names it in errors.
pub fn parse_map(text: &str, file: &str) -> Result<Grid, SourceError> {
    let err = |line: usize, col: usize, msg: String| SourceError::new(file, line, col, msg);
    let mut lines = text.lines().enumerate().map(|(i, l)| (i + 1, l));
    let mut height: Option<usize> = None;
    let mut width: Option<usize> = None;
    let mut seen_type = false;
    let mut last_line = 0;
    loop {
        let Some((n, raw)) = lines.next() else {
            return Err(err(last_line + 1, 1, "unexpected end of file: expected a `map` line before the rows".into()));
        };
        last_line = n;
        let fields = split_fields(raw);
        let Some(&(kcol, key)) = fields.first() else {
            continue;
        };
        let value = |expect: &str| -> Result<(usize, &str), SourceError> {
            match fields.as_slice() {
                [_, (c, v)] => Ok((*c, *v)),
                [_] => Err(err(n, raw.chars().count() + 1, format!("`{key}` needs a value ({expect})"))),
                [_, _, (c, v), ..] => Err(err(n, *c, format!("unexpected `{v}` after `{key}` ({expect})"))),
                [] => Err(err(n, kcol, format!("`{key}` needs a value ({expect})"))),
            }
        };
        match key {
            "type" => {
                let (c, v) = value("type octile")?;
                if v != "octile" {
                    return Err(err(n, c, format!("unsupported map type `{v}` (expected `octile`)")));
                }
                seen_type = true;
            }
            "height" | "width" => {
                let (c, v) = value("a positive whole number of cells")?;
                let size = match v.parse::<usize>() {
                    Ok(s) if s > 0 => s,
                    _ => return Err(err(n, c, format!("{key} must be a positive whole number, found `{v}`"))),
                };
                let slot = if key == "height" { &mut height } else { &mut width };
                if slot.replace(size).is_some() {
                    return Err(err(n, kcol, format!("`{key}` is given twice")));
                }
            }
            "map" => {
                if let Some(&(c, v)) = fields.get(1) {
                    return Err(err(n, c, format!("unexpected `{v}` after `map`")));
                }
                break;
            }
            other => {
                return Err(err(
                    n,
                    kcol,
                    format!("unknown header item `{other}` (expected type, height, width or map)"),
                ));
            }
        }
    }
    let map_line = last_line;
    if !seen_type {
        return Err(err(map_line, 1, "missing `type octile` line before `map`".into()));
    }
    let (Some(w), Some(h)) = (width, height) else {
        let which = if width.is_none() { "width" } else { "height" };
        return Err(err(map_line, 1, format!("missing `{which}` line before `map`")));
    };
    if w.checked_mul(h).is_none_or(|cells| cells > MAX_CELLS) {
        return Err(err(
            map_line,
            1,
            format!("a {w} × {h} map is larger than the {MAX_CELLS} cells strider reads (512 × 512)"),
        ));
    }
    if w * h > text.len() {
        return Err(err(map_line, 1, format!("the file is too short for a {w} × {h} map")));
    }
    let mut blocked = Vec::with_capacity(w * h);
    let mut rows = 0;
    for (n, raw) in lines {
        last_line = n;
        if rows == h {
            if raw.trim().is_empty() {
                continue;
            }
            return Err(err(n, 1, format!("unexpected text after the {h} map rows")));
        }
        let mut count = 0;
        for c in raw.chars() {
            count += 1;
            if count > w {
                return Err(err(n, w + 1, format!("map row {} is longer than the width {w}", rows + 1)));
            }
            blocked.push(!matches!(c, '.' | 'G' | 'S'));
        }
        if count < w {
            return Err(err(n, count + 1, format!("map row {} has {count} cells, expected {w}", rows + 1)));
        }
        rows += 1;
    }
    if rows < h {
        return Err(err(last_line + 1, 1, format!("the map has {rows} rows, expected {h}")));
    }
    Grid::new(w, h, blocked).ok_or_else(|| err(map_line, 1, "inconsistent map size".into()))
}

/// Splits a line into fields with their 1-based columns: on tabs when the line has one
/// (fields trimmed of spaces), otherwise on whitespace.
fn split_fields<'a>(line: &'a str) -> Vec<(usize, &'a str)> {
    let mut out = Vec::new();
    let tabbed = line.contains('\t');
    let is_sep = |c: char| if tabbed { c == '\t' } else { c.is_whitespace() };
    let mut start: Option<(usize, usize)> = None;
    let mut col = 0;
    let push = |out: &mut Vec<(usize, &'a str)>, b: usize, e: usize, c: usize| {
        let field = &line[b..e];
        let lead = field.len() - field.trim_start().len();
        let lead_chars = field[..lead].chars().count();
        out.push((c + lead_chars, field.trim()));
    };
    for (byte, ch) in line.char_indices() {
        col += 1;
        if is_sep(ch) {
            if let Some((b, c)) = start.take() {
                push(&mut out, b, byte, c);
            } else if tabbed {
                out.push((col, ""));
            }
        } else if start.is_none() {
            start = Some((byte, col));
        }
    }
    if let Some((b, c)) = start {
        push(&mut out, b, line.len(), c);
    }
    if tabbed {
        while out.last().is_some_and(|f| f.1.is_empty()) {
            out.pop();
        }
    }
    out
}

/// Reads a `.scen` file; `file` names it in errors. The first line must be `version 1` (or
/// `version 1.0`); blank lines are skipped.
pub fn parse_scen(text: &str, file: &str) -> Result<Vec<ScenLine>, SourceError> {
    let err = |line: usize, col: usize, msg: String| SourceError::new(file, line, col, msg);
    let mut lines = text.lines().enumerate().map(|(i, l)| (i + 1, l)).filter(|(_, l)| !l.trim().is_empty());
    let Some((n, first)) = lines.next() else {
        return Err(err(1, 1, "empty scenario file: expected `version 1`".into()));
    };
    match split_fields(first).as_slice() {
        [(_, "version"), (c, v)] => {
            if v.parse::<f64>().ok() != Some(1.0) {
                return Err(err(n, *c, format!("unsupported scenario version `{v}` (expected 1)")));
            }
        }
        [(c, _), ..] => return Err(err(n, *c, "the first line must be `version 1`".into())),
        [] => return Err(err(n, 1, "the first line must be `version 1`".into())),
    }
    let mut out = Vec::new();
    for (n, raw) in lines {
        let fields = split_fields(raw);
        if fields.len() != 9 {
            let col = fields.get(9).map_or(raw.chars().count() + 1, |f| f.0);
            return Err(err(
                n,
                col,
                format!(
                    "expected 9 fields (bucket map width height start_x start_y goal_x goal_y optimal_length), found {}",
                    fields.len()
                ),
            ));
        }
        let whole = |i: usize, what: &str| -> Result<usize, SourceError> {
            let (c, v) = fields[i];
            v.parse::<usize>()
                .map_err(|_| err(n, c, format!("{what} must be a non-negative whole number, found `{v}`")))
        };
        let bucket = whole(0, "bucket")?;
        let bucket = u32::try_from(bucket).map_err(|_| err(n, fields[0].0, format!("bucket {bucket} is too large")))?;
        let (oc, ov) = fields[8];
        let optimal_length = match ov.parse::<f64>() {
            Ok(v) if v.is_finite() && v >= 0.0 => v,
            _ => return Err(err(n, oc, format!("optimal length must be a finite number ≥ 0, found `{ov}`"))),
        };
        let mut cols = [0; 9];
        for (slot, f) in cols.iter_mut().zip(&fields) {
            *slot = f.0;
        }
        out.push(ScenLine {
            line: n,
            cols,
            bucket,
            map: fields[1].1.to_string(),
            map_width: whole(2, "map width")?,
            map_height: whole(3, "map height")?,
            start: (whole(4, "start_x")?, whole(5, "start_y")?),
            goal: (whole(6, "goal_x")?, whole(7, "goal_y")?),
            optimal_length,
        });
    }
    Ok(out)
}

/// Checks scenario lines against their grid: the map size they name, and start and goal cells
/// inside the grid and passable. Errors point into the `.scen` file `file`.
pub fn check_scen(grid: &Grid, lines: &[ScenLine], file: &str) -> Result<(), SourceError> {
    for s in lines {
        let err = |field: usize, msg: String| SourceError::new(file, s.line, s.cols[field], msg);
        if s.map_width != grid.width {
            return Err(err(2, format!("map width {} does not match the map's width {}", s.map_width, grid.width)));
        }
        if s.map_height != grid.height {
            return Err(err(3, format!("map height {} does not match the map's height {}", s.map_height, grid.height)));
        }
        for (what, (x, y), field) in [("start", s.start, 4), ("goal", s.goal, 6)] {
            if x >= grid.width || y >= grid.height {
                return Err(err(
                    field,
                    format!("{what} cell ({x}, {y}) is outside the {} × {} map", grid.width, grid.height),
                ));
            }
            if grid.is_blocked(x, y) {
                return Err(err(field, format!("{what} cell ({x}, {y}) is blocked")));
            }
        }
    }
    Ok(())
}

/// Builds the scenario for a grid and its problems: merged box obstacles (see
/// [`Grid::merged_rects`]), four boundary walls [`WALL_THICKNESS_M`] thick just outside the map,
/// one task per line from cell centre to cell centre (start facing the goal, default goal
/// radius, time limit `max(MIN_TIME_LIMIT_S, TIME_PER_METRE_S · optimal_length)` seconds), and
/// the default agent radius of 0.3 m. Lines are taken as given; run [`check_scen`] first.
pub fn scenario_from(grid: &Grid, scen_lines: &[ScenLine], name: &str) -> Scenario {
    let mut scenario = Scenario::new(name);
    scenario.agent_radius = DEFAULT_AGENT_RADIUS;
    let h = grid.height as f64;
    let w = grid.width as f64;
    let mut push_box = |x0: f64, y0: f64, x1: f64, y1: f64| {
        let shape = ObstacleShape::Box {
            center: DVec2::new((x0 + x1) * 0.5, (y0 + y1) * 0.5),
            width: x1 - x0,
            height: y1 - y0,
            yaw: 0.0,
        };
        if let Ok(o) = Obstacle::build(shape, DEFAULT_Z.0, DEFAULT_Z.1) {
            scenario.obstacles.push(o);
        }
    };
    for r in grid.merged_rects() {
        push_box(r.x0 as f64, h - r.y1 as f64, r.x1 as f64, h - r.y0 as f64);
    }
    let t = WALL_THICKNESS_M;
    push_box(-t, -t, w + t, 0.0);
    push_box(-t, h, w + t, h + t);
    push_box(-t, 0.0, 0.0, h);
    push_box(w, 0.0, w + t, h);
    for s in scen_lines {
        let start = grid.cell_center(s.start.0, s.start.1);
        let goal = grid.cell_center(s.goal.0, s.goal.1);
        let d = goal - start;
        let yaw = if d == DVec2::ZERO { 0.0 } else { d.y.atan2(d.x) };
        let mut task = Task::new(Pose { position: start, yaw }, goal);
        task.time_limit_s = (TIME_PER_METRE_S * s.optimal_length).max(MIN_TIME_LIMIT_S);
        scenario.tasks.push(task);
    }
    scenario
}

/// Reads a `.map` and its `.scen`, checks them against each other and builds the validated
/// scenario (named after the map file's stem): starts and goals are checked against the
/// obstacles through the world's spatial index, then [`Scenario::validate`] checks the rest.
/// Errors point into whichever file is wrong.
pub fn load(map_text: &str, map_file: &str, scen_text: &str, scen_file: &str) -> Result<Scenario, SourceError> {
    let grid = parse_map(map_text, map_file)?;
    let lines = parse_scen(scen_text, scen_file)?;
    if lines.is_empty() {
        return Err(SourceError::new(scen_file, 0, 0, "no problem lines after `version 1`"));
    }
    check_scen(&grid, &lines, scen_file)?;
    let map_name = Path::new(map_file).file_name().and_then(|s| s.to_str()).unwrap_or(map_file);
    for s in &lines {
        // `.scen` files name their map with or without a directory.
        let named = s.map.rsplit(['/', '\\']).next().unwrap_or(&s.map);
        if named != map_name {
            return Err(SourceError::new(
                scen_file,
                s.line,
                s.cols[1],
                format!("this problem is for map `{}`, not `{map_name}`", s.map),
            ));
        }
    }
    let name = Path::new(map_file).file_stem().and_then(|s| s.to_str()).unwrap_or(map_file);
    let mut scenario = scenario_from(&grid, &lines, name);
    let world = World::new(std::mem::take(&mut scenario.obstacles));
    if let Some((i, end, _)) = first_blocked_task(&scenario, &world) {
        let s = &lines[i];
        let (what, field) = if end == TaskEnd::Start { ("start", 4) } else { ("goal", 6) };
        return Err(SourceError::new(
            scen_file,
            s.line,
            s.cols[field],
            format!("the {what} is closer than the agent radius {} m to a blocked cell", scenario.agent_radius),
        ));
    }
    // The obstacle test of `Scenario::validate` was just done through the spatial index; the
    // remaining checks run on the tasks alone, so a 512 × 512 map does not cost
    // tasks × boxes distance queries.
    scenario.validate().map_err(|m| SourceError::new(scen_file, 0, 0, m))?;
    scenario.obstacles = world.obstacles().to_vec();
    Ok(scenario)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fields_with_columns() {
        assert_eq!(split_fields("a\tb c\t 7"), vec![(1, "a"), (3, "b c"), (8, "7")]);
        assert_eq!(split_fields("  x  yz "), vec![(3, "x"), (6, "yz")]);
        assert_eq!(split_fields("a\t\tb"), vec![(1, "a"), (3, ""), (4, "b")]);
    }

    #[test]
    fn rects_cover_blocked_cells_exactly() {
        let rows = ["@@.@", "@@.@", "..@@"];
        let blocked: Vec<bool> = rows.iter().flat_map(|r| r.chars().map(|c| c == '@')).collect();
        let g = Grid::new(4, 3, blocked).unwrap();
        let rects = g.merged_rects();
        assert_eq!(
            rects,
            vec![
                CellRect { x0: 0, y0: 0, x1: 2, y1: 2 },
                CellRect { x0: 3, y0: 0, x1: 4, y1: 3 },
                CellRect { x0: 2, y0: 2, x1: 3, y1: 3 }
            ]
        );
    }
}

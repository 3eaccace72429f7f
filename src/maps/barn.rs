//! The BARN challenge's own files (the Benchmark Autonomous Robot Navigation challenge, MIT
//! licence): a Gazebo world `world_N.world` (SDF) whose `unit_cylinder_*` models are the
//! obstacles (at most [`MAX_OBSTACLES`], counted before any is built), and its reference path
//! `path_N.npy`, a NumPy array of grid cells (row, column) of 0.15 m on the challenge's map of
//! [`GRID_CELLS`] × [`GRID_CELLS`] (a cell off it would stretch the reference to nonsense). The challenge's task is fixed: start at (−2.25, 3) facing +y, goal 10 m ahead
//! within 1 m, 100 s; its reference length runs from the start through the path's cells (each
//! at `(0.15·row − 4.575, 0.15·column + 5.075)`) to the goal, as the challenge measures it.
//!
//! Only reading happens here (text and bytes in, [`Scenario`] out): finding the path file
//! beside the world is the loader's ([`crate::load`]). Errors are [`SourceError`]s naming the
//! file, and for the world the line and column of the offending element.

use glam::DVec2;

use crate::diagnostic::SourceError;
use crate::scenario::{MAX_OBSTACLES, Reference, Scenario};
use crate::world::{Obstacle, ObstacleShape, Pose, Task, World};

/// Where the challenge starts: (−2.25, 3), facing +y.
pub const START: Pose = Pose { position: DVec2::new(-2.25, 3.0), yaw: std::f64::consts::FRAC_PI_2 };
/// Where it ends: 10 m ahead of the start.
pub const GOAL: DVec2 = DVec2::new(-2.25, 13.0);
/// The goal's radius, metres.
pub const GOAL_RADIUS_M: f64 = 1.0;
/// The challenge's time limit, seconds.
pub const TIME_LIMIT_S: f64 = 100.0;
/// Side of the path's grid cells, metres (the cylinders' diameter).
pub const CELL_M: f64 = 0.15;
/// Rows and columns of the challenge's map: its path's cells lie on a 30 × 30 grid (4.5 m square).
pub const GRID_CELLS: i64 = 30;
/// Most cells a path may hold.
const MAX_PATH_CELLS: usize = 1_000_000;

/// The world point of the reference path's cell (`row`, `column`).
pub fn cell_point(row: i64, column: i64) -> DVec2 {
    let r = CELL_M / 2.0;
    DVec2::new(row as f64 * CELL_M - r - 30.0 * CELL_M, column as f64 * CELL_M + r + 5.0)
}

/// The reference path's cells from the bytes of a `path_N.npy` file: an integer (signed or
/// unsigned, 1 to 8 bytes) or float (4 or 8 bytes) array of shape (n, 2), each cell on the
/// challenge's map of [`GRID_CELLS`] × [`GRID_CELLS`].
pub fn parse_path(bytes: &[u8], file: &str) -> Result<Vec<(i64, i64)>, SourceError> {
    let err = |m: String| SourceError::new(file, 0, 0, m);
    let npy = npyz::NpyFile::new(bytes).map_err(|e| err(format!("not a NumPy array file: {e}")))?;
    let shape = npy.shape().to_vec();
    if shape.len() != 2 || shape[1] != 2 {
        return Err(err(format!("expected an array of (row, column) cells, shape (n, 2), not {shape:?}")));
    }
    if shape[0] as usize > MAX_PATH_CELLS {
        return Err(err(format!("{} cells: at most {MAX_PATH_CELLS}", shape[0])));
    }
    if npy.order() != npyz::Order::C {
        return Err(err("expected a C-ordered array (fortran_order False)".into()));
    }
    let dtype = npy.dtype();
    let kind = match &dtype {
        npyz::DType::Plain(t) => Some((t.type_char(), t.size_field())),
        _ => None,
    };
    use npyz::TypeChar::{Float, Int, Uint};
    match kind {
        Some((Int, 1)) => cells_of(npy, file, |v: i8| v as f64),
        Some((Int, 2)) => cells_of(npy, file, |v: i16| v as f64),
        Some((Int, 4)) => cells_of(npy, file, |v: i32| v as f64),
        Some((Int, 8)) => cells_of(npy, file, |v: i64| v as f64),
        Some((Uint, 1)) => cells_of(npy, file, |v: u8| v as f64),
        Some((Uint, 2)) => cells_of(npy, file, |v: u16| v as f64),
        Some((Uint, 4)) => cells_of(npy, file, |v: u32| v as f64),
        Some((Uint, 8)) => cells_of(npy, file, |v: u64| v as f64),
        Some((Float, 4)) => cells_of(npy, file, |v: f32| v as f64),
        Some((Float, 8)) => cells_of(npy, file, |v: f64| v),
        _ => Err(err(format!("the cells must be integers or floats, not `{}`", dtype.descr()))),
    }
}

/// The cells of a path file whose numbers are `T`, each a whole number on the challenge's map
/// (`value` gives a number's value; a whole number beyond 2^53 is still off the map).
fn cells_of<T>(npy: npyz::NpyFile<&[u8]>, file: &str, value: impl Fn(T) -> f64) -> Result<Vec<(i64, i64)>, SourceError>
where
    T: npyz::Deserialize + Copy + std::fmt::Display,
{
    let err = |m: String| SourceError::new(file, 0, 0, m);
    let numbers = npy.into_vec::<T>().map_err(|e| err(format!("cannot read the cells: {e}")))?;
    let mut indices = Vec::with_capacity(numbers.len());
    for (k, &n) in numbers.iter().enumerate() {
        let (cell, axis) = (k / 2 + 1, if k % 2 == 0 { "row" } else { "column" });
        let v = value(n);
        if !(v.is_finite() && v.fract() == 0.0) {
            return Err(err(format!("cell {cell}: its {axis} {n} is not a whole number")));
        }
        if !(0.0..GRID_CELLS as f64).contains(&v) {
            return Err(err(format!(
                "cell {cell}: its {axis} {n} is off the challenge's map of {GRID_CELLS} × {GRID_CELLS} cells (0 to {})",
                GRID_CELLS - 1
            )));
        }
        indices.push(v as i64);
    }
    Ok(indices.chunks_exact(2).map(|c| (c[0], c[1])).collect())
}

/// The length of the challenge's reference path through `cells`: from the start through each
/// cell's point to the goal, metres.
pub fn reference_length(cells: &[(i64, i64)]) -> f64 {
    let mut at = START.position;
    let mut length = 0.0;
    for p in cells.iter().map(|&(r, c)| cell_point(r, c)).chain([GOAL]) {
        length += at.distance(p);
        at = p;
    }
    length
}

/// A BARN world: the cylinders of a Gazebo SDF world (`name` the scenario's name, `file` in
/// errors) with the challenge's task, and the reference path's cells when known.
pub fn parse_world(text: &str, file: &str, name: &str, path: Option<&[(i64, i64)]>) -> Result<Scenario, SourceError> {
    let doc = roxmltree::Document::parse(text).map_err(|e| {
        // A document cut short is reported where it ends, not where roxmltree leaves it (1:1).
        let (line, col) = match e {
            roxmltree::Error::UnexpectedEndOfStream | roxmltree::Error::UnclosedRootNode => end_of(text),
            _ => (e.pos().row as usize, e.pos().col as usize),
        };
        SourceError::new(file, line, col, format!("not an SDF world: {e}"))
    })?;
    // Positions are found only for an error: each costs a walk from the start of the text.
    let at = |n: roxmltree::Node| {
        let p = doc.text_pos_at(n.range().start);
        (p.row as usize, p.col as usize)
    };
    let world = doc
        .root_element()
        .children()
        .find(|n| n.has_tag_name("world"))
        .ok_or_else(|| SourceError::new(file, 1, 1, "no <world> element under <sdf>"))?;
    // The world's own models (the <state> element repeats them with their current poses).
    let cylinders = || {
        world
            .children()
            .filter(|n| n.has_tag_name("model") && n.attribute("name").unwrap_or("").starts_with("unit_cylinder"))
    };
    // Counted before any is built, so an oversized world is refused at once.
    if let Some(extra) = cylinders().nth(MAX_OBSTACLES) {
        let (line, col) = at(extra);
        return Err(SourceError::new(file, line, col, format!("more than {MAX_OBSTACLES} cylinders")));
    }
    let mut obstacles = Vec::new();
    for model in cylinders() {
        let model_name = model.attribute("name").unwrap_or("");
        let located = |m: String| {
            let (line, col) = at(model);
            SourceError::new(file, line, col, format!("model `{model_name}`: {m}"))
        };
        let pose = model
            .children()
            .find(|n| n.has_tag_name("pose"))
            .and_then(|n| n.text())
            .ok_or_else(|| located("no <pose>".into()))?;
        let numbers: Vec<f64> = pose
            .split_whitespace()
            .map(|t| t.parse::<f64>().map_err(|_| located(format!("`{t}` in <pose> is not a number"))))
            .collect::<Result<_, _>>()?;
        if numbers.len() < 2 || numbers.iter().any(|v| !v.is_finite()) {
            return Err(located(format!("<pose> needs finite x and y, got `{}`", pose.trim())));
        }
        let radius = model
            .descendants()
            .find(|n| n.has_tag_name("collision"))
            .and_then(|c| c.descendants().find(|n| n.has_tag_name("radius")))
            .and_then(|n| n.text())
            .ok_or_else(|| located("no cylinder <radius> in its <collision>".into()))?;
        let radius: f64 =
            radius.trim().parse().map_err(|_| located(format!("`{}` in <radius> is not a number", radius.trim())))?;
        let center = DVec2::new(numbers[0], numbers[1]);
        let shape = ObstacleShape::Cylinder { center, radius };
        let o = Obstacle::build(shape, crate::world::obstacle::DEFAULT_Z.0, crate::world::obstacle::DEFAULT_Z.1)
            .map_err(|e| located(format!("invalid cylinder: {e}")))?;
        obstacles.push(o);
    }
    if obstacles.is_empty() {
        return Err(SourceError::new(file, 0, 0, "no `unit_cylinder` models: not a BARN world"));
    }
    let task = Task { goal_radius: GOAL_RADIUS_M, time_limit_s: TIME_LIMIT_S, ..Task::new(START, GOAL) };
    let mut scenario = Scenario::new(name);
    scenario.obstacles = obstacles;
    scenario.tasks = vec![task];
    scenario.reference = path.map(|cells| Reference { path_length_m: reference_length(cells) });
    let grid = World::new(scenario.obstacles.clone());
    if let Some((_, end, _)) = super::first_blocked_task(&scenario, &grid) {
        let what = match end {
            super::TaskEnd::Start => "start",
            super::TaskEnd::Goal => "goal",
        };
        return Err(SourceError::new(file, 0, 0, format!("the challenge's {what} is inside a cylinder")));
    }
    scenario.validate().map_err(|m| SourceError::new(file, 0, 0, m))?;
    Ok(scenario)
}

/// The line and column just past the end of `text` (columns count characters, as roxmltree's).
fn end_of(text: &str) -> (usize, usize) {
    let last = text.rfind('\n').map_or(text, |i| &text[i + 1..]);
    (text.matches('\n').count() + 1, last.chars().count() + 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A world of the challenge's shape with the given cylinders (x, y, radius), a <state>
    /// element repeating them.
    pub(crate) fn world(cylinders: &[(f64, f64, f64)]) -> String {
        let model = |i: usize, &(x, y, r): &(f64, f64, f64)| {
            format!(
                "<model name='unit_cylinder_{i}'><pose frame=''>{x} {y} 0 0 0 0</pose><link name='link'>\
                 <collision name='collision'><geometry><cylinder><radius>{r}</radius><length>1</length>\
                 </cylinder></geometry></collision></link></model>\n"
            )
        };
        let models: String = cylinders.iter().enumerate().map(|(i, c)| model(i, c)).collect();
        format!(
            "<sdf version='1.6'>\n<world name='default'>\n<model name='ground_plane'><static>1</static></model>\n\
             {models}<state world_name='default'>{models}</state>\n</world>\n</sdf>\n"
        )
    }

    /// The bytes of a NumPy file of int64 cells.
    pub(crate) fn npy(cells: &[(i64, i64)]) -> Vec<u8> {
        let numbers: Vec<Vec<u8>> = cells.iter().flat_map(|&(r, c)| [r, c]).map(|v| v.to_le_bytes().to_vec()).collect();
        npy_of("<i8", cells.len(), &numbers)
    }

    /// The bytes of a NumPy file of `rows` cells of type `descr`, each number's bytes given.
    fn npy_of(descr: &str, rows: usize, numbers: &[Vec<u8>]) -> Vec<u8> {
        let header = format!("{{'descr': '{descr}', 'fortran_order': False, 'shape': ({rows}, 2), }}");
        let pad = 64 - (10 + header.len() + 1) % 64;
        let mut out = b"\x93NUMPY\x01\x00".to_vec();
        let len = (header.len() + pad + 1) as u16;
        out.extend(len.to_le_bytes());
        out.extend(header.bytes());
        out.extend(std::iter::repeat_n(b' ', pad));
        out.push(b'\n');
        for n in numbers {
            out.extend(n);
        }
        out
    }

    #[test]
    fn a_world_and_its_path_give_the_challenge() {
        let text = world(&[(-0.075, 0.075, 0.075), (-4.425, 9.525, 0.075), (-1.0, 8.0, 0.075)]);
        let cells = [(15, 0), (15, 1), (16, 2)];
        let path = parse_path(&npy(&cells), "path_7.npy").unwrap();
        assert_eq!(path, cells);
        let s = parse_world(&text, "world_7.world", "world_7", Some(&path)).unwrap();
        assert_eq!(s.obstacles.len(), 3, "the <state> copies are not obstacles");
        assert_eq!(s.tasks.len(), 1);
        let t = s.tasks[0];
        assert_eq!((t.start, t.goal, t.goal_radius, t.time_limit_s), (START, GOAL, 1.0, 100.0));
        // Start → (−2.325, 5.075) → (−2.325, 5.225) → (−2.175, 5.375) → goal.
        let pts = [START.position, cell_point(15, 0), cell_point(15, 1), cell_point(16, 2), GOAL];
        let want: f64 = pts.windows(2).map(|w| w[0].distance(w[1])).sum();
        assert!((s.reference.unwrap().path_length_m - want).abs() < 1e-12);
        assert!((cell_point(15, 0) - DVec2::new(-2.325, 5.075)).length() < 1e-12);
    }

    #[test]
    fn paths_of_every_integer_and_float_type_read_alike() {
        let cells = [(15u8, 0u8), (15, 1), (29, 29)];
        // The bytes of one number of a type.
        type Bytes = fn(u8) -> Vec<u8>;
        let numbers = |f: Bytes| -> Vec<Vec<u8>> { cells.iter().flat_map(|&(r, c)| [f(r), f(c)]).collect() };
        let want: Vec<(i64, i64)> = cells.iter().map(|&(r, c)| (r.into(), c.into())).collect();
        let kinds: [(&str, Bytes); 8] = [
            ("<i1", |v| vec![v]),
            ("<u1", |v| vec![v]),
            ("<i2", |v| i16::from(v).to_le_bytes().to_vec()),
            ("<i4", |v| i32::from(v).to_le_bytes().to_vec()),
            (">i4", |v| i32::from(v).to_be_bytes().to_vec()),
            ("<u8", |v| u64::from(v).to_le_bytes().to_vec()),
            ("<f4", |v| f32::from(v).to_le_bytes().to_vec()),
            ("<f8", |v| f64::from(v).to_le_bytes().to_vec()),
        ];
        for (descr, f) in kinds {
            let got = parse_path(&npy_of(descr, cells.len(), &numbers(f)), "p.npy");
            assert_eq!(got.as_deref(), Ok(&want[..]), "{descr}");
        }
        let halves = numbers(|v| (f32::from(v) + 0.5).to_le_bytes().to_vec());
        let e = parse_path(&npy_of("<f4", cells.len(), &halves), "p.npy").unwrap_err();
        assert!(e.message.contains("cell 1: its row 15.5 is not a whole number"), "{e}");
        let e = parse_path(&npy_of("|b1", 1, &[vec![1], vec![0]]), "p.npy").unwrap_err();
        assert!(e.message.contains("integers or floats"), "{e}");
    }

    #[test]
    fn cells_off_the_challenge_map_are_refused() {
        for (cell, what) in [
            ((30, 0), "cell 2: its row 30 is off"),
            ((0, -1), "cell 2: its column -1 is off"),
            ((i64::MIN, 0), "cell 2: its row -9223372036854775808 is off"),
            ((0, i64::MAX), "cell 2: its column 9223372036854775807 is off"),
        ] {
            let e = parse_path(&npy(&[(15, 0), cell]), "p.npy").unwrap_err();
            assert!(e.message.contains(what), "{e}");
        }
        let far = u64::MAX.to_le_bytes().to_vec();
        let e = parse_path(&npy_of("<u8", 1, &[far, 0u64.to_le_bytes().to_vec()]), "p.npy").unwrap_err();
        assert!(e.message.contains("its row 18446744073709551615 is off"), "{e}");
    }

    #[test]
    fn bad_worlds_and_paths_are_located_errors() {
        // Cut short: located where the text ends, not at its start.
        let e = parse_world("<sdf><world>", "w.world", "w", None).unwrap_err();
        assert_eq!((e.line, e.col), (1, 13), "{e}");
        assert!(e.message.contains("not an SDF world"), "{e}");
        let whole = world(&[(0.0, 0.0, 0.075), (1.0, 1.0, 0.075)]);
        let cut = &whole[..whole.find("unit_cylinder_1").unwrap()];
        let e = parse_world(cut, "w.world", "w", None).unwrap_err();
        assert_eq!((e.line, e.col), (5, cut.lines().last().unwrap().chars().count() + 1), "{e}");
        let text = world(&[(0.0, 0.0, 0.075)]).replace("<radius>0.075</radius>", "<radius>wide</radius>");
        let e = parse_world(&text, "w.world", "w", None).unwrap_err();
        assert_eq!(e.line, 4, "{e}");
        assert!(e.message.contains("unit_cylinder_0") && e.message.contains("wide"), "{e}");
        let e = parse_world(&world(&[]), "w.world", "w", None).unwrap_err();
        assert!(e.message.contains("no `unit_cylinder`"), "{e}");
        let e = parse_world(&world(&[(-2.25, 3.0, 0.075)]), "w.world", "w", None).unwrap_err();
        assert!(e.message.contains("start is inside"), "{e}");
        assert!(parse_path(b"not numpy", "p.npy").unwrap_err().message.contains("NumPy"));
        let mut three = npy(&[(1, 2)]);
        let at = three.windows(6).position(|w| w == b"(1, 2)").unwrap();
        three[at..at + 6].copy_from_slice(b"(2, 1)");
        assert!(parse_path(&three, "p.npy").unwrap_err().message.contains("shape"));
    }
}

//! What strider refuses because it is too much or could compute nothing, through the real
//! binary: worlds past their counts are refused at the line that passes them, before the work
//! grows; a BARN path off the challenge's map; fuzzy engines whose arithmetic overflows; a
//! script filling memory is stopped with a located error (exit 2), not killed by the system.

mod common;

use common::{refused, strider, strider_in_address_space, temp_dir};

use std::fmt::Write as _;
use std::path::Path;

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// A BARN world of `n` cylinders 3 m apart, far from the challenge's start and goal.
fn barn_world(n: usize) -> String {
    let mut text = String::from("<sdf version='1.6'>\n<world name='default'>\n");
    for i in 0..n {
        let (x, y) = (20.0 + (i % 300) as f64 * 3.0, 20.0 + (i / 300) as f64 * 3.0);
        let _ = writeln!(
            text,
            "<model name='unit_cylinder_{i}'><pose frame=''>{x} {y} 0 0 0 0</pose><link name='link'>\
             <collision name='collision'><geometry><cylinder><radius>0.075</radius><length>1</length>\
             </cylinder></geometry></collision></link></model>"
        );
    }
    text.push_str("</world>\n</sdf>\n");
    text
}

/// A NumPy file of (row, column) cells stored as `descr` (`<i8`, `<f4`…), each number's
/// bytes written by `bytes`.
fn npy(descr: &str, cells: &[(f64, f64)], bytes: impl Fn(f64) -> Vec<u8>) -> Vec<u8> {
    let header = format!("{{'descr': '{descr}', 'fortran_order': False, 'shape': ({}, 2), }}", cells.len());
    let pad = 64 - (10 + header.len() + 1) % 64;
    let mut out = b"\x93NUMPY\x01\x00".to_vec();
    out.extend(((header.len() + pad + 1) as u16).to_le_bytes());
    out.extend(header.bytes());
    out.extend(std::iter::repeat_n(b' ', pad));
    out.push(b'\n');
    for &(r, c) in cells {
        out.extend(bytes(r));
        out.extend(bytes(c));
    }
    out
}

#[test]
fn a_text_world_past_the_obstacle_limit_is_refused_at_the_line_that_passes_it() {
    let dir = temp_dir("text_count");
    let mut text = String::from("start 0 0\ngoal 5 0\n");
    for i in 0..100_001 {
        let _ = writeln!(text, "cyl {} {} 1", 10 + (i % 2000) * 3, 10 + (i / 2000) * 3);
    }
    let world = dir.join("many.txt");
    std::fs::write(&world, text).unwrap();
    refused(&strider(&["run", s(&world), "--body", "disc"]), &["many.txt:100003:1: more than 100000 obstacles"]);
    // The same bound for terrain features.
    let holes = "start 0 0\ngoal 5 0\n".to_string() + &"hole cyl 50 50 1\n".repeat(100_001);
    std::fs::write(&world, holes).unwrap();
    refused(&strider(&["run", s(&world), "--body", "disc"]), &["many.txt:100003:1: more than 100000 terrain features"]);
}

#[test]
fn a_map_script_past_the_obstacle_limit_is_stopped_at_the_call_that_passes_it() {
    let dir = temp_dir("script_count");
    let map = dir.join("many.rhai");
    let script = "let m = world(\"many\");\nm.start(0.0, 0.0, 0.0);\nm.goal(5.0, 0.0, 0.5);\n\
                  for i in 0..100001 {\n    m.cylinder(10.0 + (i % 2000) * 3.0, 10.0 + (i / 2000) * 3.0, 1.0);\n}\nm";
    std::fs::write(&map, script).unwrap();
    refused(&strider(&["run", s(&map), "--body", "disc"]), &["many.rhai:5:", "more than 100000 obstacles"]);
}

#[test]
fn an_outline_past_the_point_limit_is_refused_at_the_point_that_passes_it() {
    let dir = temp_dir("outline");
    let n = 10_001;
    let points: Vec<String> = (0..n)
        .map(|i| {
            let a = std::f64::consts::TAU * i as f64 / n as f64;
            format!("{} {}", 100.0 + 50.0 * a.cos(), 100.0 + 50.0 * a.sin())
        })
        .collect();
    let line = format!("poly {}", points.join(" "));
    // The column of the 10,001st point's x.
    let col = line.chars().count() - points[n - 1].chars().count() + 1;
    let world = dir.join("outline.txt");
    std::fs::write(&world, format!("start 0 0\ngoal 5 0\n{line}\n")).unwrap();
    let o = strider(&["run", s(&world), "--body", "disc"]);
    refused(&o, &[&format!("outline.txt:3:{col}:"), "10001 points: at most 10000"]);
}

#[test]
fn a_barn_world_past_the_cylinder_limit_is_refused_at_the_first_cylinder_too_many() {
    let dir = temp_dir("barn_count");
    let world = dir.join("world_1.world");
    std::fs::write(&world, barn_world(100_001)).unwrap();
    // Line 1 is <sdf>, line 2 <world>, then one model a line.
    refused(&strider(&["run", s(&world), "--body", "disc"]), &["world_1.world:100003:1: more than 100000 cylinders"]);
}

#[test]
fn a_barn_path_off_the_challenge_map_is_refused() {
    let dir = temp_dir("barn_path");
    let world = dir.join("world_3.world");
    std::fs::write(&world, barn_world(1)).unwrap();
    let path = dir.join("path_3.npy");
    let i8 = |v: f64| (v as i64).to_le_bytes().to_vec();
    std::fs::write(&path, npy("<i8", &[(15.0, 0.0), (40.0, 3.0)], i8)).unwrap();
    refused(
        &strider(&["run", s(&world), "--body", "disc"]),
        &["path_3.npy", "cell 2: its row 40 is off the challenge's map"],
    );
    // Past the old "beyond a million" check, whose `abs` overflowed.
    let min = |v: f64| if v < 0.0 { i64::MIN.to_le_bytes().to_vec() } else { (v as i64).to_le_bytes().to_vec() };
    std::fs::write(&path, npy("<i8", &[(15.0, -1.0)], min)).unwrap();
    refused(&strider(&["run", s(&world), "--body", "disc"]), &["cell 1: its column -9223372036854775808 is off"]);
}

#[test]
fn engines_that_could_only_give_nan_are_refused_where_they_are_written() {
    let dir = temp_dir("nan_engines");
    let fll = |input_term: &str, output_range: &str| {
        format!(
            "Engine: nan\nInputVariable: x\n  enabled: true\n  range: 0 10\n  term: a {input_term}\n\
             OutputVariable: y\n  enabled: true\n  range: {output_range}\n  aggregation: Maximum\n\
             defuzzifier: Centroid 100\n  default: nan\n  term: one Triangle 0 0.5 1\nRuleBlock: r\n\
             conjunction: Minimum\n  disjunction: Maximum\n  implication: Minimum\n  activation: General\n\
             rule: if x is a then y is one\n"
        )
    };
    let fll_cases = [
        (fll("Arc -1e308 1e308", "0 1"), "e.fll:5:9:", "overflow its arithmetic"),
        (fll("SemiEllipse -1e308 1e308", "0 1"), "e.fll:5:9:", "overflow its arithmetic"),
        (fll("Triangle 0 5 10", "-1e308 1e308"), "e.fll:6:1:", "wider than the largest number"),
        (fll("Triangle 0 5 10", "0 1e307"), "e.fll:6:1:", "Centroid sums 100 samples"),
    ];
    let rhai = |term: &str, range: &str| {
        format!(
            "let e = fuzzy_engine(\"nan\");\nlet x = e.input(\"x\", 0, 10);\nx.term(\"a\", {term});\n\
             let y = e.output(\"y\", {range});\ny.term(\"one\", \"triangle\", [0, 0.5, 1]);\n\
             let b = e.rule_block(\"r\");\nb.rule(\"if x is a then y is one\");\ne"
        )
    };
    let rhai_cases = [
        (rhai("\"arc\", [-1e308, 1e308]", "0, 1"), "e.rhai:3:", "overflow its arithmetic"),
        (rhai("\"semiellipse\", [-1e308, 1e308]", "0, 1"), "e.rhai:3:", "overflow its arithmetic"),
        (rhai("\"triangle\", [0, 5, 10]", "-1e308, 1e308"), "e.rhai:4:", "wider than the largest number"),
        (rhai("\"triangle\", [0, 5, 10]", "0, 1e306"), "e.rhai:4:", "Centroid sums 1000 samples"),
    ];
    let files = [dir.join("e.fll"), dir.join("e.rhai")];
    for (file, cases) in files.iter().zip([fll_cases, rhai_cases]) {
        for (text, at, what) in cases {
            std::fs::write(file, &text).unwrap();
            refused(&strider(&["fuzzy", "eval", s(file)]), &[at, what]);
        }
    }
}

/// Address space the memory tests run in, KiB: 6 GB, so a script that fills memory fails
/// there rather than taking the machine's.
const ADDRESS_SPACE_KIB: u64 = 6_000_000;

#[test]
fn a_script_filling_memory_is_stopped_with_a_located_error() {
    let dir = temp_dir("memory");
    // 16,000 closures each holding its own 512 KiB string: every value within Rhai's sizes.
    let fill = "let s = \"x\";\nfor i in 0..19 { s += s; }\nlet fs = [];\nfor i in 0..16000 { let t = s + i; fs.push(|| t); }\n";
    let rules = dir.join("rules.rhai");
    std::fs::write(&rules, fill).unwrap();
    let map = dir.join("map.rhai");
    std::fs::write(&map, format!("{fill}let m = world(\"w\");\nm.start(0.0, 0.0, 0.0);\nm.goal(5.0, 0.0, 0.5);\nm"))
        .unwrap();
    let experiment = dir.join("experiment.rhai");
    std::fs::write(&experiment, fill).unwrap();
    let via_experiment = dir.join("loads.rhai");
    std::fs::write(&via_experiment, format!("let r = load_rules({:?});\n", s(&rules))).unwrap();
    let runs: [(&[&str], &str); 4] = [
        (&["run", "random:sparse", "--body", "disc", "--rules", s(&rules)], "rules.rhai:4:"),
        (&["run", s(&map), "--body", "disc"], "map.rhai:4:"),
        (&["experiment", s(&experiment)], "experiment.rhai:4:"),
        (&["experiment", s(&via_experiment)], "rules.rhai:4:"),
    ];
    for (args, at) in runs {
        let o = strider_in_address_space(args, ADDRESS_SPACE_KIB);
        refused(&o, &[at, "its memory limit"]);
    }
}

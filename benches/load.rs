//! Loading is near-linear in what is loaded: time per world or engine at growing sizes, each
//! four (or five) times the one before, so a linear loader's times grow about fourfold and a
//! quadratic one's sixteenfold. Text and BARN worlds of far-apart cylinders (up to the 100,000
//! a world may hold), non-convex outlines split into convex parts (up to the 10,000 points an
//! outline may have), and FLL engines with as many rules as terms.

use std::fmt::Write as _;

use divan::{Bencher, black_box};
use glam::DVec2;
use strider::fuzzy::fll;
use strider::geom::decompose;
use strider::maps::{barn, text};

fn main() {
    divan::main();
}

/// Where the `i`-th of the far-apart cylinders stands: rows of 300, 3 m apart.
fn spot(i: usize) -> (f64, f64) {
    (20.0 + (i % 300) as f64 * 3.0, 20.0 + (i / 300) as f64 * 3.0)
}

#[divan::bench(args = [6_250, 25_000, 100_000], sample_count = 3, sample_size = 1)]
fn text_world(bencher: Bencher, n: usize) {
    let mut world = String::from("start 0 0\ngoal 5 0\n");
    for i in 0..n {
        let (x, y) = spot(i);
        let _ = writeln!(world, "cyl {x} {y} 0.075");
    }
    bencher.bench(|| black_box(text::parse(&world, "w.txt").expect("text world")));
}

#[divan::bench(args = [6_250, 25_000, 100_000], sample_count = 3, sample_size = 1)]
fn barn_world(bencher: Bencher, n: usize) {
    let mut world = String::from("<sdf version='1.6'>\n<world name='default'>\n");
    for i in 0..n {
        let (x, y) = spot(i);
        let _ = writeln!(
            world,
            "<model name='unit_cylinder_{i}'><pose frame=''>{x} {y} 0 0 0 0</pose><link name='link'>\
             <collision name='collision'><geometry><cylinder><radius>0.075</radius><length>1</length>\
             </cylinder></geometry></collision></link></model>"
        );
    }
    world.push_str("</world>\n</sdf>\n");
    bencher.bench(|| black_box(barn::parse_world(&world, "world_1.world", "world_1", None).expect("BARN world")));
}

/// A star of `n` points alternating between two radii: non-convex, split into long thin parts.
#[divan::bench(args = [625, 2_500, 10_000], sample_count = 3, sample_size = 1)]
fn star_outline(bencher: Bencher, n: usize) {
    let outline: Vec<DVec2> = (0..n)
        .map(|i| DVec2::from_angle(std::f64::consts::TAU * i as f64 / n as f64) * if i % 2 == 0 { 50.0 } else { 49.0 })
        .collect();
    bencher.bench(|| black_box(decompose(&outline).expect("star")));
}

/// A comb of `n / 4` teeth.
#[divan::bench(args = [625, 2_500, 10_000], sample_count = 3, sample_size = 1)]
fn comb_outline(bencher: Bencher, n: usize) {
    let mut outline = vec![DVec2::new(0.0, 0.0)];
    for t in 0..n / 4 - 1 {
        let x = 2.0 * t as f64;
        outline.extend([DVec2::new(x, 1.0), DVec2::new(x, 3.0), DVec2::new(x + 1.0, 3.0), DVec2::new(x + 1.0, 1.0)]);
    }
    let end = 2.0 * (n / 4) as f64;
    outline.extend([DVec2::new(end, 1.0), DVec2::new(end, 0.0)]);
    bencher.bench(|| black_box(decompose(&outline).expect("comb")));
}

/// An FLL engine of one input and one output with `n` terms each and `n` rules, each rule on a
/// term of its own.
#[divan::bench(args = [6_250, 25_000, 100_000], sample_count = 3, sample_size = 1)]
fn fll_engine(bencher: Bencher, n: usize) {
    let mut text = String::from("Engine: big\nInputVariable: x\n  enabled: true\n  range: 0 10\n");
    for i in 0..n {
        let a = i as f64 * 1e-4;
        let _ = writeln!(text, "  term: t{i} Triangle {a} {} {}", a + 0.5, a + 1.0);
    }
    text.push_str("OutputVariable: y\n  enabled: true\n  range: 0 1\n  aggregation: Maximum\n");
    text.push_str("  defuzzifier: Centroid 100\n  default: nan\n");
    for i in 0..n {
        let _ = writeln!(text, "  term: o{i} Triangle 0 0.5 1");
    }
    text.push_str("RuleBlock: r\n  conjunction: Minimum\n  disjunction: Maximum\n  implication: Minimum\n");
    text.push_str("  activation: General\n");
    for i in (0..n).rev() {
        let _ = writeln!(text, "  rule: if x is t{i} then y is o{i}");
    }
    bencher.bench(|| black_box(fll::export(&fll::import(&text, "big.fll").expect("FLL engine"))));
}

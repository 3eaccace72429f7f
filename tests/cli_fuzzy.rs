//! End-to-end checks of `strider fuzzy …` and the default scenario, through the real binary.

mod common;

use common::{stderr, stdout, strider};

use std::path::{Path, PathBuf};

fn temp_dir(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn eval_grid_and_rows() {
    let o = strider(&["fuzzy", "eval", "scripts/simple_nav.rhai"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[0], "distance,angle,turn,speed");
    assert_eq!(lines.len(), 1 + 32 * 32);
    assert_eq!(lines[1].split(',').take(2).collect::<Vec<_>>(), vec!["0", "-180"]);

    let dir = temp_dir("eval_rows");
    let csv = dir.join("in.csv");
    std::fs::write(&csv, "food,service\n0,0\n10,10\nnan,5\n").unwrap();
    let o = strider(&["fuzzy", "eval", "tests/fixtures/fuzzy/tipper.fll", "--inputs", csv.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let rows: Vec<Vec<f64>> =
        stdout(&o).lines().skip(1).map(|l| l.split(',').map(|v| v.parse().unwrap()).collect()).collect();
    assert_eq!(rows.len(), 3);
    // Takagi-Sugeno output by hand. service = 0, food = 0: cheap fires fully (z = 5), average with
    // the gaussian tail g(0; 5, 1.5), generous with g(0; 10, 1.5) (z = 1·0 + 1·0 + 5).
    let g = |x: f64, m: f64| (-(x - m) * (x - m) / (2.0 * 1.5 * 1.5)).exp();
    let (w1, w2, w3) = (1.0, g(0.0, 5.0), g(0.0, 10.0));
    let expected = (w1 * 5.0 + w2 * 15.0 + w3 * 5.0) / (w1 + w2 + w3);
    assert!((rows[0][3] - expected).abs() < 1e-12, "{} vs {expected}", rows[0][3]);
    // service = 10, food = 10: generous fully (z = 10 + 10 + 5 = 25), average with g(10; 5, 1.5),
    // cheap with g(10; 0, 1.5).
    let (w1, w2, w3) = (g(10.0, 0.0), g(10.0, 5.0), 1.0);
    let expected = (w1 * 5.0 + w2 * 15.0 + w3 * 25.0) / (w1 + w2 + w3);
    assert!((rows[1][3] - expected).abs() < 1e-12, "{} vs {expected}", rows[1][3]);
    assert!(rows[0][2] > 0.0 && rows[0][2] < 10.0);
}

#[test]
fn export_then_import_gives_identical_outputs() {
    let dir = temp_dir("export");
    let o = strider(&["fuzzy", "export", "scripts/simple_nav.rhai", "--format", "fll"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let fll = dir.join("nav.fll");
    std::fs::write(&fll, o.stdout).unwrap();
    let a = strider(&["fuzzy", "eval", "scripts/simple_nav.rhai"]);
    let b = strider(&["fuzzy", "eval", fll.to_str().unwrap()]);
    assert!(b.status.success(), "{}", stderr(&b));
    assert_eq!(stdout(&a), stdout(&b));
}

#[test]
fn bad_input_is_a_located_error_with_exit_code_2() {
    let o = strider(&["fuzzy", "eval", "tests/fixtures/fuzzy/bad_rule.fll"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("bad_rule.fll:46:"), "{}", stderr(&o));
    assert!(stderr(&o).contains("unknown term 'averag'"), "{}", stderr(&o));

    let o = strider(&["fuzzy", "eval", "tests/fixtures/fuzzy/endless.rhai"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("endless.rhai:5:"), "{}", stderr(&o));
    assert!(stderr(&o).contains("operation limit"), "{}", stderr(&o));

    let o = strider(&["fuzzy", "eval", "tests/fixtures/fuzzy/missing.fll"]);
    assert_eq!(o.status.code(), Some(2));
    let o = strider(&["fuzzy", "eval", "Cargo.toml"]);
    assert_eq!(o.status.code(), Some(2));

    let dir = temp_dir("bad_csv");
    let csv = dir.join("bad.csv");
    std::fs::write(&csv, "service,food\n1,x\n").unwrap();
    let o = strider(&["fuzzy", "eval", "tests/fixtures/fuzzy/tipper.fll", "--inputs", csv.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("bad.csv:2:3"), "{}", stderr(&o));
}

#[test]
fn plot_writes_pngs() {
    let dir = temp_dir("plot");
    let o = strider(&[
        "fuzzy",
        "plot",
        "tests/fixtures/fuzzy/tipper.fll",
        "--out",
        dir.to_str().unwrap(),
        "--size",
        "320x200",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    for name in ["tipper_input_service.png", "tipper_output_tsTip.png", "surface_tip.png", "surface_tsTip.png"] {
        let img = image::open(dir.join(name)).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!((img.width(), img.height()), (320, 200));
    }
}

#[test]
fn bench_reports_rate_and_agreement() {
    let o = strider(&["fuzzy", "bench", "scripts/simple_nav.rhai", "--seconds", "0.2", "--check", "200"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(text.contains("inferences per second"), "{text}");
    assert!(text.contains("max |compiled - reference| over 200 inputs"), "{text}");
}

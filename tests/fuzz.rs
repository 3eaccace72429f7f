//! Fuzzing every front door that reads user input: FLL, rules, Rhai map and rule scripts, text
//! worlds, SteerSuite test cases, MovingAI `.map` and `.scen`, BVH and policy files. Each target feeds its parser
//! mutated seeds from `tests/fuzz_corpus/<target>/` (bytes flipped, inserted, deleted,
//! repeated, spliced from another seed, numbers replaced by NaN, infinities, huge or tiny
//! values, deep brackets) and arbitrary bytes, and asserts that every input gives a valid result
//! or an error naming the file — never a panic — within a bounded time. What parses is used:
//! engines are evaluated on NaN and infinite inputs, worlds and clips written back and read
//! again, policies queried.
//!
//! `STRIDER_FUZZ_CASES` sets the cases per target (a short smoke by default, so the whole suite
//! stays well under a minute); `STRIDER_FUZZ_CASES=200000 cargo test --release --test fuzz`
//! runs it long. `STRIDER_FUZZ_SEED` changes the random stream (the default is fixed, so a
//! plain `cargo test` is reproducible).

use std::path::Path;
use std::time::{Duration, Instant};

use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestCaseError, TestRng, TestRunner};

use strider::anim::bvh::{self, BvhOptions};
use strider::anim::db::Fnv;
use strider::anim::policy::{Errors, LearnParams, Policy, StateGrid};
use strider::anim::{Database, DbParams, rig};
use strider::fuzzy::{Inference, Rule, fll};
use strider::maps::{movingai, text};
use strider::script::{Limits, ScriptLog, load_engines, load_scenario};

/// Cases per target in a plain `cargo test`.
const SMOKE_CASES: u32 = 1000;

/// Longest time one input may take, a bound far above any parser's real cost: only a hang
/// (or a quadratic blow-up) comes near it.
const CASE_LIMIT: Duration = Duration::from_secs(20);

fn cases() -> u32 {
    std::env::var("STRIDER_FUZZ_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(SMOKE_CASES)
}

fn runner(target: &str) -> TestRunner {
    let seed: u64 = std::env::var("STRIDER_FUZZ_SEED").ok().and_then(|v| v.parse().ok()).unwrap_or(14);
    let mut key = [0u8; 32];
    key[..8].copy_from_slice(&seed.to_le_bytes());
    for (i, b) in target.bytes().enumerate() {
        key[8 + i % 24] ^= b;
    }
    let config = Config {
        cases: cases(),
        failure_persistence: None,
        max_shrink_iters: 2_000,
        max_global_rejects: u32::MAX,
        ..Config::default()
    };
    TestRunner::new_with_rng(config, TestRng::from_seed(RngAlgorithm::ChaCha, &key))
}

/// The seed inputs of a target, in name order.
fn corpus(target: &str) -> Vec<Vec<u8>> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz_corpus").join(target);
    let mut paths: Vec<_> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .collect();
    paths.sort();
    let seeds: Vec<Vec<u8>> = paths.iter().map(|p| std::fs::read(p).unwrap()).collect();
    assert!(!seeds.is_empty(), "{}: no seeds", dir.display());
    seeds
}

/// Text a mutation may insert: odd numbers, brackets and separators.
const TOKENS: &[&str] = &[
    "nan",
    "NaN",
    "inf",
    "-inf",
    "+inf",
    "infinity",
    "1e308",
    "-1e308",
    "1e309",
    "4.9e-324",
    "-0",
    "0",
    "-1",
    "1e6",
    "18446744073709551616",
    "99999999999999999999999",
    "0x10",
    "1.",
    ".5",
    "1e",
    "--1",
    "(",
    ")",
    "((((((((",
    "))))",
    "{",
    "}",
    "[",
    "]",
    "\"",
    "'",
    ",",
    ";",
    ":",
    "#",
    "//",
    "/*",
    "\n",
    "\r\n",
    "\t",
    " ",
    "\u{feff}",
    "\u{0}",
    "é",
    "\u{10ffff}",
    "if",
    "then",
    "and",
    "or",
    "not",
    "with",
    "is",
    "very",
    "any",
    "let",
    "fn",
    "loop",
    "while true {}",
    "ROOT",
    "JOINT",
    "End Site",
    "OFFSET",
    "CHANNELS",
    "MOTION",
    "Frames:",
    "Frame Time:",
    "@",
    "T",
    ".",
    "map",
    "version 1",
    "type octile",
    "height",
    "width",
    "box",
    "cyl",
    "poly",
    "convex",
    "start",
    "goal",
];

/// One change to a seed.
#[derive(Debug, Clone)]
enum Mutation {
    /// Overwrite a byte.
    Set(prop::sample::Index, u8),
    /// Insert a token.
    Insert(prop::sample::Index, prop::sample::Index),
    /// Delete up to `n` bytes.
    Delete(prop::sample::Index, usize),
    /// Repeat a stretch of up to `n` bytes `k` times.
    Repeat(prop::sample::Index, usize, usize),
    /// Replace the number at a position by a token.
    Number(prop::sample::Index, prop::sample::Index),
    /// Put a stretch of another seed here.
    Splice(prop::sample::Index, prop::sample::Index, prop::sample::Index, usize),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    let i = any::<prop::sample::Index>;
    prop_oneof![
        3 => (i(), any::<u8>()).prop_map(|(a, b)| Mutation::Set(a, b)),
        3 => (i(), i()).prop_map(|(a, t)| Mutation::Insert(a, t)),
        2 => (i(), 1..64usize).prop_map(|(a, n)| Mutation::Delete(a, n)),
        1 => (i(), 1..64usize, 1..64usize).prop_map(|(a, n, k)| Mutation::Repeat(a, n, k)),
        3 => (i(), i()).prop_map(|(a, t)| Mutation::Number(a, t)),
        1 => (i(), i(), i(), 1..256usize).prop_map(|(a, s, b, n)| Mutation::Splice(a, s, b, n)),
    ]
}

fn apply(seeds: &[Vec<u8>], base: &[u8], mutations: &[Mutation]) -> Vec<u8> {
    let mut v = base.to_vec();
    let at = |i: &prop::sample::Index, len: usize| if len == 0 { 0 } else { i.index(len + 1) };
    for m in mutations {
        let len = v.len();
        match m {
            Mutation::Set(i, b) if len > 0 => {
                let k = i.index(len);
                v[k] = *b;
            }
            Mutation::Set(..) => v.push(b'0'),
            Mutation::Insert(i, t) => {
                let k = at(i, len);
                let tok = TOKENS[t.index(TOKENS.len())].as_bytes();
                v.splice(k..k, tok.iter().copied());
            }
            Mutation::Delete(i, n) => {
                let k = at(i, len);
                let end = (k + n).min(len);
                v.drain(k..end);
            }
            Mutation::Repeat(i, n, k) => {
                let s = at(i, len);
                let e = (s + n).min(len);
                let piece = v[s..e].to_vec();
                for _ in 0..*k {
                    v.splice(e..e, piece.iter().copied());
                }
            }
            Mutation::Number(i, t) => {
                let digit = |b: u8| b.is_ascii_digit() || matches!(b, b'.' | b'-' | b'+' | b'e' | b'E');
                let mut s = at(i, len).min(len);
                while s < len && !v[s].is_ascii_digit() {
                    s += 1;
                }
                if s == len {
                    continue;
                }
                while s > 0 && digit(v[s - 1]) {
                    s -= 1;
                }
                let mut e = s;
                while e < len && digit(v[e]) {
                    e += 1;
                }
                let tok = TOKENS[t.index(16)].as_bytes();
                v.splice(s..e, tok.iter().copied());
            }
            Mutation::Splice(i, s, j, n) => {
                let other = &seeds[s.index(seeds.len())];
                let from = at(j, other.len()).min(other.len());
                let end = (from + n).min(other.len());
                let k = at(i, len);
                v.splice(k..k, other[from..end].iter().copied());
            }
        }
        // Keep inputs small enough that one case stays cheap.
        v.truncate(1 << 16);
    }
    v
}

/// Mutated seeds (most cases), the seeds themselves, and arbitrary bytes.
fn input(seeds: Vec<Vec<u8>>) -> impl Strategy<Value = Vec<u8>> {
    let n = seeds.len();
    let s2 = seeds.clone();
    let mutated =
        (0..n, prop::collection::vec(mutation(), 1..5)).prop_map(move |(k, ms)| apply(&seeds, &seeds[k], &ms));
    prop_oneof![
        1 => (0..n).prop_map(move |k| s2[k].clone()),
        12 => mutated,
        3 => prop::collection::vec(any::<u8>(), 0..1024),
    ]
}

/// Runs `check` on the target's inputs, as text (lossy UTF-8, as no loader passes invalid
/// UTF-8 on) or bytes, and fails with the smallest failing input found.
/// The check returns whether the input was accepted (for the statistics printed at the end).
fn fuzz(target: &str, check: impl Fn(&[u8]) -> Result<bool, TestCaseError>) {
    let seeds = corpus(target);
    let mut runner = runner(target);
    let started = Instant::now();
    let runs = std::cell::Cell::new(0u64);
    let accepted = std::cell::Cell::new(0u64);
    let result = runner.run(&input(seeds), |bytes| {
        runs.set(runs.get() + 1);
        let t = Instant::now();
        if check(&bytes)? {
            accepted.set(accepted.get() + 1);
        }
        prop_assert!(t.elapsed() < CASE_LIMIT, "one input took {:?}", t.elapsed());
        Ok(())
    });
    eprintln!(
        "fuzz {target}: {} executions ({} accepted) in {:.1} s",
        runs.get(),
        accepted.get(),
        started.elapsed().as_secs_f64()
    );
    if let Err(e) = result {
        panic!("fuzz {target}: {e}");
    }
}

fn text_of(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// Values an engine must survive as inputs.
const NASTY_INPUTS: [f64; 8] = [f64::NAN, f64::INFINITY, f64::NEG_INFINITY, f64::MAX, f64::MIN, 0.0, -1e-300, 1e300];

/// A validated engine evaluates every nasty input without panicking, and its FLL export reads
/// back.
fn exercise_engine(engine: &strider::fuzzy::Engine) -> Result<(), TestCaseError> {
    let mut inf =
        Inference::new(engine).map_err(|e| TestCaseError::fail(format!("validated but not compiled: {e:?}")))?;
    let n = engine.inputs.len();
    for (k, &x) in NASTY_INPUTS.iter().enumerate() {
        for i in 0..n {
            inf.set_input(i, NASTY_INPUTS[(k + i) % NASTY_INPUTS.len()].min(x.max(f64::MIN)));
        }
        inf.process();
    }
    let text = fll::export(engine);
    let back = fll::import(&text, "export.fll");
    prop_assert!(back.is_ok(), "the export of a valid engine does not read back: {:?}\n{text}", back.err());
    Ok(())
}

fn located(e: &strider::diagnostic::SourceError, file: &str) -> Result<(), TestCaseError> {
    prop_assert_eq!(&e.file, file);
    prop_assert!(!e.message.is_empty());
    Ok(())
}

#[test]
fn fuzz_fll() {
    fuzz("fll", |b| match fll::import(&text_of(b), "f.fll") {
        Ok(engine) => exercise_engine(&engine).map(|_| true),
        Err(e) => located(&e, "f.fll").map(|_| false),
    });
}

/// Ground profiles of `strider steps`: parsed, and when they read, walked by the footstep
/// planner (courses up to 30 m long; every step it takes passes the one step check).
#[test]
fn fuzz_profiles() {
    use strider::footstep::{FootstepParams, PlannerMode, check_step, walk};
    fuzz("profile", |b| match strider::ground::parse(&text_of(b), "p.profile") {
        Ok(course) => {
            if (course.goal_m - course.start_m).abs() <= 30.0 {
                let params = FootstepParams::default();
                if let Ok(w) = walk(&course, params, PlannerMode::Window) {
                    for s in &w.steps {
                        let sw = &s.swing;
                        let (a, b, c) = (sw.lift_off.x_m, sw.stance.x_m, sw.touch_down.x_m);
                        prop_assert!(check_step(&course.ground, &params, a, b, c).is_ok(), "an invalid step: {sw:?}");
                    }
                }
            }
            Ok(true)
        }
        Err(e) => located(&e, "p.profile").map(|_| false),
    });
}

#[test]
fn fuzz_rules() {
    let tipper =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz_corpus/fll/tipper.fll"))
            .unwrap();
    let engine = fll::import(&tipper, "tipper.fll").unwrap();
    fuzz("rule", |b| {
        let text = text_of(b);
        let mut any = false;
        for line in text.lines().chain(std::iter::once(text.as_str())) {
            if let Ok(rule) = Rule::parse(line, &engine.inputs, &engine.outputs) {
                any = true;
                let again = rule.to_text(&engine.inputs, &engine.outputs);
                let back = Rule::parse(&again, &engine.inputs, &engine.outputs);
                prop_assert!(back.as_ref().is_ok_and(|r| *r == rule), "'{line}' → '{again}' → {back:?}");
            }
        }
        Ok(any)
    });
}

#[test]
fn fuzz_rhai_rule_scripts() {
    fuzz("rhai_rules", |b| {
        let log = ScriptLog::new();
        match load_engines(&text_of(b), "r.rhai", Limits::default(), &log) {
            Ok(engines) => engines.iter().try_for_each(exercise_engine).map(|_| true),
            Err(e) => located(&e, "r.rhai").map(|_| false),
        }
    });
}

#[test]
fn fuzz_rhai_map_scripts() {
    fuzz("rhai_map", |b| {
        let log = ScriptLog::new();
        match load_scenario(&text_of(b), "m.rhai", Limits::default(), &log) {
            Ok(s) => {
                let written = text::write(&s);
                let back = text::parse(&written, "written.txt");
                prop_assert!(back.is_ok(), "a valid world does not read back: {:?}\n{written}", back.err());
                Ok(true)
            }
            Err(e) => located(&e, "m.rhai").map(|_| false),
        }
    });
}

#[test]
fn fuzz_text_worlds() {
    fuzz("text_world", |b| match text::parse(&text_of(b), "w.txt") {
        Ok(s) => {
            let written = text::write(&s);
            let back = text::parse(&written, "written.txt");
            prop_assert!(back.is_ok(), "a valid world does not read back: {:?}\n{written}", back.err());
            Ok(true)
        }
        Err(e) => located(&e, "w.txt").map(|_| false),
    });
}

/// SteerSuite test cases: a case read is a crowd that the text format keeps; anything else is
/// a located error.
#[test]
fn fuzz_steersuite_cases() {
    fuzz("steersuite", |b| match strider::maps::steersuite::parse(&text_of(b), "c.xml", 7) {
        Ok(s) => {
            let written = text::write(&s);
            let back = text::parse(&written, "written.txt");
            prop_assert!(back.is_ok(), "a valid case does not read back: {:?}\n{written}", back.err());
            prop_assert_eq!(&back.unwrap().crowd, &s.crowd);
            Ok(true)
        }
        Err(e) => located(&e, "c.xml").map(|_| false),
    });
}

#[test]
fn fuzz_movingai_maps() {
    let scen = "version 1\n0\tx.map\t6\t5\t0\t0\t5\t4\t6.41421356\n";
    fuzz("movingai_map", |b| {
        let text = text_of(b);
        let ok = match movingai::parse_map(&text, "x.map") {
            Ok(grid) => {
                let cells: usize = grid.merged_rects().iter().map(|r| (r.x1 - r.x0) * (r.y1 - r.y0)).sum();
                prop_assert_eq!(cells, grid.blocked_count());
                true
            }
            Err(e) => located(&e, "x.map").map(|_| false)?,
        };
        if let Err(e) = movingai::load(&text, "x.map", scen, "x.map.scen") {
            prop_assert!(e.file == "x.map" || e.file == "x.map.scen", "{e}");
        }
        Ok(ok)
    });
}

#[test]
fn fuzz_movingai_scenarios() {
    let map =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz_corpus/movingai_map/tiny.map"))
            .unwrap();
    fuzz("movingai_scen", |b| {
        let text = text_of(b);
        if let Err(e) = movingai::parse_scen(&text, "tiny.map.scen") {
            located(&e, "tiny.map.scen")?;
        }
        match movingai::load(&map, "tiny.map", &text, "tiny.map.scen") {
            Ok(s) => {
                prop_assert!(s.validate().is_ok());
                Ok(true)
            }
            Err(e) => {
                prop_assert!(e.file == "tiny.map" || e.file == "tiny.map.scen", "{e}");
                Ok(false)
            }
        }
    });
}

#[test]
fn fuzz_bvh() {
    fuzz("bvh", |b| match bvh::parse(&text_of(b), "c.bvh", "c", &BvhOptions::default()) {
        Ok(parsed) => {
            let written = bvh::write(&parsed.skeleton, &parsed.clip, &BvhOptions::default());
            let back = bvh::parse(&written, "written.bvh", "c", &BvhOptions::default());
            prop_assert!(back.is_ok(), "a clip does not read back: {:?}\n{written}", back.err());
            if let Some((feet, _)) = rig::locate_feet(&parsed.skeleton, &[]) {
                let _ = rig::guess_unit(&parsed.skeleton, feet);
            }
            if parsed.clip.frames.len() <= 400 && parsed.skeleton.len() <= 64 {
                let params = DbParams { k: 1, ..DbParams::default() };
                let _ = Database::build(vec![parsed.clip], parsed.skeleton, params, None);
            }
            Ok(true)
        }
        Err(e) => located(&e, "c.bvh").map(|_| false),
    });
}

/// A database small enough to fuzz its policies: the walk in centimetres of the BVH fixtures.
fn small_database() -> Database {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/bvh/centimetres.bvh");
    let b = bvh::parse(&std::fs::read_to_string(path).unwrap(), "centimetres.bvh", "walk", &BvhOptions { scale: 0.01 })
        .unwrap();
    Database::build(vec![b.clip], b.skeleton, DbParams { k: 3, ..DbParams::default() }, None).unwrap()
}

/// Policy files: the corpus is made here (an untrained and a briefly trained policy of
/// [`small_database`]); mutated files get their checksum recomputed half of the time, so the
/// reader is tried past its checksum too.
#[test]
fn fuzz_policies() {
    let db = small_database();
    let fresh = Policy::new(&db, StateGrid::default(), LearnParams::default(), 3);
    let mut trained = fresh.clone();
    trained.train(&db, 128, 1, &mut |_| {}, &mut |_| {});
    let seeds = vec![fresh.to_bytes(), trained.to_bytes()];
    let mut runner = runner("policy");
    let started = Instant::now();
    let strategy = (input(seeds), any::<bool>());
    let (runs, accepted) = (std::cell::Cell::new(0u64), std::cell::Cell::new(0u64));
    let result = runner.run(&strategy, |(mut bytes, fix)| {
        runs.set(runs.get() + 1);
        if fix && bytes.len() >= 8 {
            let n = bytes.len() - 8;
            let mut h = Fnv::default();
            h.bytes(&bytes[..n]);
            bytes[n..].copy_from_slice(&h.0.to_le_bytes());
        }
        let t = Instant::now();
        if let Ok(p) = Policy::from_bytes(&bytes, &db) {
            accepted.set(accepted.get() + 1);
            prop_assert!(p.check(&db).is_ok());
            for i in 0..db.intervals.len() {
                for e in [0.0, f64::NAN, f64::INFINITY, -1e300] {
                    let a = p.choose(i, Errors { speed: e, direction: -e });
                    prop_assert!(a < db.candidates[i].len());
                }
            }
            prop_assert!(Policy::from_bytes(&p.to_bytes(), &db).is_ok());
        }
        prop_assert!(t.elapsed() < CASE_LIMIT);
        Ok(())
    });
    eprintln!(
        "fuzz policy: {} executions ({} accepted) in {:.1} s",
        runs.get(),
        accepted.get(),
        started.elapsed().as_secs_f64()
    );
    if let Err(e) = result {
        panic!("fuzz policy: {e}");
    }
}

// Regressions: inputs the fuzzer found, fixed where they went wrong.

/// A Rhai map accepted a cylinder of radius 0 that its own text export then refused: every
/// importer now refuses it, naming the line.
#[test]
fn regression_a_cylinder_of_zero_radius_is_refused_by_every_importer() {
    let script = "let m = world(\"w\");\nm.start(0.0, 0.0, 0.0);\nm.goal(9.0, 0.0, 0.5);\nm.cylinder(2.0, 0.7, 0);\nm";
    let e = load_scenario(script, "m.rhai", Limits::default(), &ScriptLog::new()).unwrap_err();
    assert_eq!(e.line, 4, "{e}");
    assert!(e.message.contains("radius"), "{e}");
    let e = text::parse("start 0 0\ngoal 9 0\ncyl 2 0.7 0\n", "w.txt").unwrap_err();
    assert_eq!(e.line, 3, "{e}");
}

/// A BARN optimal time so large that the reference length derived from it (at 2 m/s) became
/// infinite was accepted, and the world it wrote could not be read back: both BARN values are
/// now bounded, with the line and column of the value.
#[test]
fn regression_a_benchmark_reference_that_overflows_is_refused() {
    for line in ["optimal_time_at_2mps 1e308", "ref_path_length 1e300"] {
        let e = text::parse(&format!("start 0 0\ngoal 9 0\n{line}\n"), "w.txt").unwrap_err();
        assert_eq!((e.line, e.col), (3, line.find(' ').unwrap() + 2), "{e}");
        assert!(e.message.contains("at most"), "{e}");
    }
    let s = text::parse("start 0 0\ngoal 9 0\noptimal_time_at_2mps 5e6\n", "w.txt").unwrap();
    assert_eq!(s.reference.map(|r| r.path_length_m), Some(1e7));
}

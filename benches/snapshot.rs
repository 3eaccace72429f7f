//! Snapshot checking speed (issue bar: a snapshot of 300 frames at 800×800 is compared in
//! ≤ 2 s): the whole check of `maps/open_field.rhai` with a frame every step — 323 frames —
//! against goldens written beforehand: the episode simulated, every frame drawn, every golden
//! decoded and compared.

use std::path::PathBuf;

use divan::{Bencher, black_box};
use strider::snapshot::{self, Settings, Spec};

fn main() {
    divan::main();
}

/// Checks 323 frames of 800×800 against their goldens (time per check).
#[divan::bench(sample_count = 5, sample_size = 1)]
fn check_323_frames_800x800(bencher: Bencher) {
    let dir = std::env::temp_dir().join(format!("strider-bench-snapshot-{}", std::process::id()));
    let map = concat!(env!("CARGO_MANIFEST_DIR"), "/maps/open_field.rhai");
    let settings = Settings { every: 1, size: (800, 800), ..Settings::default() };
    let spec = Spec::new(map).settings(settings.clone());
    let episode = snapshot::load(&spec).expect("open field episode");
    let written = snapshot::check_episode(&episode, &Settings { update: true, ..settings.clone() }, &dir)
        .expect("goldens written");
    assert!(written.frames.len() >= 300, "{} frames", written.frames.len());
    bencher.bench_local(|| {
        let report = snapshot::check_episode(black_box(&episode), &settings, &dir).expect("check");
        assert!(report.passed(), "{report}");
    });
    let _ = std::fs::remove_dir_all(PathBuf::from(&dir));
}

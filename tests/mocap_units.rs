//! Motion capture as the usual tools write it builds a database with no flag: the unit is read
//! from the leg length (metres, CMU units, centimetres, millimetres), namespace prefixes such as
//! `mixamorig:` are ignored, and the feet are found from the hierarchy's shape when the names
//! say nothing; `--scale` and `--feet` override.
//!
//! The fixtures under `tests/fixtures/bvh/` are the built-in actor's straight walk written in
//! each convention by [`fixture`]; `UPDATE_GOLDEN=1 cargo test --test mocap_units` rewrites
//! them. The CMU files of `STRIDER_CMU_DIR` (default `../shared/motions/cmu`) are tried too when
//! that folder exists.

mod common;

use common::strider;

use std::path::{Path, PathBuf};

use strider::anim::bvh::{self, BvhOptions};
use strider::anim::procedural::{Gait, locomotion};
use strider::anim::rig::{self, FeetFrom};
use strider::anim::{Joint, Skeleton, actor};

/// How a fixture names its joints and which unit it is written in.
struct Convention {
    file: &'static str,
    rename: fn(usize, &str) -> String,
    metres_per_unit: f64,
}

const CONVENTIONS: [Convention; 4] = [
    // CMU: the actor's names, lengths in units of 0.056444 m.
    Convention { file: "cmu_style.bvh", rename: |_, n| n.to_string(), metres_per_unit: 0.056444 },
    // Mixamo: every joint in the `mixamorig:` namespace, centimetres.
    Convention { file: "mixamo_style.bvh", rename: |_, n| format!("mixamorig:{n}"), metres_per_unit: 0.01 },
    // A plain export in centimetres.
    Convention { file: "centimetres.bvh", rename: |_, n| n.to_string(), metres_per_unit: 0.01 },
    // Joints named by number only, millimetres: the feet come from the hierarchy's shape.
    Convention { file: "anonymous_mm.bvh", rename: |i, _| format!("j{i}"), metres_per_unit: 0.001 },
];

fn fixture_path(file: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/bvh").join(file)
}

/// The BVH text of a fixture: eight steps of the built-in walk at 30 Hz.
fn fixture(c: &Convention) -> String {
    let actor = actor::actor();
    let joints: Vec<Joint> =
        actor.joints().iter().enumerate().map(|(i, j)| Joint { name: (c.rename)(i, &j.name), ..j.clone() }).collect();
    let skeleton = Skeleton::new(joints).unwrap();
    let clip = locomotion(&Gait::walk(), 0.0, 8, 30.0, "walk");
    bvh::write(&skeleton, &clip, &BvhOptions { scale: c.metres_per_unit })
}

#[test]
fn fixtures_are_the_walk_in_each_convention() {
    for c in &CONVENTIONS {
        let text = fixture(c);
        let path = fixture_path(c.file);
        if std::env::var_os("UPDATE_GOLDEN").is_some() {
            std::fs::write(&path, &text).unwrap();
        }
        let stored = std::fs::read_to_string(&path).unwrap();
        assert!(stored == text, "{} differs from its generator; UPDATE_GOLDEN=1 rewrites it", c.file);
    }
}

#[test]
fn the_unit_and_feet_are_read_from_each_fixture() {
    for c in &CONVENTIONS {
        let text = std::fs::read_to_string(fixture_path(c.file)).unwrap();
        let b = bvh::parse(&text, c.file, "walk", &BvhOptions::default()).unwrap();
        let (feet, from) = rig::locate_feet(&b.skeleton, &[]).unwrap();
        let names = feet.map(|f| b.skeleton.joints()[f].name.clone());
        let actor = actor::actor();
        let expected = [actor::LEFT_FOOT, actor::RIGHT_FOOT].map(|n| actor.find(n).unwrap());
        assert_eq!(feet, expected, "{}: {names:?}", c.file);
        let want = if c.file.starts_with("anonymous") { FeetFrom::Topology } else { FeetFrom::Name };
        assert_eq!(from, want, "{}", c.file);
        let g = rig::guess_unit(&b.skeleton, feet).unwrap();
        assert!(g.human, "{}", c.file);
        assert_eq!(g.unit.metres, c.metres_per_unit, "{}", c.file);
    }
}

#[test]
fn the_actor_in_metres_is_read_as_metres_and_its_feet_by_shape_too() {
    let a = actor::actor();
    let (feet, from) = rig::locate_feet(&a, &[]).unwrap();
    assert_eq!(from, FeetFrom::Name);
    assert_eq!(rig::feet_by_topology(&a), Some(feet));
    assert_eq!(rig::guess_unit(&a, feet).unwrap().unit.metres, 1.0);
}

#[test]
fn feet_given_by_hand_win_and_unknown_ones_are_none() {
    let a = actor::actor();
    let given = [actor::RIGHT_FOOT.to_string(), actor::LEFT_FOOT.to_string()];
    let (feet, from) = rig::locate_feet(&a, &given).unwrap();
    assert_eq!(from, FeetFrom::Given);
    assert_eq!(feet, [a.find(actor::RIGHT_FOOT).unwrap(), a.find(actor::LEFT_FOOT).unwrap()]);
    assert_eq!(rig::locate_feet(&a, &["nope".into(), actor::LEFT_FOOT.into()]), None);
    // Prefixed names given without their prefix still match.
    let joints: Vec<Joint> =
        a.joints().iter().map(|j| Joint { name: format!("Armature|{}", j.name), ..j.clone() }).collect();
    let prefixed = Skeleton::new(joints).unwrap();
    assert_eq!(rig::locate_feet(&prefixed, &given).map(|f| f.1), Some(FeetFrom::Given));
}

#[test]
fn a_skeleton_without_legs_has_no_feet() {
    let spine = |name: &str, parent: Option<usize>| Joint {
        name: name.into(),
        parent,
        offset: glam::DVec3::new(0.0, 0.0, 0.3),
        channels: Vec::new(),
        end_site: None,
    };
    let s = Skeleton::new(vec![spine("a", None), spine("b", Some(0)), spine("c", Some(1))]).unwrap();
    assert_eq!(rig::locate_feet(&s, &[]), None);
}

fn out_dir(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("mocap_units").join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.parent().unwrap()).unwrap();
    dir
}

/// Runs `db build` and returns the number of intervals it reports, with its stderr.
#[track_caller]
fn build(files: &[&Path], extra: &[&str], out: &Path) -> (usize, String) {
    let mut args = vec!["db", "build", "--bvh"];
    args.extend(files.iter().map(|f| f.to_str().unwrap()));
    args.extend(["--out", out.to_str().unwrap()]);
    args.extend(extra);
    let o = strider(&args);
    let (stdout, stderr) = (String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr));
    assert_eq!(o.status.code(), Some(0), "{args:?}\n{stdout}{stderr}");
    let n = stdout.split_whitespace().next().and_then(|w| w.parse().ok()).expect("an interval count");
    (n, stderr.into_owned())
}

#[test]
fn db_build_needs_no_flag_for_any_convention_and_says_the_unit() {
    for c in &CONVENTIONS {
        let out = out_dir(c.file);
        let (n, stderr) = build(&[&fixture_path(c.file)], &[], &out);
        assert!(n >= 8, "{}: {n} intervals\n{stderr}", c.file);
        let unit = rig::UNITS.iter().find(|u| u.metres == c.metres_per_unit).unwrap();
        assert!(stderr.contains(unit.name) && stderr.contains("read from the leg"), "{}: {stderr}", c.file);
        let how = if c.file.starts_with("anonymous") { "shape of the hierarchy" } else { "found by name" };
        assert!(stderr.contains(how), "{}: {stderr}", c.file);
        // The database reloads (its feet are found the same way again).
        let info = strider(&["db", "info", out.to_str().unwrap()]);
        assert_eq!(info.status.code(), Some(0), "{}", String::from_utf8_lossy(&info.stderr));
    }
}

#[test]
fn scale_and_feet_flags_override_what_is_read() {
    let file = fixture_path("anonymous_mm.bvh");
    // Read as metres the walk is a kilometre-tall giant's: no foot ever slows enough to plant.
    let out = out_dir("forced_scale");
    let o = strider(&["db", "build", "--bvh", file.to_str().unwrap(), "--out", out.to_str().unwrap(), "--scale", "1"]);
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(e.contains("--scale"), "{e}");
    // Feet named by hand are kept in the manifest, so the database reloads with them.
    let out = out_dir("forced_feet");
    let (n, stderr) = build(&[&file], &["--feet", "j10,j13"], &out);
    assert!(n >= 8 && stderr.contains("as given"), "{stderr}");
    let manifest = std::fs::read_to_string(out.join("database.json")).unwrap();
    assert!(manifest.contains("\"feet\"") && manifest.contains("j13"), "{manifest}");
    assert_eq!(strider(&["db", "info", out.to_str().unwrap()]).status.code(), Some(0));
    // Unknown feet are refused, naming the file and the names.
    let o = strider(&[
        "db",
        "build",
        "--bvh",
        file.to_str().unwrap(),
        "--out",
        out_dir("bad_feet").to_str().unwrap(),
        "--feet",
        "Lefty,Righty",
    ]);
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(e.contains("anonymous_mm.bvh") && e.contains("Lefty"), "{e}");
}

/// The shared CMU captures, when present: each builds a database with no flag.
#[test]
fn shared_cmu_files_build_without_flags_when_present() {
    let dir = std::env::var_os("STRIDER_CMU_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/motions/cmu"));
    let Ok(entries) = std::fs::read_dir(&dir) else {
        eprintln!("skipped: no CMU captures in {}", dir.display());
        return;
    };
    let mut files: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "bvh"))
        .collect();
    files.sort();
    for f in &files {
        let (n, stderr) = build(&[f], &[], &out_dir(&format!("cmu_{}", f.file_name().unwrap().to_string_lossy())));
        assert!(n >= 2 && stderr.contains("CMU units"), "{}: {n}\n{stderr}", f.display());
        eprintln!("{}: {n} intervals", f.display());
    }
}

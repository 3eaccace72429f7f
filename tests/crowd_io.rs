//! Crowds through the command line: `strider gen CASE.xml --seed S` prints a SteerSuite test
//! case written here with every random draw made, as a text world that reads back to the same
//! crowd; bad cases are located errors with exit code 2.

mod common;

use std::path::PathBuf;

use common::{stderr, stdout, strider};
use strider::maps::{steersuite, text};

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("crowd-io-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A case of a fixed agent and a region of eight random agents around a wall, all seeking a
/// random target, after a comment and an XML declaration as the published cases have them.
const CASE: &str = r#"<!-- a comment before the declaration --><?xml version="1.0" ?>
<SteerBenchTestCase xmlns="http://www.magix.ucla.edu/steerbench">
  <header>
    <version>1.0</version>
    <name>fixture</name>
    <worldBounds><xmin>-20</xmin><xmax>20</xmax><ymin>0</ymin><ymax>0</ymax><zmin>-20</zmin><zmax>20</zmax></worldBounds>
  </header>
  <obstacle><xmin>-1</xmin><xmax>1</xmax><ymin>0</ymin><ymax>1</ymax><zmin>-5</zmin><zmax>5</zmax></obstacle>
  <agent>
    <name>lead</name>
    <initialConditions>
      <radius>0.5</radius>
      <position><x>-10</x><y>0</y><z>0</z></position>
      <direction><x>1</x><y>0</y><z>0</z></direction>
      <speed>0</speed>
    </initialConditions>
    <goalSequence>
      <seekStaticTarget>
        <targetLocation><x>10</x><y>0</y><z>0</z></targetLocation>
        <desiredSpeed>1.3</desiredSpeed>
        <timeDuration>100</timeDuration>
      </seekStaticTarget>
    </goalSequence>
  </agent>
  <agentRegion>
    <numAgents>8</numAgents>
    <regionBounds><xmin>-8</xmin><xmax>-2</xmax><ymin>0</ymin><ymax>0</ymax><zmin>-6</zmin><zmax>6</zmax></regionBounds>
    <initialConditions>
      <direction><random>true</random></direction>
      <radius>0.4</radius>
      <speed>0</speed>
    </initialConditions>
    <goalSequence>
      <seekStaticTarget>
        <targetLocation><random>true</random></targetLocation>
        <desiredSpeed>1.2</desiredSpeed>
        <timeDuration>200</timeDuration>
      </seekStaticTarget>
    </goalSequence>
  </agentRegion>
</SteerBenchTestCase>
"#;

#[test]
fn gen_prints_a_case_resolved_by_its_seed() {
    let dir = temp_dir("gen");
    let case = dir.join("fixture.xml");
    std::fs::write(&case, CASE).unwrap();
    let path = case.to_str().unwrap();
    let a = strider(&["gen", path, "--seed", "3"]);
    assert!(a.status.success(), "{}", stderr(&a));
    assert_eq!(strider(&["gen", path, "--seed", "3"]).stdout, a.stdout, "the same seed, the same world");
    assert_ne!(strider(&["gen", path, "--seed", "4"]).stdout, a.stdout, "another seed, other draws");
    let printed = text::parse(&stdout(&a), "printed.txt").unwrap();
    let read = steersuite::parse(CASE, "fixture.xml", 3).unwrap();
    assert_eq!(printed.crowd, read.crowd);
    assert_eq!(printed.obstacles, read.obstacles);
    assert_eq!(printed.crowd.as_ref().unwrap().agents.len(), 9);
    // The printed world prints back the same, through `gen` itself.
    let world = dir.join("world.txt");
    std::fs::write(&world, &a.stdout).unwrap();
    let again = strider(&["gen", world.to_str().unwrap()]);
    assert!(again.status.success(), "{}", stderr(&again));
    assert_eq!(stdout(&again).lines().skip(1).collect::<Vec<_>>(), stdout(&a).lines().skip(1).collect::<Vec<_>>());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_cases_exit_2_naming_file_line_and_column() {
    let dir = temp_dir("bad");
    let case = dir.join("bad.xml");
    std::fs::write(&case, CASE.replace("<speed>0</speed>\n    </initialConditions>\n    <goalSequence>\n      <seekStaticTarget>\n        <targetLocation><x>", "<speed>slow</speed>\n    </initialConditions>\n    <goalSequence>\n      <seekStaticTarget>\n        <targetLocation><x>")).unwrap();
    let o = strider(&["gen", case.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("bad.xml:15:7:"), "{}", stderr(&o));
    assert!(stderr(&o).contains("`slow`"), "{}", stderr(&o));
    std::fs::write(&case, &CASE[..CASE.len() / 2]).unwrap();
    let o = strider(&["gen", case.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    let last = CASE[..CASE.len() / 2].lines().count();
    assert!(stderr(&o).contains(&format!("bad.xml:{last}:")), "{}", stderr(&o));
    assert_eq!(strider(&["gen"]).status.code(), Some(2), "a map or --kind");
    let _ = std::fs::remove_dir_all(&dir);
}

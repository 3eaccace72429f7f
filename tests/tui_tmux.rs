//! End-to-end test of `strider tui` in a real terminal (DESIGN.md §6): the binary runs in a
//! detached tmux session of fixed size, keys are sent, and the captured pane is checked for
//! what a person would see. It needs tmux (`.ci/run` installs it); without tmux the test
//! fails unless `STRIDER_SKIP_TMUX=1` is set.

use std::process::{Command, Output};
use std::thread::sleep;
use std::time::{Duration, Instant};

/// A tmux server of its own (socket named after this process) with one session.
struct Tmux {
    socket: String,
}

impl Tmux {
    fn run(&self, args: &[&str]) -> Output {
        Command::new("tmux").arg("-L").arg(&self.socket).args(args).output().expect("tmux runs")
    }

    fn capture(&self) -> String {
        String::from_utf8_lossy(&self.run(&["capture-pane", "-p", "-t", "e2e"]).stdout).into_owned()
    }

    fn keys(&self, keys: &[&str]) {
        let mut args = vec!["send-keys", "-t", "e2e"];
        args.extend_from_slice(keys);
        assert!(self.run(&args).status.success());
    }

    /// Waits up to 15 s for the pane to satisfy `ok`; returns the last capture.
    fn wait_for(&self, what: &str, ok: impl Fn(&str) -> bool) -> String {
        let start = Instant::now();
        loop {
            let pane = self.capture();
            if ok(&pane) {
                return pane;
            }
            assert!(start.elapsed() < Duration::from_secs(15), "timed out waiting for {what}; the pane shows:\n{pane}");
            sleep(Duration::from_millis(100));
        }
    }
}

impl Drop for Tmux {
    fn drop(&mut self) {
        let _ = self.run(&["kill-server"]);
    }
}

/// The simulated time shown in the title line (` t 12.35 s`).
fn shown_time(pane: &str) -> Option<f64> {
    let line = pane.lines().next()?;
    let rest = &line[line.rfind(" t ")? + 3..];
    rest.split_whitespace().next()?.parse().ok()
}

#[test]
fn tui_in_tmux() {
    if Command::new("tmux").arg("-V").output().is_err() {
        if std::env::var("STRIDER_SKIP_TMUX").is_ok_and(|v| v == "1") {
            eprintln!("tmux is not installed: skipping the end-to-end test (STRIDER_SKIP_TMUX=1)");
            return;
        }
        panic!("tmux is not installed: install it (apt-get install -y tmux) or set STRIDER_SKIP_TMUX=1 to skip");
    }
    let bin = env!("CARGO_BIN_EXE_strider");
    let dir = env!("CARGO_MANIFEST_DIR");
    let tmux = Tmux { socket: format!("strider-e2e-{}", std::process::id()) };
    // After the view exits, the shell prints the exit code and stays, so the restored screen
    // can be checked.
    let cmd = format!("cd '{dir}' && '{bin}' tui maps/u_trap.rhai; echo \"strider exited: $?\"; sleep 60");
    let started = tmux.run(&["new-session", "-d", "-s", "e2e", "-x", "100", "-y", "30", &cmd]);
    assert!(started.status.success(), "tmux new-session failed: {}", String::from_utf8_lossy(&started.stderr));

    let pane = tmux.wait_for("the view", |p| p.contains("strider") && p.contains("Fuzzy inputs"));
    for want in ["u_trap", "autopilot", "Agent 1/1", "Fuzzy outputs", "Rules fired", "goal_angle", "? help"] {
        assert!(pane.contains(want), "missing {want:?} in\n{pane}");
    }

    tmux.keys(&["?"]);
    let pane = tmux.wait_for("the help overlay", |p| p.contains("pause / resume"));
    assert!(pane.contains("new random world"), "{pane}");
    tmux.keys(&["Escape"]);
    tmux.wait_for("the help to close", |p| !p.contains("pause / resume"));

    tmux.keys(&["Space"]);
    let pane = tmux.wait_for("pause", |p| p.contains("paused"));
    let t0 = shown_time(&pane).expect("time in the title");
    sleep(Duration::from_millis(400));
    assert_eq!(shown_time(&tmux.capture()), Some(t0), "time moved while paused");

    tmux.keys(&["."]);
    let pane = tmux.wait_for("one step", |p| shown_time(p).is_some_and(|t| t > t0));
    let t1 = shown_time(&pane).unwrap();
    assert!((t1 - t0 - 0.05).abs() < 1e-6, "one step should advance 0.05 s: {t0} -> {t1}");

    tmux.keys(&["q"]);
    let pane = tmux.wait_for("the exit", |p| p.contains("strider exited"));
    assert!(pane.contains("strider exited: 0"), "{pane}");
    assert!(!pane.contains("Fuzzy inputs"), "the alternate screen was not left:\n{pane}");
}

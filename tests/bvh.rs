//! BVH import and export against hand-written files: forward kinematics of a known frame
//! computed by hand, channel order, located errors, frame-count warnings, scale, round trips
//! through `write`, and robustness to mutated input.

use glam::{DQuat, DVec3};
use proptest::prelude::*;
use strider::anim::bvh::{self, Bvh, BvhOptions};
use strider::anim::{Channel, Pose, angle_between};

const WALKER: &str = include_str!("fixtures/bvh/walker.bvh");
/// The same file with CRLF line ends, tabs and runs of spaces, blank lines, `End site`, braces
/// on name lines and a frame time written `.04`.
const WALKER_CRLF: &str = include_str!("fixtures/bvh/walker_crlf.bvh");

fn parse(text: &str) -> Bvh {
    bvh::parse(text, "walker.bvh", "walker", &BvhOptions::default()).expect("valid BVH")
}

fn error(text: &str) -> String {
    bvh::parse(text, "walker.bvh", "walker", &BvhOptions::default()).expect_err("invalid BVH").to_string()
}

fn close(a: DVec3, b: DVec3, tolerance: f64) -> bool {
    (a - b).length() < tolerance
}

/// `text` with `from` (which must occur exactly once) replaced by `to`.
fn edit(text: &str, from: &str, to: &str) -> String {
    assert_eq!(text.matches(from).count(), 1, "'{from}' must occur once");
    text.replacen(from, to, 1)
}

#[test]
fn hierarchy_is_read_in_file_order_in_the_z_up_frame() {
    let bvh = parse(WALKER);
    assert!(bvh.warnings.is_empty(), "{:?}", bvh.warnings);
    let joints = bvh.skeleton.joints();
    let names: Vec<&str> = joints.iter().map(|j| j.name.as_str()).collect();
    assert_eq!(names, ["Hips", "Spine", "Left Leg", "LeftShin", "RightLeg"]);
    let parents: Vec<Option<usize>> = joints.iter().map(|j| j.parent).collect();
    assert_eq!(parents, [None, Some(0), Some(0), Some(2), Some(0)]);
    // BVH (x, y, z) is ours (z, x, y): BVH up (y) becomes our z, BVH x our y.
    assert_eq!(joints[0].offset, DVec3::new(0.0, 0.0, 1.0));
    assert_eq!(joints[2].offset, DVec3::new(0.0, 0.1, 0.0));
    assert_eq!(joints[1].end_site, Some(DVec3::new(0.0, 0.0, 0.3)));
    assert_eq!(joints[2].end_site, None);
    assert_eq!(joints[3].end_site, Some(DVec3::new(0.0, 0.0, -0.4)));
    use Channel::*;
    // Xposition Yposition Zposition Zrotation Xrotation Yrotation, relabelled.
    assert_eq!(joints[0].channels, [YPosition, ZPosition, XPosition, XRotation, YRotation, ZRotation]);
    // Yrotation Xrotation Zrotation.
    assert_eq!(joints[1].channels, [ZRotation, YRotation, XRotation]);
    assert_eq!(joints[4].channels, [YRotation, XRotation]);
    assert_eq!(bvh.clip.name, "walker");
    assert_eq!(bvh.clip.frame_time, 0.04);
    assert_eq!(bvh.clip.frames.len(), 2);
}

#[test]
fn forward_kinematics_of_a_known_frame_matches_hand_computation() {
    let bvh = parse(WALKER);
    let s = &bvh.skeleton;
    // Frame 0 is the bind pose at the root offset.
    let bind = s.positions(&bvh.clip.frames[0]);
    let expected_bind = [(0.0, 0.0, 1.0), (0.0, 0.0, 1.5), (0.0, 0.1, 1.0), (0.0, 0.1, 0.5), (0.0, -0.1, 1.0)];
    for (p, e) in bind.iter().zip(expected_bind) {
        assert!(close(*p, e.into(), 1e-12), "{p} vs {e:?}");
    }
    // Frame 1, worked out by hand in the Z-up frame:
    // Hips: BVH offset (0, 1, 0) + (1, 0, 2) = (1, 1, 2), ours (2, 1, 1); Yrotation 90 is a
    // quarter turn about our Z (x → y, y → −x).
    // Spine: (0, 0, 0.5) up from the hips; Xrotation 90 turns its tip (BVH (0, 0.3, 0)) to
    // BVH (0, 0, 0.3) = ours (0.3, 0, 0), and the hips' yaw to (0, 0.3, 0).
    // Left Leg: ours (0, 0.1, 0) yawed to (−0.1, 0, 0). Zrotation 90 · Xrotation 90 takes the
    // shin offset BVH (0, −0.5, 0) to BVH (0, 0, −0.5) = ours (−0.5, 0, 0), yawed (0, −0.5, 0).
    // LeftShin: Xrotation −90 takes its tip BVH (0, −0.4, 0) to BVH (0, 0, 0.4); the leg's
    // rotation takes that to BVH (0.4, 0, 0) = ours (0, 0.4, 0), yawed (−0.4, 0, 0).
    // RightLeg: ours (0, −0.1, 0) yawed to (0.1, 0, 0); its tip hangs 0.9 straight down.
    let pose = &bvh.clip.frames[1];
    assert_eq!(pose.root, DVec3::new(2.0, 1.0, 1.0));
    let mut globals = Vec::new();
    s.globals(pose, &mut globals);
    let expected = [(2.0, 1.0, 1.0), (2.0, 1.0, 1.5), (1.9, 1.0, 1.0), (1.9, 0.5, 1.0), (2.1, 1.0, 1.0)];
    let expected_tips = [(2.0, 1.0, 1.0), (2.0, 1.3, 1.5), (1.9, 1.0, 1.0), (1.5, 0.5, 1.0), (2.1, 1.0, 0.1)];
    for i in 0..s.len() {
        assert!(close(globals[i].0, expected[i].into(), 1e-12), "joint {i}: {} vs {:?}", globals[i].0, expected[i]);
        let tip = s.tip(&globals, i);
        assert!(close(tip, expected_tips[i].into(), 1e-12), "tip {i}: {tip} vs {:?}", expected_tips[i]);
    }
    assert_eq!(s.positions(pose), globals.iter().map(|g| g.0).collect::<Vec<_>>());
}

#[test]
fn crlf_tabs_and_odd_spacing_read_the_same() {
    assert!(WALKER_CRLF.contains("\r\n"), "the fixture must keep its CRLF line ends");
    let (a, b) = (parse(WALKER), parse(WALKER_CRLF));
    assert!(b.warnings.is_empty(), "{:?}", b.warnings);
    assert_eq!(a.skeleton, b.skeleton);
    assert_eq!(a.clip, b.clip);
    // Converting the clean fixture to CRLF changes nothing either.
    assert_eq!(parse(&WALKER.replace('\n', "\r\n")).clip, a.clip);
}

#[test]
fn channel_order_is_the_order_of_intrinsic_rotations() {
    let file = |channels: &str| {
        format!(
            "HIERARCHY\nROOT r\n{{\n\tOFFSET 0 0 0\n\tCHANNELS 2 {channels}\n\tEnd Site\n\t{{\n\t\tOFFSET 0 1 0\n\t}}\n}}\n\
             MOTION\nFrames: 1\nFrame Time: 0.1\n90 90\n"
        )
    };
    let tip = |channels: &str| {
        let bvh = parse(&file(channels));
        let mut g = Vec::new();
        bvh.skeleton.globals(&bvh.clip.frames[0], &mut g);
        bvh.skeleton.tip(&g, 0)
    };
    // Rz(90)·Rx(90) takes BVH up (0, 1, 0) to (0, 0, 1) (BVH), ours (1, 0, 0).
    assert!(close(tip("Zrotation Xrotation"), DVec3::X, 1e-12));
    // Rx(90)·Rz(90) takes it to (−1, 0, 0) (BVH), ours (0, −1, 0).
    assert!(close(tip("Xrotation Zrotation"), -DVec3::Y, 1e-12));
}

#[test]
fn scale_multiplies_lengths_on_import_and_divides_on_export() {
    let unit = parse(WALKER);
    let opts = BvhOptions { scale: 2.5 };
    let scaled = bvh::parse(WALKER, "walker.bvh", "walker", &opts).unwrap();
    for (a, b) in unit.skeleton.joints().iter().zip(scaled.skeleton.joints()) {
        assert!(close(b.offset, a.offset * 2.5, 1e-12));
        assert_eq!(a.end_site.map(|e| e * 2.5), b.end_site);
    }
    for (a, b) in unit.clip.frames.iter().zip(&scaled.clip.frames) {
        assert!(close(b.root, a.root * 2.5, 1e-12));
        assert_eq!(a.rotations, b.rotations);
    }
    assert_eq!(scaled.clip.frames[1].root, DVec3::new(5.0, 2.5, 2.5));
    // Written with the same scale, the file has its original numbers again.
    let text = bvh::write(&scaled.skeleton, &scaled.clip, &opts);
    assert!(text.contains("\tJOINT Spine\n\t{\n\t\tOFFSET 0 0.5 0\n"), "{text}");
    assert!(text.contains("\n1 0 2 0 0 90 "), "{text}");
    // Written in metres, it is 2.5 times larger.
    let metres = bvh::write(&scaled.skeleton, &scaled.clip, &BvhOptions::default());
    assert!(metres.contains("\t\tOFFSET 0 1.25 0\n"), "{metres}");
    assert!(metres.contains("\n2.5 0 5 0 0 90 "), "{metres}");
}

#[test]
fn writing_the_fixture_reproduces_it() {
    let bvh = parse(WALKER);
    let text = bvh::write(&bvh.skeleton, &bvh.clip, &BvhOptions::default());
    let (got, want): (Vec<&str>, Vec<&str>) = (text.lines().collect(), WALKER.lines().collect());
    assert_eq!(got.len(), want.len(), "{text}");
    for (g, w) in got.iter().zip(&want) {
        let tabs = |s: &str| s.len() - s.trim_start_matches('\t').len();
        assert_eq!(tabs(g), tabs(w), "indentation of '{g}'");
        let (gt, wt): (Vec<&str>, Vec<&str>) = (g.split_whitespace().collect(), w.split_whitespace().collect());
        assert_eq!(gt.len(), wt.len(), "'{g}' vs '{w}'");
        for (a, b) in gt.iter().zip(&wt) {
            let same_number = matches!((a.parse::<f64>(), b.parse::<f64>()), (Ok(x), Ok(y)) if x == y);
            assert!(a == b || same_number, "'{g}' vs '{w}'");
        }
    }
    // The frame with angles at gimbal lock (Yrotation Xrotation Zrotation = 0 90 0, and
    // Zrotation Xrotation Yrotation = 90 90 0) comes back with the same angles.
    assert!(text.ends_with("\n1 0 2 0 0 90 0 90 0 90 90 0 -90 0 0\n"), "{text}");
}

/// A chain using every three-axis order, a two-axis and a one-axis joint, with frames of
/// pseudo-random angles (some at gimbal lock) and root motion.
fn every_order_file() -> String {
    const ORDERS: [&str; 6] = ["X Y Z", "X Z Y", "Y X Z", "Y Z X", "Z X Y", "Z Y X"];
    let channels = |order: &str| order.split(' ').map(|a| format!("{a}rotation")).collect::<Vec<_>>().join(" ");
    let mut text = String::from("HIERARCHY\nROOT Root\n{\n\tOFFSET 0.1 0.9 -0.2\n");
    text += &format!("\tCHANNELS 6 Zposition Xposition Yposition {}\n", channels(ORDERS[0]));
    let mut n_channels = 6;
    let mut joints: Vec<String> = ORDERS[1..].iter().map(|o| format!("CHANNELS 3 {}", channels(o))).collect();
    joints.push("CHANNELS 2 Zrotation Yrotation".into());
    joints.push("CHANNELS 1 Yrotation".into());
    for (i, j) in joints.iter().enumerate() {
        text += &format!("JOINT J{i}\n{{\nOFFSET 0.05 0.3 {}\n{j}\n", 0.01 * i as f64);
        n_channels += j.split(' ').nth(1).unwrap().parse::<usize>().unwrap();
    }
    text += "End Site\n{\nOFFSET 0 0.2 0.1\n}\n";
    text += &"}\n".repeat(joints.len() + 1);
    let frames = 40;
    text += &format!("MOTION\nFrames: {frames}\nFrame Time: 0.0083333\n");
    let mut state = 0x2545_F491_4F6C_DD1Du64;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64 * 360.0 - 180.0
    };
    for f in 0..frames {
        let values: Vec<String> = (0..n_channels)
            .map(|c| match (f % 4, c % 3) {
                // Some frames put every middle angle at gimbal lock.
                (0, 1) if c > 3 => "90".to_string(),
                (1, 1) if c > 3 => "-90".to_string(),
                _ if c < 3 => format!("{:.4}", next() / 100.0),
                _ => format!("{:.5}", next()),
            })
            .collect();
        text += &values.join(" ");
        text += "\n";
    }
    text
}

fn assert_same_motion(s: &strider::anim::Skeleton, a: &[Pose], b: &[Pose]) {
    assert_eq!(a.len(), b.len());
    for (pa, pb) in a.iter().zip(b) {
        assert!(close(pa.root, pb.root, 1e-6), "{} vs {}", pa.root, pb.root);
        for (qa, qb) in pa.rotations.iter().zip(&pb.rotations) {
            assert!(angle_between(*qa, *qb) < 1e-6, "{qa} vs {qb}");
        }
        for (xa, xb) in s.positions(pa).iter().zip(s.positions(pb)) {
            assert!(close(*xa, xb, 1e-6), "{xa} vs {xb}");
        }
    }
}

#[test]
fn parse_write_parse_round_trips_every_rotation_order() {
    let text = every_order_file();
    for scale in [1.0, 0.056444] {
        let opts = BvhOptions { scale };
        let a = bvh::parse(&text, "orders.bvh", "o", &opts).unwrap();
        assert_eq!(a.clip.frames.len(), 40);
        // The input angles are not canonical (middle angles beyond ±90°, first and last
        // anywhere), so the written angles differ while the rotations agree.
        let written = bvh::write(&a.skeleton, &a.clip, &opts);
        let b = bvh::parse(&written, "orders.bvh", "o", &opts).unwrap();
        assert!(b.warnings.is_empty());
        assert_eq!(b.skeleton.len(), a.skeleton.len());
        for (ja, jb) in a.skeleton.joints().iter().zip(b.skeleton.joints()) {
            assert_eq!((&ja.name, ja.parent, &ja.channels), (&jb.name, jb.parent, &jb.channels));
            assert!(close(ja.offset, jb.offset, 1e-9));
        }
        assert_same_motion(&a.skeleton, &a.clip.frames, &b.clip.frames);
        // Rotations that are not products of a joint's rotation channels still export without
        // NaN and, for three-axis joints, exactly.
        let mut clip = a.clip.clone();
        for (k, pose) in clip.frames.iter_mut().enumerate() {
            for (i, q) in pose.rotations.iter_mut().enumerate().take(6) {
                *q = DQuat::from_axis_angle(DVec3::new(1.0, -2.0, 0.5 + i as f64).normalize(), 0.3 * k as f64);
            }
        }
        let c = bvh::parse(&bvh::write(&a.skeleton, &clip, &opts), "orders.bvh", "o", &opts).unwrap();
        assert_same_motion(&a.skeleton, &clip.frames, &c.clip.frames);
    }
}

#[test]
fn frame_count_mismatches_keep_every_frame_and_warn() {
    let more = parse(&edit(WALKER, "Frames: 2", "Frames: 1"));
    assert_eq!(more.clip.frames.len(), 2);
    assert_eq!(more.warnings, ["walker.bvh:40:1: 'Frames: 1' but 2 frame lines follow; all are kept"]);
    let fewer = parse(&edit(WALKER, "Frames: 2", "Frames: 5"));
    assert_eq!(fewer.clip.frames.len(), 2);
    assert_eq!(fewer.warnings, ["walker.bvh:40:1: 'Frames: 5' but only 2 frame lines follow"]);
    // Blank lines between and after frames are not frames.
    let spaced = parse(&edit(WALKER, "0 0 0\n1 0 2", "0 0 0\n\n \t\n1 0 2").replace("0 0\n", "0 0\n\n\n"));
    assert!(spaced.warnings.is_empty());
    assert_eq!(spaced.clip, parse(WALKER).clip);
}

#[test]
fn non_root_position_channels_are_ignored_with_one_warning() {
    let text = edit(WALKER, "CHANNELS 1 Xrotation", "CHANNELS 4 Xposition Xrotation Yposition Zposition");
    let text = edit(&text, " -90 0 0\n", " 5 -90 6 7 0 0\n");
    let text = edit(&text, "\n0 0 0 0 0 0 0 0 0 0 0 0 0 0 0\n", "\n0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0\n");
    let bvh = parse(&text);
    assert_eq!(bvh.warnings.len(), 1, "{:?}", bvh.warnings);
    assert!(bvh.warnings[0].starts_with("walker.bvh:22:4: joint 'LeftShin' has position channels"));
    let plain = parse(WALKER);
    assert_eq!(bvh.clip, plain.clip);
    // The channels are kept, so the file writes back with the same layout (positions as 0).
    let text = bvh::write(&bvh.skeleton, &bvh.clip, &BvhOptions::default());
    assert!(text.contains("CHANNELS 4 Xposition Xrotation Yposition Zposition"));
    assert!(text.ends_with(" 0 -90 0 0 0 0\n"), "{text}");
}

#[test]
fn errors_name_file_line_and_column() {
    let cases = [
        (edit(WALKER, "OFFSET 0.0 0.5 0.0", "OFFSET 0.0 0.5x 0.0"), "walker.bvh:8:14: bad number '0.5x'"),
        (
            edit(WALKER, "Yrotation Xrotation Zrotation", "Yrotation Xrotatoin Zrotation"),
            "walker.bvh:9:24: unknown channel 'Xrotatoin'",
        ),
        (edit(WALKER, "JOINT RightLeg", "JOINT Spine"), "walker.bvh:29:8: duplicate joint name 'Spine'"),
        (edit(WALKER, "JOINT Spine\n\t{\n", "JOINT Spine\n"), "walker.bvh:7:3: expected '{', found 'OFFSET'"),
        (edit(WALKER, "\t}\n}\nMOTION", "\t}\nMOTION"), "walker.bvh:38:1: unexpected 'MOTION' in joint 'Hips'"),
        (edit(WALKER, "CHANNELS 1 Xrotation", "CHANNELS x Xrotation"), "walker.bvh:22:13: bad channel count 'x'"),
        (edit(WALKER, "Frames: 2", "Frames: two"), "walker.bvh:40:9: bad frame count 'two'"),
        (edit(WALKER, "Time: 0.04", "Time: inf"), "walker.bvh:41:13: non-finite number 'inf'"),
        (
            edit(WALKER, "Time: 0.04", "Time: -0.04"),
            "walker.bvh:41:13: frame time must be positive and at most 1 s, not -0.04",
        ),
        (
            edit(WALKER, "Time: 0.04", "Time: 100"),
            "walker.bvh:41:13: frame time must be positive and at most 1 s, not 100",
        ),
        (edit(WALKER, "0 0 -90 0 0", "0 0 1e308 0 0"), "walker.bvh:43:29: number '1e308' is beyond ±1e6"),
        (edit(WALKER, "OFFSET 0.0 0.5 0.0", "OFFSET 0.0 1e308 0.0"), "walker.bvh:8:14: number '1e308' is beyond ±1e6"),
        (edit(WALKER, "0 0 -90 0 0", "0 0 NaN 0 0"), "walker.bvh:43:29: non-finite number 'NaN'"),
        (edit(WALKER, "-90 0 0\n", "-90 0 0 7\n"), "walker.bvh:43:37: frame line has more than 15 values"),
        (edit(WALKER, "-90 0 0\n", "-90 0\n"), "walker.bvh:43:35: frame line has 14 values, expected 15"),
        (edit(WALKER, "1 0 2 0 0 90 0", "1 0 2 0 0 9e0 x"), "walker.bvh:43:15: bad number 'x'"),
    ];
    for (text, want) in &cases {
        assert_eq!(&error(text), want);
    }
}

#[test]
fn a_hierarchy_100000_joints_deep_is_refused_at_once() {
    let n = 100_000;
    let mut text = String::from("HIERARCHY\nROOT j0\n{\nOFFSET 0 0 0\nCHANNELS 3 Xposition Yposition Zposition\n");
    for i in 1..n {
        text += &format!("JOINT j{i}\n{{\nOFFSET 0 1 0\n");
    }
    text += &"}\n".repeat(n);
    text += "MOTION\nFrames: 1\nFrame Time: 0.1\n0 0 0\n";
    let err = error(&text);
    assert_eq!(err, format!("walker.bvh:{}:1: joint hierarchy deeper than 256 levels", 6 + 3 * 255), "{err}");
}

#[test]
fn truncated_files_and_missing_sections_are_located_errors() {
    let cut = |marker: &str| {
        let at = WALKER.find(marker).expect("marker") + marker.len();
        error(&WALKER[..at])
    };
    assert_eq!(cut("JOINT LeftShin\n\t\t{\n"), "walker.bvh:21:1: unexpected end of file, expected '}'");
    assert_eq!(cut("OFFSET 0.0 -0.5"), "walker.bvh:21:19: unexpected end of file, expected a number");
    assert_eq!(cut("CHANNELS 3 Zrotation"), "walker.bvh:18:23: unexpected end of file, expected a channel name");
    assert_eq!(cut("\n}\n"), "walker.bvh:39:1: no MOTION section");
    assert_eq!(cut("Frame Time:"), "walker.bvh:41:12: unexpected end of file, expected a frame time");
    assert_eq!(cut("1 0 2 0 0 90"), "walker.bvh:43:14: frame line has 6 values, expected 15");
    assert_eq!(cut("Frame Time: 0.04\n"), "walker.bvh:40:9: the file has no frames");
    // Frame lines after 'Frames: 0' are still frames.
    let zero = parse(&edit(WALKER, "Frames: 2", "Frames: 0"));
    assert_eq!(zero.clip.frames.len(), 2);
    assert_eq!(zero.warnings, ["walker.bvh:40:1: 'Frames: 0' but 2 frame lines follow; all are kept"]);
}

/// Bytes worth planting in a BVH text to break it in interesting ways.
fn nasty_byte() -> impl Strategy<Value = u8> {
    prop_oneof![prop::sample::select(b"{}\n\r\t -.e9x0".to_vec()), any::<u8>(),]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn parse_never_panics_on_mutated_files(
        crlf in any::<bool>(),
        cut in prop_oneof![Just(1.0), 0.0..=1.0f64],
        edits in prop::collection::vec((0.0..1.0f64, nasty_byte(), 0usize..3), 0..5),
    ) {
        let mut bytes = if crlf { WALKER_CRLF } else { WALKER }.as_bytes().to_vec();
        for (at, byte, kind) in edits {
            let i = ((at * bytes.len() as f64) as usize).min(bytes.len() - 1);
            match kind {
                0 => bytes[i] = byte,
                1 => bytes.insert(i, byte),
                _ => {
                    bytes.remove(i);
                }
            }
        }
        bytes.truncate((cut * bytes.len() as f64) as usize);
        let text = String::from_utf8_lossy(&bytes);
        if let Ok(bvh) = bvh::parse(&text, "m.bvh", "m", &BvhOptions::default()) {
            // Whatever is accepted is a usable clip.
            prop_assert!(!bvh.clip.frames.is_empty());
            prop_assert!(bvh.clip.frame_time > 0.0 && bvh.clip.frame_time.is_finite());
            for pose in &bvh.clip.frames {
                prop_assert_eq!(pose.rotations.len(), bvh.skeleton.len());
                prop_assert!(pose.root.is_finite());
                prop_assert!(pose.rotations.iter().all(|q| q.is_finite() && (q.length() - 1.0).abs() < 1e-9));
            }
            let again = bvh::parse(&bvh::write(&bvh.skeleton, &bvh.clip, &BvhOptions::default()), "m", "m", &BvhOptions::default());
            prop_assert!(again.is_ok(), "{:?}", again);
        }
    }
}

//! BVH (Biovision Hierarchy) motion capture files for the animation database (seed 000 §3.2,
//! DESIGN.md §3): [`parse`] reads a hierarchy and its motion into a [`Skeleton`] and a [`Clip`],
//! [`write`] produces standard BVH text from them.
//!
//! Axes: BVH files are Y up; this crate is Z up, X forward, Y to the left. A BVH vector
//! (x, y, z) is ours (z, x, y). That cyclic permutation is a proper rotation, so angles keep
//! their sign: BVH `Xrotation` turns about our Y, `Yrotation` about our Z and `Zrotation` about
//! our X; `Xposition` moves along our Y, `Yposition` along our Z and `Zposition` along our X.
//! [`Joint::channels`] hold the relabelled channels in file order and export converts them back
//! exactly. Lengths are multiplied by [`BvhOptions::scale`] on import and divided by it on
//! export.
//!
//! Semantics: angles are degrees and a joint's rotation channels compose in file order as
//! intrinsic rotations (`Zrotation Xrotation Yrotation` with angles a, b, c is Rz(a)·Rx(b)·Ry(c)).
//! The root's position channels are added to its `OFFSET`. Joints below the root only rotate,
//! so their position channels are kept in [`Joint::channels`] but their values are ignored (with
//! a warning) and exported as zero.
//!
//! The parser is iterative and bounded by the input: any text gives a skeleton and clip or a
//! [`SourceError`] naming `file:line:col`.

use std::collections::HashSet;
use std::fmt::{self, Write as _};

use glam::{DMat3, DQuat, DVec3};

use super::clip::Clip;
use super::skeleton::{Channel, Joint, Pose, Skeleton, twist};
use crate::diagnostic::SourceError;

/// Deepest joint hierarchy accepted (a human skeleton is about 10 deep, hands included).
pub const MAX_DEPTH: usize = 256;

/// Most joints accepted in one file.
pub const MAX_JOINTS: usize = 4096;

/// Largest magnitude of any number in a file (offsets, positions, angles in degrees).
pub const MAX_VALUE: f64 = 1e6;

/// Longest frame time accepted, seconds.
pub const MAX_FRAME_TIME_S: f64 = 1.0;

/// Import and export settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BvhOptions {
    /// Metres per file unit: lengths are multiplied by it on import and divided by it on export
    /// (1.0 for files in metres; 0.056444 for the CMU database).
    pub scale: f64,
}

impl Default for BvhOptions {
    fn default() -> Self {
        BvhOptions { scale: 1.0 }
    }
}

/// An imported BVH file.
#[derive(Debug, Clone, PartialEq)]
pub struct Bvh {
    /// The hierarchy, joints in file order.
    pub skeleton: Skeleton,
    /// The motion, one pose per frame line.
    pub clip: Clip,
    /// Problems that did not stop the import, each as `file:line:col: message`.
    pub warnings: Vec<String>,
}

/// Reads BVH `text` (named `file` in errors and warnings) into a skeleton and a clip called
/// `clip_name`.
pub fn parse(text: &str, file: &str, clip_name: &str, options: &BvhOptions) -> Result<Bvh, SourceError> {
    let scale = options.scale;
    if !(scale.is_finite() && scale > 0.0) {
        return Err(SourceError::new(file, 0, 0, format!("scale must be positive and finite, not {scale}")));
    }
    let mut cur = Cursor { text, file, pos: 0, line: 1, col: 1 };
    let mut warnings = Vec::new();
    let joints = parse_hierarchy(&mut cur, scale, &mut warnings)?;
    let (frame_time, frames) = parse_motion(&mut cur, &joints, scale, &mut warnings)?;
    let skeleton = Skeleton::new(joints).map_err(|e| SourceError::new(file, 0, 0, e.to_string()))?;
    let clip = Clip { name: clip_name.to_string(), frame_time, frames };
    Ok(Bvh { skeleton, clip, warnings })
}

/// BVH text for `clip` played on `skeleton`: tab-indented hierarchy, then one line per frame.
/// Lengths are divided by `options.scale`. Each rotation is decomposed into its joint's rotation
/// channels: exactly for three axes in any order (the middle angle in [-90°, 90°], the last 0 at
/// gimbal lock); for one or two axes exactly when the rotation is such a product, otherwise the
/// closest swing about the first axis and the remaining twist about the second. Position channels
/// of joints other than the root are written as 0.
pub fn write(skeleton: &Skeleton, clip: &Clip, options: &BvhOptions) -> String {
    let mut out = String::new();
    write_into(&mut out, skeleton, clip, options.scale).expect("formatting into a String cannot fail");
    out
}

// ---------------------------------------------------------------------------------------------
// Axes and channels

/// A BVH vector in this crate's frame.
fn from_bvh(v: DVec3) -> DVec3 {
    DVec3::new(v.z, v.x, v.y)
}

/// A vector of this crate's frame in the BVH frame.
fn to_bvh(v: DVec3) -> DVec3 {
    DVec3::new(v.y, v.z, v.x)
}

/// BVH channel names and the channels they denote in this crate's frame.
const CHANNEL_NAMES: [(&str, Channel); 6] = [
    ("Xposition", Channel::YPosition),
    ("Yposition", Channel::ZPosition),
    ("Zposition", Channel::XPosition),
    ("Xrotation", Channel::YRotation),
    ("Yrotation", Channel::ZRotation),
    ("Zrotation", Channel::XRotation),
];

/// The channel a BVH channel name (any letter case) denotes, relabelled into this crate's frame.
fn channel_from_name(name: &str) -> Option<Channel> {
    CHANNEL_NAMES.iter().find(|(n, _)| n.eq_ignore_ascii_case(name)).map(|&(_, c)| c)
}

/// The BVH name of a channel of this crate's frame.
fn channel_name(channel: Channel) -> &'static str {
    CHANNEL_NAMES.iter().find(|&&(_, c)| c == channel).map_or("", |&(n, _)| n)
}

/// Index (0, 1, 2 for X, Y, Z, in this crate's frame) of the axis a channel moves along or turns
/// about.
fn axis(channel: Channel) -> usize {
    match channel {
        Channel::XPosition | Channel::XRotation => 0,
        Channel::YPosition | Channel::YRotation => 1,
        Channel::ZPosition | Channel::ZRotation => 2,
    }
}

// ---------------------------------------------------------------------------------------------
// Tokens

/// A position in the text that tracks its line and column (1-based, in characters).
#[derive(Clone)]
struct Cursor<'a> {
    text: &'a str,
    file: &'a str,
    pos: usize,
    line: usize,
    col: usize,
}

/// A whitespace-separated word, or a lone brace.
#[derive(Clone, Copy)]
struct Token<'a> {
    text: &'a str,
    line: usize,
    col: usize,
}

impl<'a> Cursor<'a> {
    /// Moves `bytes` bytes on, counting lines and columns.
    fn advance(&mut self, bytes: usize) {
        for c in self.text[self.pos..self.pos + bytes].chars() {
            if c == '\n' {
                self.line += 1;
                self.col = 1;
            } else {
                self.col += 1;
            }
        }
        self.pos += bytes;
    }

    /// The next token, or `None` at the end of the text (the cursor then sits at the end).
    fn next(&mut self) -> Option<Token<'a>> {
        let rest = &self.text[self.pos..];
        self.advance(rest.len() - rest.trim_start().len());
        let rest = &self.text[self.pos..];
        let first = rest.chars().next()?;
        let len = if matches!(first, '{' | '}') {
            1
        } else {
            rest.find(|c: char| c.is_whitespace() || c == '{' || c == '}').unwrap_or(rest.len())
        };
        let token = Token { text: &rest[..len], line: self.line, col: self.col };
        self.advance(len);
        Some(token)
    }

    /// The rest of the current line, trimmed, as a token; the cursor moves to the end of the line.
    fn rest_of_line(&mut self) -> Token<'a> {
        let rest = &self.text[self.pos..];
        let line = &rest[..rest.find('\n').unwrap_or(rest.len())];
        let lead = line.len() - line.trim_start().len();
        self.advance(lead);
        let token = Token { text: line.trim(), line: self.line, col: self.col };
        self.advance(line.len() - lead);
        token
    }

    /// An error at `token`.
    fn error_at(&self, token: Token, message: impl Into<String>) -> SourceError {
        SourceError::new(self.file, token.line, token.col, message)
    }

    /// An error at the cursor.
    fn error_here(&self, message: impl Into<String>) -> SourceError {
        SourceError::new(self.file, self.line, self.col, message)
    }

    /// The next token; at the end of the text, an error saying what was `expected`.
    fn expect_any(&mut self, expected: &str) -> Result<Token<'a>, SourceError> {
        self.next().ok_or_else(|| self.error_here(format!("unexpected end of file, expected {expected}")))
    }

    /// The next token, which must be `keyword` (any letter case).
    fn expect(&mut self, keyword: &str) -> Result<Token<'a>, SourceError> {
        let token = self.expect_any(&format!("'{keyword}'"))?;
        if token.text.eq_ignore_ascii_case(keyword) {
            Ok(token)
        } else {
            Err(self.error_at(token, format!("expected '{keyword}', found '{}'", shown(token.text))))
        }
    }

    /// The next token as a finite number.
    fn number(&mut self, expected: &str) -> Result<f64, SourceError> {
        let token = self.expect_any(expected)?;
        number(token.text).map_err(|m| self.error_at(token, m))
    }

    /// Three numbers: a BVH vector, converted to this crate's frame and scaled.
    fn vector(&mut self, scale: f64) -> Result<DVec3, SourceError> {
        let mut v = DVec3::ZERO;
        for i in 0..3 {
            v[i] = self.number("a number")?;
        }
        let v = from_bvh(v) * scale;
        if v.is_finite() { Ok(v) } else { Err(self.error_here("offset out of range after scaling")) }
    }
}

/// A finite number, or why the text is not one.
fn number(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(v) if v.abs() <= MAX_VALUE => Ok(v),
        Ok(v) if v.is_finite() => Err(format!("number '{}' is beyond ±{MAX_VALUE:e}", shown(text))),
        Ok(_) => Err(format!("non-finite number '{}'", shown(text))),
        Err(_) => Err(format!("bad number '{}'", shown(text))),
    }
}

/// `text` cut to a length fit for a message.
fn shown(text: &str) -> String {
    const MAX: usize = 40;
    match text.char_indices().nth(MAX) {
        Some((at, _)) => format!("{}…", &text[..at]),
        None => text.to_string(),
    }
}

/// The whitespace-separated fields of a line with their 1-based columns.
fn fields(line: &str) -> impl Iterator<Item = (usize, &str)> {
    let mut col = 1;
    let mut start: Option<(usize, usize)> = None;
    let mut chars = line.char_indices().chain(std::iter::once((line.len(), ' ')));
    std::iter::from_fn(move || {
        for (i, c) in chars.by_ref() {
            let here = col;
            col += 1;
            match (c.is_whitespace(), start) {
                (false, None) => start = Some((i, here)),
                (true, Some((s, s_col))) => {
                    start = None;
                    return Some((s_col, &line[s..i]));
                }
                _ => {}
            }
        }
        None
    })
}

// ---------------------------------------------------------------------------------------------
// Hierarchy

/// What the parser knows about a joint being read.
struct Seen {
    offset: bool,
    channels: bool,
}

/// `HIERARCHY` … up to the root's closing brace: the joints in file order.
fn parse_hierarchy<'a>(
    cur: &mut Cursor<'a>,
    scale: f64,
    warnings: &mut Vec<String>,
) -> Result<Vec<Joint>, SourceError> {
    cur.expect("HIERARCHY")?;
    cur.expect("ROOT")?;
    let mut joints: Vec<Joint> = Vec::new();
    let mut seen: Vec<Seen> = Vec::new();
    let mut names = HashSet::new();
    // Joints whose opening brace has been read and whose closing brace has not, innermost last.
    let mut open = vec![begin_joint(cur, None, &mut joints, &mut names)?];
    seen.push(Seen { offset: false, channels: false });
    while let Some(&j) = open.last() {
        let token = cur.expect_any("'}'")?;
        let keyword = token.text.to_ascii_uppercase();
        match keyword.as_str() {
            "OFFSET" => {
                if seen[j].offset {
                    return Err(cur.error_at(token, format!("second OFFSET in joint '{}'", shown(&joints[j].name))));
                }
                seen[j].offset = true;
                joints[j].offset = cur.vector(scale)?;
            }
            "CHANNELS" => {
                if seen[j].channels {
                    return Err(cur.error_at(token, format!("second CHANNELS in joint '{}'", shown(&joints[j].name))));
                }
                seen[j].channels = true;
                joints[j].channels = parse_channels(cur)?;
                if j != 0 && joints[j].channels.iter().any(|c| c.is_position()) {
                    let message = format!(
                        "joint '{}' has position channels; only the root translates, so their values are ignored",
                        shown(&joints[j].name)
                    );
                    warnings.push(cur.error_at(token, message).to_string());
                }
            }
            "JOINT" => {
                if open.len() >= MAX_DEPTH {
                    return Err(cur.error_at(token, format!("joint hierarchy deeper than {MAX_DEPTH} levels")));
                }
                if joints.len() >= MAX_JOINTS {
                    return Err(cur.error_at(token, format!("more than {MAX_JOINTS} joints")));
                }
                open.push(begin_joint(cur, Some(j), &mut joints, &mut names)?);
                seen.push(Seen { offset: false, channels: false });
            }
            "END" => {
                cur.expect("Site")?;
                cur.expect("{")?;
                cur.expect("OFFSET")?;
                let site = cur.vector(scale)?;
                cur.expect("}")?;
                if joints[j].end_site.is_none() {
                    joints[j].end_site = Some(site);
                } else {
                    let message =
                        format!("joint '{}' has a second End Site; the first is kept", shown(&joints[j].name));
                    warnings.push(cur.error_at(token, message).to_string());
                }
            }
            "}" => {
                if !seen[j].offset {
                    return Err(cur.error_at(token, format!("joint '{}' has no OFFSET", shown(&joints[j].name))));
                }
                open.pop();
            }
            _ => {
                let message = format!("unexpected '{}' in joint '{}'", shown(token.text), shown(&joints[j].name));
                return Err(cur.error_at(token, message));
            }
        }
    }
    Ok(joints)
}

/// A joint after its `ROOT` or `JOINT` keyword: the name (the rest of the line) and the opening
/// brace, which may end that line. Returns the new joint's index.
fn begin_joint<'a>(
    cur: &mut Cursor<'a>,
    parent: Option<usize>,
    joints: &mut Vec<Joint>,
    names: &mut HashSet<&'a str>,
) -> Result<usize, SourceError> {
    let line = cur.rest_of_line();
    let (name, brace) = match line.text.strip_suffix('{') {
        Some(name) => (name.trim_end(), true),
        None => (line.text, false),
    };
    if name.is_empty() {
        return Err(cur.error_at(line, "expected a joint name"));
    }
    if name.ends_with('{') {
        let col = line.col + name.chars().count() - 1;
        return Err(SourceError::new(cur.file, line.line, col, "unexpected '{' after the joint name"));
    }
    if !names.insert(name) {
        return Err(cur.error_at(line, format!("duplicate joint name '{}'", shown(name))));
    }
    if !brace {
        cur.expect("{")?;
    }
    joints.push(Joint { name: name.to_string(), parent, offset: DVec3::ZERO, channels: Vec::new(), end_site: None });
    Ok(joints.len() - 1)
}

/// `CHANNELS` after its keyword: the count, then that many distinct channel names.
fn parse_channels(cur: &mut Cursor) -> Result<Vec<Channel>, SourceError> {
    let count = cur.expect_any("a channel count")?;
    let n: usize =
        count.text.parse().map_err(|_| cur.error_at(count, format!("bad channel count '{}'", shown(count.text))))?;
    let mut channels = Vec::new();
    for _ in 0..n {
        let token = cur.expect_any("a channel name")?;
        let channel = channel_from_name(token.text)
            .ok_or_else(|| cur.error_at(token, format!("unknown channel '{}'", shown(token.text))))?;
        if channels.contains(&channel) {
            return Err(cur.error_at(token, format!("channel '{}' listed twice", shown(token.text))));
        }
        channels.push(channel);
    }
    Ok(channels)
}

// ---------------------------------------------------------------------------------------------
// Motion

/// `MOTION` … to the end: the frame time and the poses.
fn parse_motion(
    cur: &mut Cursor,
    joints: &[Joint],
    scale: f64,
    warnings: &mut Vec<String>,
) -> Result<(f64, Vec<Pose>), SourceError> {
    let motion = cur.next().ok_or_else(|| cur.error_here("no MOTION section"))?;
    if !motion.text.eq_ignore_ascii_case("MOTION") {
        return Err(cur.error_at(motion, format!("expected 'MOTION', found '{}'", shown(motion.text))));
    }
    let frames_keyword = cur.expect("Frames:")?;
    let count = cur.expect_any("a frame count")?;
    let declared: usize =
        count.text.parse().map_err(|_| cur.error_at(count, format!("bad frame count '{}'", shown(count.text))))?;
    cur.expect("Frame")?;
    cur.expect("Time:")?;
    let time_token = cur.expect_any("a frame time")?;
    let frame_time = number(time_token.text).map_err(|m| cur.error_at(time_token, m))?;
    if !(frame_time > 0.0 && frame_time <= MAX_FRAME_TIME_S) {
        return Err(cur.error_at(
            time_token,
            format!("frame time must be positive and at most {MAX_FRAME_TIME_S} s, not {frame_time}"),
        ));
    }
    let trailing = cur.rest_of_line();
    if !trailing.text.is_empty() {
        return Err(cur.error_at(trailing, format!("unexpected '{}' after the frame time", shown(trailing.text))));
    }

    // Every channel of the file in frame-line order: (joint, channel).
    let slots: Vec<(usize, Channel)> =
        joints.iter().enumerate().flat_map(|(i, j)| j.channels.iter().map(move |&c| (i, c))).collect();
    let mut frames = Vec::new();
    let mut values = Vec::with_capacity(slots.len());
    let first_line = cur.line + 1;
    let rest = &cur.text[cur.pos..];
    for (k, line) in rest.strip_prefix('\n').unwrap_or(rest).split('\n').enumerate() {
        let line_no = first_line + k;
        let err = |col: usize, message: String| SourceError::new(cur.file, line_no, col, message);
        values.clear();
        let mut end_col = 1;
        for (col, field) in fields(line) {
            if values.len() == slots.len() {
                return Err(err(col, format!("frame line has more than {} values", slots.len())));
            }
            values.push(number(field).map_err(|m| err(col, m))?);
            end_col = col + field.chars().count();
        }
        // Blank lines are skipped, except that they are the frames of a file without channels.
        if values.is_empty() && !(slots.is_empty() && frames.len() < declared) {
            continue;
        }
        if values.len() < slots.len() {
            let message = format!("frame line has {} values, expected {}", values.len(), slots.len());
            return Err(err(end_col + 1, message));
        }
        let pose = pose(joints, &slots, &values, scale);
        if !pose.root.is_finite() {
            return Err(err(1, "root position out of range after scaling".to_string()));
        }
        frames.push(pose);
    }
    if frames.is_empty() {
        return Err(cur.error_at(count, "the file has no frames"));
    }
    if frames.len() != declared {
        let message = if frames.len() > declared {
            format!("'Frames: {declared}' but {} frame lines follow; all are kept", frames.len())
        } else {
            format!("'Frames: {declared}' but only {} frame lines follow", frames.len())
        };
        warnings.push(cur.error_at(frames_keyword, message).to_string());
    }
    Ok((frame_time, frames))
}

/// The pose one frame line's `values` give, `slots` naming the joint and channel of each.
fn pose(joints: &[Joint], slots: &[(usize, Channel)], values: &[f64], scale: f64) -> Pose {
    let mut rotations = vec![DQuat::IDENTITY; joints.len()];
    let mut shift = DVec3::ZERO;
    for (&v, &(j, c)) in values.iter().zip(slots) {
        if !c.is_position() {
            rotations[j] *= DQuat::from_axis_angle(DVec3::AXES[axis(c)], v.to_radians());
        } else if j == 0 {
            shift[axis(c)] = v * scale;
        }
    }
    for q in &mut rotations {
        *q = q.normalize();
    }
    Pose { root: joints[0].offset + shift, rotations }
}

// ---------------------------------------------------------------------------------------------
// Export

/// Where the depth-first export walk is: entering a joint, or closing it.
enum Step {
    Open(usize, usize),
    Close(usize, usize),
}

fn write_into(out: &mut String, skeleton: &Skeleton, clip: &Clip, scale: f64) -> fmt::Result {
    let joints = skeleton.joints();
    let mut children = vec![Vec::new(); joints.len()];
    for (i, j) in joints.iter().enumerate() {
        if let Some(p) = j.parent {
            children[p].push(i);
        }
    }
    // Frame lines list channels in the order joints appear in the file (depth first), which
    // differs from the skeleton's order when a joint's children are not listed contiguously.
    let mut order = Vec::with_capacity(joints.len());
    let mut stack = vec![Step::Open(0, 0)];
    writeln!(out, "HIERARCHY")?;
    while let Some(step) = stack.pop() {
        match step {
            Step::Open(i, depth) => {
                order.push(i);
                let joint = &joints[i];
                let tabs = "\t".repeat(depth);
                let keyword = if depth == 0 { "ROOT" } else { "JOINT" };
                writeln!(out, "{tabs}{keyword} {}\n{tabs}{{", joint.name)?;
                writeln!(out, "{tabs}\tOFFSET {}", Vector(joint.offset / scale))?;
                write!(out, "{tabs}\tCHANNELS {}", joint.channels.len())?;
                for &c in &joint.channels {
                    write!(out, " {}", channel_name(c))?;
                }
                writeln!(out)?;
                stack.push(Step::Close(i, depth));
                stack.extend(children[i].iter().rev().map(|&c| Step::Open(c, depth + 1)));
            }
            Step::Close(i, depth) => {
                let tabs = "\t".repeat(depth);
                if let Some(site) = joints[i].end_site {
                    writeln!(
                        out,
                        "{tabs}\tEnd Site\n{tabs}\t{{\n{tabs}\t\tOFFSET {}\n{tabs}\t}}",
                        Vector(site / scale)
                    )?;
                }
                writeln!(out, "{tabs}}}")?;
            }
        }
    }
    writeln!(out, "MOTION\nFrames: {}\nFrame Time: {}", clip.frames.len(), clip.frame_time)?;
    for pose in &clip.frames {
        let mut separator = "";
        for &i in &order {
            let joint = &joints[i];
            let rotation = pose.rotations.get(i).copied().unwrap_or(DQuat::IDENTITY);
            let shift = if i == 0 { (pose.root - joint.offset) / scale } else { DVec3::ZERO };
            // Each axis gets its value at its first rotation (position) channel, zero at repeats.
            let mut axes = [0; 3];
            let mut n = 0;
            for &c in &joint.channels {
                if !c.is_position() && !axes[..n].contains(&axis(c)) {
                    axes[n] = axis(c);
                    n += 1;
                }
            }
            let angles = euler_angles(rotation, &axes[..n]);
            let (mut rotation_done, mut position_done) = ([false; 3], [false; 3]);
            let mut k = 0;
            for &c in &joint.channels {
                let a = axis(c);
                if c.is_position() {
                    let v = if position_done[a] { 0.0 } else { shift[a] };
                    position_done[a] = true;
                    write!(out, "{separator}{}", Number(v, LENGTH_DECIMALS))?;
                } else {
                    let v = if rotation_done[a] { 0.0 } else { angles[k].to_degrees() };
                    if !rotation_done[a] {
                        k += 1;
                    }
                    rotation_done[a] = true;
                    write!(out, "{separator}{}", Number(v, ANGLE_DECIMALS))?;
                }
                separator = " ";
            }
        }
        writeln!(out)?;
    }
    Ok(())
}

/// Decimals written for lengths (file units) and angles (degrees): enough that a re-import
/// reproduces poses to well under 1e-6 m and 1e-6 rad.
const LENGTH_DECIMALS: usize = 8;
const ANGLE_DECIMALS: usize = 6;

/// A number with at most the given decimals, trailing zeros dropped, `-0` written as `0`.
struct Number(f64, usize);

impl fmt::Display for Number {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = format!("{:.*}", self.1, self.0);
        let s = if s.contains('.') { s.trim_end_matches('0').trim_end_matches('.') } else { &s };
        f.write_str(if s == "-0" { "0" } else { s })
    }
}

/// A vector of this crate's frame written as a BVH vector.
struct Vector(DVec3);

impl fmt::Display for Vector {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let v = to_bvh(self.0);
        let n = |x| Number(x, LENGTH_DECIMALS);
        write!(f, "{} {} {}", n(v.x), n(v.y), n(v.z))
    }
}

/// Angles (radians) about `axes` (distinct indices of this crate's X, Y, Z; at most three are
/// used) whose intrinsic product, in order, is `q`. Three axes give an exact Tait–Bryan
/// decomposition (middle angle in [-π/2, π/2]; at gimbal lock the last angle is 0). Two axes are
/// exact when `q` is such a product; otherwise the first angle points the second axis as close
/// to where `q` takes it as the first axis allows, and the second is the remaining twist. One
/// axis gives the twist of `q` about it.
fn euler_angles(q: DQuat, axes: &[usize]) -> [f64; 3] {
    let q = if q.is_finite() && q.length_squared() > 0.0 { q.normalize() } else { DQuat::IDENTITY };
    let e = |a: usize| DVec3::AXES[a];
    match *axes {
        [] => [0.0; 3],
        [a] => [twist(q, e(a)), 0.0, 0.0],
        [a, b] => {
            let d = q * e(b);
            let first = e(a).dot(e(b).cross(d)).atan2(e(b).dot(d));
            let rest = DQuat::from_axis_angle(e(a), -first) * q;
            [first, twist(rest, e(b)), 0.0]
        }
        [i, j, k, ..] => tait_bryan(q, i, j, k),
    }
}

/// Angles (α, β, γ) with `q` = R_i(α)·R_j(β)·R_k(γ) for distinct axes i, j, k.
fn tait_bryan(q: DQuat, i: usize, j: usize, k: usize) -> [f64; 3] {
    let m = DMat3::from_quat(q);
    let at = |row: usize, col: usize| m.col(col)[row];
    // +1 when (i, j, k) is a cyclic order of (X, Y, Z), -1 otherwise.
    let s = if (i + 1) % 3 == j { 1.0 } else { -1.0 };
    let sin_b = s * at(i, k);
    let cos_b = at(i, i).hypot(at(i, j));
    let beta = sin_b.atan2(cos_b);
    // Below this the first and last axes (nearly) coincide: the error of splitting the turn
    // between them by the general formulas (~1e-16 / cos β) would exceed the error of giving
    // it all to the first (~cos β).
    const GIMBAL: f64 = 1e-8;
    if cos_b > GIMBAL {
        [(-s * at(j, k)).atan2(at(k, k)), beta, (-s * at(i, j)).atan2(at(i, i))]
    } else {
        [(s * at(k, j)).atan2(at(j, j)), beta, 0.0]
    }
}

#[cfg(test)]
mod tests {
    use std::f64::consts::FRAC_PI_2;

    use glam::EulerRot;

    use super::*;

    /// Distance between rotations, resolving differences far below 1e-8 (unlike an arccosine).
    fn dist(a: DQuat, b: DQuat) -> f64 {
        (a - b).length().min((a + b).length())
    }

    const ORDERS: [([usize; 3], EulerRot); 6] = [
        ([0, 1, 2], EulerRot::XYZ),
        ([0, 2, 1], EulerRot::XZY),
        ([1, 0, 2], EulerRot::YXZ),
        ([1, 2, 0], EulerRot::YZX),
        ([2, 0, 1], EulerRot::ZXY),
        ([2, 1, 0], EulerRot::ZYX),
    ];

    fn compose(axes: &[usize], angles: &[f64]) -> DQuat {
        axes.iter().zip(angles).fold(DQuat::IDENTITY, |q, (&a, &t)| q * DQuat::from_axis_angle(DVec3::AXES[a], t))
    }

    /// Deterministic angles in (-π, π) from a counter.
    fn angle(n: u64) -> f64 {
        let x = n.wrapping_mul(0x9E37_79B9_7F4A_7C15).rotate_left(17) >> 11;
        (x as f64 / (1u64 << 53) as f64 * 2.0 - 1.0) * std::f64::consts::PI
    }

    #[test]
    fn three_axis_decomposition_is_exact_for_every_order() {
        for (axes, euler) in ORDERS {
            for n in 0..400u64 {
                let (a, mut b, c) = (angle(3 * n), angle(3 * n + 1), angle(3 * n + 2));
                // Some exactly or nearly at gimbal lock.
                match n % 8 {
                    0 => b = FRAC_PI_2,
                    1 => b = -FRAC_PI_2,
                    2 => b = FRAC_PI_2 - 1e-9,
                    3 => b = -FRAC_PI_2 + 3e-8,
                    _ => {}
                }
                // The reference composition is glam's, independent of `compose`.
                let q = DQuat::from_euler(euler, a, b, c);
                let got = euler_angles(q, &axes);
                assert!(got.iter().all(|x| x.is_finite()), "{axes:?} {got:?}");
                assert!(got[1].abs() <= FRAC_PI_2 + 1e-12);
                let back = DQuat::from_euler(euler, got[0], got[1], got[2]);
                // At and next to gimbal lock the split between first and last angle costs ~1e-8.
                let tolerance = if n % 8 < 4 { 1e-7 } else { 1e-12 };
                assert!(dist(q, back) < tolerance, "{axes:?} ({a}, {b}, {c}) -> {got:?}");
                if n % 8 >= 4 && b.abs() < 1.5 {
                    // Away from gimbal lock the angles themselves come back.
                    for (x, y) in [a, b, c].iter().zip(&got) {
                        assert!((x - y).abs() < 1e-9, "{axes:?} ({a}, {b}, {c}) -> {got:?}");
                    }
                }
            }
        }
    }

    #[test]
    fn two_and_one_axis_decompositions_are_exact_when_representable() {
        for a in 0..3 {
            for b in (0..3).filter(|&b| b != a) {
                for n in 0..200u64 {
                    let angles = [angle(2 * n), angle(2 * n + 1)];
                    let q = compose(&[a, b], &angles);
                    let got = euler_angles(q, &[a, b]);
                    assert!(dist(q, compose(&[a, b], &got[..2])) < 1e-12, "{a}{b} {angles:?} {got:?}");
                    // Not representable: finite angles, and the second axis lands where the
                    // first can bring it closest.
                    let r = q * DQuat::from_axis_angle(DVec3::AXES[3 - a - b], 0.4);
                    let got = euler_angles(r, &[a, b]);
                    assert!(got.iter().all(|x| x.is_finite()));
                    let target = r * DVec3::AXES[b];
                    let reached = compose(&[a, b], &got[..2]) * DVec3::AXES[b];
                    let best = (0..720)
                        .map(|s| {
                            DQuat::from_axis_angle(DVec3::AXES[a], s as f64 * 0.5f64.to_radians()) * DVec3::AXES[b]
                        })
                        .map(|v| v.dot(target))
                        .fold(f64::MIN, f64::max);
                    assert!(reached.dot(target) >= best - 1e-4);
                }
            }
            let q = DQuat::from_axis_angle(DVec3::AXES[a], 2.5);
            assert!((euler_angles(q, &[a])[0] - 2.5).abs() < 1e-12);
            assert!((euler_angles(-q, &[a])[0] - 2.5).abs() < 1e-12);
        }
        // A half turn about a perpendicular axis has no twist at all.
        let half = DQuat::from_xyzw(1.0, 0.0, 0.0, -0.0);
        assert_eq!(euler_angles(half, &[2])[0], 0.0);
        assert_eq!(euler_angles(DQuat::from_xyzw(0.0, 0.0, 0.0, 0.0), &[0, 1, 2]), [0.0; 3]);
    }

    #[test]
    fn axis_conversion_is_a_proper_rotation() {
        let (a, b) = (DVec3::new(1.0, 2.0, 3.0), DVec3::new(-0.5, 0.25, 2.0));
        assert_eq!(from_bvh(a), DVec3::new(3.0, 1.0, 2.0));
        assert_eq!(to_bvh(from_bvh(a)), a);
        assert_eq!(from_bvh(a.cross(b)), from_bvh(a).cross(from_bvh(b)));
        // BVH's up (Y) is our Z, its X our Y; each BVH rotation axis is the converted vector.
        for (name, c) in CHANNEL_NAMES {
            assert_eq!(channel_from_name(&name.to_uppercase()), Some(c));
            assert_eq!(channel_name(c), name);
            let bvh_axis = DVec3::AXES[(name.as_bytes()[0] - b'X') as usize];
            assert_eq!(from_bvh(bvh_axis), DVec3::AXES[axis(c)]);
        }
        assert_eq!(channel_from_name("Wrotation"), None);
    }

    #[test]
    fn tokens_and_fields_know_their_columns() {
        let text = "A\t bb{\r\n  }x\n\ncc  ";
        let mut cur = Cursor { text, file: "t", pos: 0, line: 1, col: 1 };
        let mut got = Vec::new();
        while let Some(t) = cur.next() {
            got.push((t.text, t.line, t.col));
        }
        assert_eq!(got, [("A", 1, 1), ("bb", 1, 4), ("{", 1, 6), ("}", 2, 3), ("x", 2, 4), ("cc", 4, 1)]);
        assert_eq!((cur.line, cur.col), (4, 5));
        let f: Vec<_> = fields(" 1\t22  é3 4\r").collect();
        assert_eq!(f, [(2, "1"), (4, "22"), (8, "é3"), (11, "4")]);
        let mut cur = Cursor { text: "ROOT  My Hips {  \nx", file: "t", pos: 0, line: 1, col: 1 };
        cur.next();
        let rest = cur.rest_of_line();
        assert_eq!((rest.text, rest.col), ("My Hips {", 7));
        assert_eq!(cur.next().map(|t| (t.text, t.line)), Some(("x", 2)));
    }

    #[test]
    fn numbers_are_written_short_and_read_back() {
        assert_eq!(Number(1.5, 6).to_string(), "1.5");
        assert_eq!(Number(-0.0000001, 6).to_string(), "0");
        assert_eq!(Number(20.0, 6).to_string(), "20");
        assert_eq!(Number(-3.1234567, 6).to_string(), "-3.123457");
        assert_eq!(number(".0083333"), Ok(0.0083333));
        assert!(number("nan").unwrap_err().starts_with("non-finite"));
        assert!(number("1e999").unwrap_err().starts_with("non-finite"));
        assert_eq!(number("1,5"), Err("bad number '1,5'".to_string()));
    }

    const SMALL: &str = "HIERARCHY\nROOT r\n{\n OFFSET 0 1 0\n CHANNELS 3 Xposition Yposition Zposition\n \
                         JOINT a {\n  OFFSET 0 1 0\n  CHANNELS 2 Xposition Zrotation\n  End Site { OFFSET 1 0 0 }\n  \
                         End Site { OFFSET 2 0 0 }\n }\n}\nMOTION\nFrames: 1\nFrame Time: 0.5\n1 2 3 9 90\n";

    #[test]
    fn parses_braces_on_name_lines_and_warns_about_oddities() {
        let bvh = parse(SMALL, "s.bvh", "s", &BvhOptions::default()).unwrap();
        let j = bvh.skeleton.joints();
        assert_eq!(j[1].name, "a");
        assert_eq!(j[1].channels, [Channel::YPosition, Channel::XRotation]);
        // The first End Site is kept (BVH x is our y).
        assert_eq!(j[1].end_site, Some(DVec3::new(0.0, 1.0, 0.0)));
        assert_eq!(bvh.warnings.len(), 2, "{:?}", bvh.warnings);
        assert!(bvh.warnings[0].starts_with("s.bvh:8:3: joint 'a' has position channels"));
        assert!(bvh.warnings[1].starts_with("s.bvh:10:3: joint 'a' has a second End Site"));
        let pose = &bvh.clip.frames[0];
        // Root: offset (0, 1, 0) + (1, 2, 3) in BVH = (1, 3, 3) = ours (3, 1, 3).
        assert_eq!(pose.root, DVec3::new(3.0, 1.0, 3.0));
        // The joint's position value 9 is ignored; Zrotation 90 is a quarter turn about our X.
        assert!(dist(pose.rotations[1], DQuat::from_rotation_x(FRAC_PI_2)) < 1e-12);
        assert_eq!(bvh.clip.frame_time, 0.5);
    }

    #[test]
    fn structural_errors_are_located() {
        let err = |text: &str| parse(text, "e.bvh", "e", &BvhOptions::default()).unwrap_err().to_string();
        let dup = SMALL.replace("JOINT a", "JOINT r");
        assert_eq!(err(&dup), "e.bvh:6:8: duplicate joint name 'r'");
        let no_brace = SMALL.replace("ROOT r\n{", "ROOT r\n");
        assert_eq!(err(&no_brace), "e.bvh:4:2: expected '{', found 'OFFSET'");
        let no_offset = SMALL.replace(" OFFSET 0 1 0\n CHANNELS 3", " CHANNELS 3");
        assert_eq!(err(&no_offset), "e.bvh:11:1: joint 'r' has no OFFSET");
        let twice = SMALL.replace("Xposition Yposition", "Xposition XPOSITION");
        assert_eq!(err(&twice), "e.bvh:5:23: channel 'XPOSITION' listed twice");
        let stray = SMALL.replace("JOINT a {", "JOINTS a {");
        assert_eq!(err(&stray), "e.bvh:6:2: unexpected 'JOINTS' in joint 'r'");
        let no_name = SMALL.replace("JOINT a {", "JOINT {");
        assert_eq!(err(&no_name), "e.bvh:6:8: expected a joint name");
        let brace_name = SMALL.replace("JOINT a {", "JOINT a{ {");
        assert_eq!(err(&brace_name), "e.bvh:6:9: unexpected '{' after the joint name");
        let no_hierarchy = "ROOT r";
        assert_eq!(err(no_hierarchy), "e.bvh:1:1: expected 'HIERARCHY', found 'ROOT'");
        assert_eq!(err(""), "e.bvh:1:1: unexpected end of file, expected 'HIERARCHY'");
        let zero_time = SMALL.replace("Time: 0.5", "Time: 0");
        assert_eq!(err(&zero_time), "e.bvh:15:13: frame time must be positive and at most 1 s, not 0");
        let no_frames = SMALL.replace("1 2 3 9 90\n", "\n  \n");
        assert_eq!(err(&no_frames), "e.bvh:14:9: the file has no frames");
        let scale = parse(SMALL, "e.bvh", "e", &BvhOptions { scale: 0.0 }).unwrap_err();
        assert_eq!(scale.to_string(), "e.bvh: scale must be positive and finite, not 0");
    }

    #[test]
    fn a_skeleton_without_channels_has_one_frame_per_line() {
        let text = "HIERARCHY\nROOT r\n{\nOFFSET 0 0 0\nCHANNELS 0\n}\nMOTION\nFrames: 2\nFrame Time: 1\n\n\n\n";
        let bvh = parse(text, "z", "z", &BvhOptions::default()).unwrap();
        assert_eq!(bvh.clip.frames.len(), 2);
        assert!(bvh.warnings.is_empty());
        let again = parse(&write(&bvh.skeleton, &bvh.clip, &BvhOptions::default()), "z", "z", &BvhOptions::default());
        assert_eq!(again.unwrap(), bvh);
    }

    #[test]
    fn export_walks_the_hierarchy_depth_first() {
        // Joint 2 is a child of joint 1 but a sibling (joint 3) sits between them in the list:
        // the file must list channels in depth-first order and re-import in that order.
        let j = |name: &str, parent, channels: Vec<Channel>| Joint {
            name: name.into(),
            parent,
            offset: DVec3::Z,
            channels,
            end_site: None,
        };
        let skeleton = Skeleton::new(vec![
            j("root", None, vec![Channel::ZRotation]),
            j("a", Some(0), vec![Channel::XRotation]),
            j("b", Some(0), vec![Channel::YRotation]),
            j("a1", Some(1), vec![Channel::ZRotation]),
        ])
        .unwrap();
        let mut pose = skeleton.bind_pose();
        for (i, q) in pose.rotations.iter_mut().enumerate() {
            *q = DQuat::from_axis_angle(DVec3::AXES[axis(skeleton.joints()[i].channels[0])], 0.1 * (i + 1) as f64);
        }
        let clip = Clip { name: "c".into(), frame_time: 0.1, frames: vec![pose.clone()] };
        let text = write(&skeleton, &clip, &BvhOptions::default());
        assert!(text.contains("\tJOINT a\n\t{\n\t\tOFFSET 0 1 0\n\t\tCHANNELS 1 Zrotation\n\t\tJOINT a1\n"), "{text}");
        assert!(
            text.ends_with("MOTION\nFrames: 1\nFrame Time: 0.1\n5.729578 11.459156 22.918312 17.188734\n"),
            "{text}"
        );
        let back = parse(&text, "x", "c", &BvhOptions::default()).unwrap();
        let names: Vec<&str> = back.skeleton.joints().iter().map(|j| j.name.as_str()).collect();
        assert_eq!(names, ["root", "a", "a1", "b"]);
        let expected = skeleton.positions(&pose);
        let got = back.skeleton.positions(&back.clip.frames[0]);
        for (i, k) in [0, 1, 3, 2].into_iter().enumerate() {
            assert!((got[i] - expected[k]).length() < 1e-7);
        }
    }
}

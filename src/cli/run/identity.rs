//! The identity of a run: what the output of `strider run --shard I/N` carries so that
//! `strider merge` joins only the shards of one run (seed 000 §4's batches, split across
//! machines).
//!
//! A run is its worlds, its rules, its body, its seed and its episode count, run by one version
//! of strider. Paths say little (one map file may be copied, edited or given another way), so
//! the worlds and the rules are identified by SHA-256 digests of what was loaded (every scenario
//! and the rule network as they are in memory: what the episodes run, whatever file they came
//! from), and the body by a digest of its database and policy files.

use std::fmt::{self, Write as _};
use std::path::Path;

use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use crate::experiment::Shard;
use crate::files;
use crate::load::{BodyArgs, BodyKind, Failure, MapSource, Switch, TransitionArg, baseline, database_files};
use crate::sim::LayeredController;

/// What identifies a run, carried by each of its shards' outputs (JSON: the `run` object; CSV:
/// a first line `# strider run: ` and this object as JSON). Two shards belong to one run when
/// every field but [`RunIdentity::shard`]'s index is equal.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunIdentity {
    /// The version of strider that ran it.
    pub strider: String,
    /// The map argument as given (a path or `random:KIND`), for messages.
    pub map: String,
    /// SHA-256 of the run's worlds as loaded, hex.
    pub map_sha256: String,
    /// The rule script as given, or `built-in`, for messages.
    pub rules: String,
    /// SHA-256 of the navigation rules as loaded, hex.
    pub rules_sha256: String,
    /// `animated` or `disc`.
    pub body: String,
    /// SHA-256 of what drives the animated body (database and policy files, transition,
    /// footstep planner), hex; of nothing for the disc.
    pub body_sha256: String,
    /// The run's seed, as a string of digits (as every seed in strider's JSON).
    pub seed: String,
    /// Episodes of the whole run.
    pub episodes: usize,
    /// The shard, `I/N`.
    pub shard: String,
}

/// Fields of [`RunIdentity`] that say which run it is, named, in the order merge checks them.
type Field<'a> = (&'static str, &'a str);

impl RunIdentity {
    /// The identity of the run `shard` belongs to: `map` and `rules` as given (`None`: built
    /// in), loaded as `source` and `controller`, with the body of `body`, `seed` and
    /// `episodes` in all.
    pub fn new(
        (map, source): (&str, &MapSource),
        (rules, controller): (Option<&Path>, &LayeredController),
        body: &BodyArgs,
        seed: u64,
        episodes: usize,
        shard: Shard,
    ) -> Result<RunIdentity, Failure> {
        Ok(RunIdentity {
            strider: env!("CARGO_PKG_VERSION").to_string(),
            map: map.to_string(),
            map_sha256: debug_digest(source),
            rules: rules.map_or_else(|| "built-in".to_string(), |p| p.display().to_string()),
            rules_sha256: debug_digest(controller),
            body: match body.body {
                BodyKind::Animated => "animated",
                BodyKind::Disc => "disc",
            }
            .to_string(),
            body_sha256: body_digest(body)?,
            seed: seed.to_string(),
            episodes,
            shard: format!("{}/{}", shard.index, shard.count),
        })
    }

    /// The shard, read back from [`RunIdentity::shard`].
    pub fn shard(&self) -> Result<Shard, String> {
        self.shard.parse()
    }

    /// The fields that must agree between the shards of one run (all but the shard's index).
    fn run_fields(&self) -> [Field<'_>; 6] {
        [
            ("strider version", &self.strider),
            ("worlds", &self.map_sha256),
            ("rules", &self.rules_sha256),
            ("body", &self.body),
            ("body's database and policy", &self.body_sha256),
            ("seed", &self.seed),
        ]
    }

    /// Why `other` is not a shard of the same run as `self` (naming the first field that
    /// differs), or `None` when it is.
    pub fn differs(&self, other: &RunIdentity) -> Option<String> {
        let count = |r: &RunIdentity| r.shard().map(|s| s.count).ok();
        for ((name, a), (_, b)) in self.run_fields().into_iter().zip(other.run_fields()) {
            if a != b {
                let what = match name {
                    "worlds" => format!(" ({} here, {} there)", other.map, self.map),
                    "rules" => format!(" ({} here, {} there)", other.rules, self.rules),
                    _ => format!(" ({b} here, {a} there)"),
                };
                return Some(format!("another {name}{what}"));
            }
        }
        if self.episodes != other.episodes {
            return Some(format!("another episode count ({} here, {} there)", other.episodes, self.episodes));
        }
        if count(self) != count(other) {
            return Some(format!("another shard count ({} here, {} there)", other.shard, self.shard));
        }
        None
    }
}

/// Hex SHA-256 of `value`'s `Debug` text: every field of the loaded data, each number in full
/// (Rust's shortest text that reads back as the same value).
fn debug_digest(value: &impl fmt::Debug) -> String {
    struct Hashing(Sha256);
    impl fmt::Write for Hashing {
        fn write_str(&mut self, s: &str) -> fmt::Result {
            self.0.update(s.as_bytes());
            Ok(())
        }
    }
    let mut h = Hashing(Sha256::new());
    // Writing into a hash cannot fail.
    let _ = write!(h, "{value:?}");
    hex(h.0.finalize().as_slice())
}

/// Hex SHA-256 of what drives the animated body: the database (its manifest and clip files, or
/// the built-in one), the policy (its file, a baseline's name, or the shipped one), the
/// transition and the footstep planner; of nothing for the disc, which none of them drive.
fn body_digest(body: &BodyArgs) -> Result<String, Failure> {
    let mut h = Sha256::new();
    if body.body == BodyKind::Disc {
        return Ok(hex(h.finalize().as_slice()));
    }
    let file = |h: &mut Sha256, label: &str, path: &Path| -> Result<(), Failure> {
        let bytes = files::read_bytes(path)?;
        h.update(format!("{label} {} bytes\n", bytes.len()));
        h.update(&bytes);
        Ok(())
    };
    match &body.db {
        Some(dir) => {
            for f in database_files(dir) {
                file(&mut h, &format!("database {}", f.display()), &dir.join(&f))?;
            }
        }
        None => h.update("database built-in\n"),
    }
    match (&body.policy, baseline(body.policy.as_deref())) {
        (Some(_), Some(b)) => h.update(format!("policy {}\n", b.name())),
        (Some(p), None) => file(&mut h, "policy", p)?,
        (None, _) => h.update("policy shipped\n"),
    }
    h.update(match body.transition {
        TransitionArg::Crossfade => "transition crossfade\n",
        TransitionArg::Inertialize => "transition inertialize\n",
    });
    h.update(match body.planner {
        Switch::On => "planner on\n",
        Switch::Off => "planner off\n",
    });
    Ok(hex(h.finalize().as_slice()))
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().fold(String::with_capacity(2 * bytes.len()), |mut s, b| {
        let _ = write!(s, "{b:02x}");
        s
    })
}

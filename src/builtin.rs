//! Data built into the binary, so strider runs on a fresh machine with nothing else: the
//! default navigation rules (seed 000 §3.1), the default scenario (seed 000 Fig 2 (b)), the
//! animation database of the 22-DOF actor's generated clips and the policy trained on it
//! (seed 000 §3.2).

use crate::anim::policy::{Policy, PolicyError};
use crate::anim::{Database, DbError};
use crate::script::{Limits, ScriptLog, load_engines};
use crate::sim::{Animation, ControllerParams, LayeredController};

/// The default navigation rules: the layered fuzzy network of `scripts/nav.rhai`.
pub const DEFAULT_RULES: &str = include_str!("../scripts/nav.rhai");

/// Name under which the default rules report errors.
pub const DEFAULT_RULES_FILE: &str = "scripts/nav.rhai";

/// The default scenario: the semi-cluttered environment of `maps/semi_cluttered.rhai`.
pub const DEFAULT_MAP: &str = include_str!("../maps/semi_cluttered.rhai");

/// Name under which the default map reports errors.
pub const DEFAULT_MAP_FILE: &str = "maps/semi_cluttered.rhai";

/// The policy trained on [`database`] (`assets/default.policy`, written by `strider train`).
pub const DEFAULT_POLICY: &[u8] = include_bytes!("../assets/default.policy");

/// Name under which the built-in policy reports errors.
pub const DEFAULT_POLICY_FILE: &str = "assets/default.policy";

/// The built-in animation database: the 22-DOF actor's generated clips, cut at their exact foot
/// plants (the same database `assets/db` holds as files).
pub fn database() -> Result<Database, DbError> {
    crate::anim::procedural::default_database()
}

/// The built-in policy, checked against `db` (the built-in database).
pub fn policy(db: &Database) -> Result<Policy, PolicyError> {
    Policy::from_bytes(DEFAULT_POLICY, db)
}

/// The built-in character: [`database`] played by [`policy`], with default playback.
pub fn animation() -> Result<Animation, String> {
    let db = database().map_err(|e| e.to_string())?;
    let policy = policy(&db).map_err(|e| e.to_string())?;
    Ok(Animation::new(db, policy))
}

/// The layered controller of [`DEFAULT_RULES`] with default parameters (what the rules print
/// goes nowhere).
pub fn controller() -> Result<LayeredController, String> {
    let engines = load_engines(DEFAULT_RULES, DEFAULT_RULES_FILE, Limits::default(), &ScriptLog::new())
        .map_err(|e| e.to_string())?;
    LayeredController::new(&engines, ControllerParams::default())
}

//! Data built into the binary, so strider runs on a fresh machine with nothing else: the
//! default navigation rules (seed 000 §3.1) and the default scenario (seed 000 Fig 2 (b)).

/// The default navigation rules: the layered fuzzy network of `scripts/nav.rhai`.
pub const DEFAULT_RULES: &str = include_str!("../scripts/nav.rhai");

/// Name under which the default rules report errors.
pub const DEFAULT_RULES_FILE: &str = "scripts/nav.rhai";

/// The default scenario: the semi-cluttered environment of `maps/semi_cluttered.rhai`.
pub const DEFAULT_MAP: &str = include_str!("../maps/semi_cluttered.rhai");

/// Name under which the default map reports errors.
pub const DEFAULT_MAP_FILE: &str = "maps/semi_cluttered.rhai";

//! Planar geometry (placeholder until filled).

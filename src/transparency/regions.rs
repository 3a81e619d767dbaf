//! Per-region mask regeneration (placeholder while being written).

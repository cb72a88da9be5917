//! Simulator (work in progress).
pub fn register(_r: &mut keylo_core::Registry) {}

//! Inputs the benches share (each bench is its own crate: they include this folder by path).
pub mod edit;

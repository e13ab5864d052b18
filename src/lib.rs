//! # ncgear
//!
//! Design of the non-circular gears of the rotary transplanting (planting-arm) mechanism of
//! high-speed rice transplanters, and companion gear-train analyses.
//!
//! The design chain, one module per stage (spec: `design-chain.md`):
//!
//! `trajectory` → `inverse` (l1, l3, ψ3, i31) → `compat` (half-closure origin τ, E_c) →
//! `segmented` (Fourier hypothesis, mirror/weight iteration) → `fourier` (least-squares fit) →
//! `refine` (direct tip-deviation fit) → `pitch` / `mechanism` (pitch curves, assembly, forward
//! model, round trip) → `design` (the whole chain and its report).
//!
//! Units: files speak mm and degrees; the library works in mm and radians. Every public quantity
//! carries its unit in its name or its doc comment.
#![warn(missing_docs)]
// Every declared dependency is used (the test and bench targets have their own dev-dependencies).
#![cfg_attr(not(test), warn(unused_crate_dependencies))]
#![warn(clippy::print_stdout, clippy::print_stderr)]
// `!(x > 0.0)` is how the input checks reject NaN together with out-of-range values.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

// Dependencies the library declares but does not name: argmin's nalgebra 0.34 backend (a
// feature-only dependency), and those of the `ncgear` binary (the `cli` feature).
use argmin_math as _;
#[cfg(all(feature = "cli", unix))]
use libc as _;
#[cfg(feature = "cli")]
use {clap as _, indicatif as _};

pub mod analysis;
pub mod config;
pub mod design;
pub mod export;
pub mod geometry;
pub mod math;
pub mod output;
pub mod pair;
pub mod simulate;
pub mod teeth;

//! Measurement evaluation (A.7–A.8) — filled in below.

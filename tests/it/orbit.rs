//! Integration tests: orbit.

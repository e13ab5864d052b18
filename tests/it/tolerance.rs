//! Integration tests: tolerance.

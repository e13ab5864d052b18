//! Integration tests: teeth.

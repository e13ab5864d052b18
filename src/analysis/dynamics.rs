//! See `companion-methods.md`.

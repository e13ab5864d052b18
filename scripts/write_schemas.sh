#!/usr/bin/env bash
# Writes docs/schemas/<report>.schema.json from the report types (ncgear::output::schemas);
# tests/it/schemas.rs checks that the committed files equal what this writes.
# Usage: scripts/write_schemas.sh
set -euo pipefail
cd "$(dirname "$0")/.."
rm -f docs/schemas/*.schema.json
cargo run --release --quiet --example schemas -- docs/schemas

#!/usr/bin/env bash
# The comparison suite against the peer ncgears: installs ncgears 0.3.1 (PyPI, pinned)
# into the venv target/pyvenv and runs scripts/compare_ncgears.py — every law made by both tools,
# centre distances to 1e-9, tooth counts, areas within 1 %, ncgear's interference 0 and its
# transmission error ≤ ncgears'. Prints the markdown table (docs/performance.md's) and fails on any check.
# Needs target/release/ncgear (built by `cargo test --release`). Usage: scripts/check_ncgears.sh
set -euo pipefail
cd "$(dirname "$0")/.."
venv=target/pyvenv
start=$(date +%s)
[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
"$venv/bin/python" -c "import ncgears, importlib.metadata as m; assert m.version('ncgears') == '0.3.1'" 2> /dev/null \
  || "$venv/bin/pip" install -q --disable-pip-version-check ncgears==0.3.1
cargo build --release --quiet
"$venv/bin/python" scripts/compare_ncgears.py --ncgear target/release/ncgear --ncgears "$venv/bin/ncgears" \
  --out target/ncgears-suite
echo "check_ncgears: $(($(date +%s) - start)) s"

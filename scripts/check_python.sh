#!/usr/bin/env bash
# The Python package: the wheel built by maturin (`pip install .`) into a venv under
# target/, pytest over the Python API — the tests also read every STEP file they write back with
# OCCT (cadquery-ocp, via build123d from PyPI) — the type stubs checked against the module
# (mypy.stubtest), then the build123d pipeline of examples/python.
# Needs target/release/ncgear (built by `cargo test --release`). Usage: scripts/check_python.sh
set -euo pipefail
cd "$(dirname "$0")/.."
venv=target/pyenv
start=$(date +%s)
[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
"$venv/bin/pip" install -q -r python/requirements-ci.txt
cargo fmt --check --manifest-path python/Cargo.toml
# The binding crate is a member of the root workspace (not a default one): it builds into
# target/release beside the root's artifacts and reuses those it shares with the root's
# `cargo test --release` (same lock, profile and dependency features).
build=$(date +%s)
"$venv/bin/pip" install -q --force-reinstall --no-deps .
echo "check_python: binding built and installed in $(($(date +%s) - build)) s"
NCGEAR_BIN="$PWD/target/release/ncgear" "$venv/bin/python" -m pytest -q -p no:cacheprovider python/tests
# The stubs (ncgear/__init__.pyi, ncgear/_ncgear.pyi) against the installed module.
"$venv/bin/python" -m mypy.stubtest ncgear
"$venv/bin/python" examples/python/pipeline.py target/python-pipeline
echo "check_python: $(($(date +%s) - start)) s"

#!/usr/bin/env bash
# The instruction gate (docs/performance.md, "The instruction gate"): the hot paths' instruction
# counts under Valgrind's callgrind (benches/instructions.rs, gungraun) against
# benches/instructions/baseline.toml; fails when one grows by more than 5 % unless the baseline
# re-blesses it, with a one-line reason.
# Usage: scripts/check_instructions.sh                   measure and check
#        scripts/check_instructions.sh --bless "why"     measure and write the baseline
#        add --from FILE to either to read gungraun's JSON lines from FILE instead of measuring
# Installs Debian's valgrind and gungraun-runner (the version of gungraun in Cargo.lock) when
# missing. ≈ 1.5 min on a quiet 2-core machine; the kidney's failed design is most of it.
set -euo pipefail
cd "$(dirname "$0")/.."
baseline=benches/instructions/baseline.toml
mode=check reason="" from=""
while [ $# -gt 0 ]; do
    case "$1" in
        --bless) mode=bless; reason="${2:?--bless needs a one-line reason}"; shift 2 ;;
        --from) from="${2:?--from needs a file}"; shift 2 ;;
        *) echo "unknown argument: $1 (see the usage at the top of $0)" >&2; exit 2 ;;
    esac
done
if [ -z "$from" ]; then
    if ! command -v valgrind >/dev/null; then
        apt-get update -qq && apt-get install -y -qq valgrind >/dev/null
    fi
    # gungraun-runner must be the version of the gungraun library the benchmark links.
    version=$(awk '/^name = "gungraun"$/ { getline; gsub(/[^0-9.]/, ""); print; exit }' Cargo.lock)
    [ -n "$version" ] || { echo "no gungraun in Cargo.lock" >&2; exit 1; }
    if [ "$(gungraun-runner --version 2>/dev/null | awk '{print $NF}')" != "$version" ]; then
        cargo install --quiet --locked --version "$version" gungraun-runner
    fi
    from=target/instructions.json
    # Counts of this tree's code only: no cache simulation, each benchmark once.
    cargo bench --quiet --bench instructions -- --output-format=json >"$from"
fi
if [ "$mode" = bless ]; then
    python3 scripts/instructions_gate.py bless "$from" "$baseline" "$reason"
else
    python3 scripts/instructions_gate.py check "$from" "$baseline"
fi

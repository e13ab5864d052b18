#!/usr/bin/env bash
# ncgear against the yardsticks, back to back in one run: prints the README's performance table.
# Usage: bash benches/compare.sh [--yardsticks DIR] [--repeat 3]
#   DIR holds mc_numpy_best.py and numpy_chain/ (default ../shared/bench; not part of the project).
#   Without DIR's mc_numpy_best.py, the Monte Carlo's yardstick is benches/python/mc_numpy.py.
#   The venv target/pyvenv gets numpy, scipy, threadpoolctl and ncgears 0.3.1 from PyPI on first use.
#   --only TEXT runs the rows whose work contains TEXT (e.g. --only "Monte Carlo").
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release -q
[ -x target/pyvenv/bin/ncgears ] || { python3 -m venv target/pyvenv && target/pyvenv/bin/pip install -q ncgears==0.3.1 ezdxf; }
target/pyvenv/bin/python -c "import numpy, scipy, threadpoolctl" 2>/dev/null || target/pyvenv/bin/pip install -q numpy scipy threadpoolctl
exec target/pyvenv/bin/python benches/compare.py --ncgears target/pyvenv/bin/ncgears "$@"

#!/usr/bin/env bash
# Same job in the Python peer ncgears (PyPI 0.3.1) and in ncgear, timed (wall clock).
# Usage: bash benches/python/ncgears_pair.sh   (creates target/pyvenv with ncgears + ezdxf)
set -euo pipefail
cd "$(dirname "$0")/../.."
[ -x target/pyvenv/bin/ncgears ] || { python3 -m venv target/pyvenv && target/pyvenv/bin/pip install -q ncgears ezdxf; }
cargo build --release -q
echo "ncgears:"; /usr/bin/time -f "%e s wall, %U s user" target/pyvenv/bin/ncgears "phi - 0.08*sin(2*phi)" --teeth 24 --module 1.5 --output target/ncgears_out > target/ncgears_out.log
echo "ncgear (design + exports, no verification):"; /usr/bin/time -f "%e s wall, %U s user" target/release/ncgear pair "phi - 0.08*sin(2*phi)" --teeth 24 --module 1.5 --verify-steps 0 --out target/ncgear_out0
echo "ncgear (with 90-step mesh verification):"; /usr/bin/time -f "%e s wall, %U s user" target/release/ncgear pair "phi - 0.08*sin(2*phi)" --teeth 24 --module 1.5 --out target/ncgear_out

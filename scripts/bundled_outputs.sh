#!/usr/bin/env bash
# Run the bundled examples into $1 (a fresh dir); used before/after the restructure.
set -u
cd "$(dirname "$0")/.."
B=${BIN:-$(pwd)/target/release/ncgear}
O=$(realpath -m "$1"); rm -rf "$O"; mkdir -p "$O"; cd "$(dirname "$0")/.."
run() { local name=$1; shift; "$B" "$@" > "$O/$name.stdout" 2> "$O/$name.stderr"; echo "$?" > "$O/$name.rc"; }
run design_g1 design assets/trajectories/g1_ellipse.csv --out "$O/g1" --json
run design_g1_teeth design assets/trajectories/g1_ellipse.csv --out "$O/g1t" --module 2 --json
for f in assets/trajectories/*; do n=$(basename "$f"); run "traj_$n" design "$f" --out "$O/t_$n" --json; done
for f in assets/cases/*.csv; do n=$(basename "$f" .csv); run "case_$n" design "$f" --out "$O/c_$n" --json; done
run pair pair "phi - 0.08*sin(2*phi)" --teeth 24 --module 1.5 --out "$O/pair" --json
run simulate simulate "$O/g1t/design.json" --out "$O/sim" --json
for f in assets/tolerance/*; do n=$(basename "$f"); run "tol_$n" tolerance "$f" --samples 20000 --seed 1 --out "$O/tol_$n" --json; done
run transplanter tolerance assets/transplanter/g1_design.json --errors assets/transplanter/g1_errors.toml --samples 2000 --seed 1 --out "$O/tp" --json
run orbit_model orbit model assets/orbit/model.toml --plot "$O/orbit.svg"
run orbit_measure orbit measure assets/orbit/signals.csv --model assets/orbit/model.toml --frame derotate --plot-dir "$O/oplots" --json
run orbit_identify orbit identify --model assets/orbit/model.toml --signals assets/orbit/signals.csv --frame derotate --json
for f in assets/dynamics/*.toml; do n=$(basename "$f" .toml); run "dyn_$n" dynamics "$f" --out "$O/dyn_$n" --json; done
run dyn_sweep dynamics assets/dynamics/backlash_oscillator.toml --sweep 0.6:1.0:0.02 --out "$O/sweep" --json

#!/usr/bin/env bash
# Every JSON report the CLI writes, run on the bundled examples, validates against its schema in
# docs/schemas/ (scripts/check_schemas.py; jsonschema from PyPI in the venv target/pyenv, version
# pinned in python/requirements-ci.txt). The reports and their `--json` stdout: design (g1, g1
# with teeth, the kidney with teeth, the clockwise JSON trajectory, a failed design with its
# alternatives, the module sized by strength), pair, simulate, dynamics
# (every bundled scene and a sweep), tolerance, transplanter, loads, tradeoff, synthesis (both
# specs) orbit model/measure/identify and compare (the bundled G1 track). Fails naming the file and the JSON path of its first
# violation; a command that exits with an error other than a failed verdict (3) fails too; and
# when python/ncgear/reports.py is not what scripts/gen_reports.py writes from the schemas.
# Needs target/release/ncgear (built by `cargo test --release`). Usage: scripts/check_schemas.sh
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${NCGEAR:-$PWD/target/release/ncgear}
venv=target/pyenv
[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
"$venv/bin/python" -c "import jsonschema" 2>/dev/null ||
  "$venv/bin/pip" install -q "$(grep '^jsonschema==' python/requirements-ci.txt)"
# The Python report classes are generated from the schemas: python/ncgear/reports.py must be what
# scripts/gen_reports.py writes from them (stdlib only; python/tests/ checks the classes further).
"$venv/bin/python" scripts/gen_reports.py --check
out=target/check-schemas
rm -rf "$out"
mkdir -p "$out"
pairs=()
# run NAME REPORT ARGS...: ncgear ARGS with its stdout in $out/NAME.stdout; exit 0 or 3.
run() {
  local name=$1 report=$2 rc=0
  shift 2
  "$bin" "$@" >"$out/$name.stdout" 2>"$out/$name.stderr" || rc=$?
  if [ "$rc" -ne 0 ] && [ "$rc" -ne 3 ]; then
    echo "check_schemas: ncgear $* exited with $rc:" >&2
    cat "$out/$name.stderr" >&2
    exit 1
  fi
  pairs+=("$report=$out/$name.stdout")
}
# file REPORT PATH: a report file the runs wrote.
file() { pairs+=("$1=$out/$2"); }

t=assets/trajectories
run g1 design design $t/g1_ellipse.csv --out "$out/g1" --json
file design g1/design.json
run g1_m2 design design $t/g1_ellipse.csv --out "$out/g1_m2" --module 2 --json
file design g1_m2/design.json
run kidney design design $t/designer_kidney.csv --out "$out/kidney" --module 1.5 --json
file design kidney/design.json
run cw design design $t/asymmetric_cw.json --out "$out/cw" --json
file design cw/design.json
# A failed design: its nearest alternatives are written.
run odd3 design design assets/cases/designer_odd3.csv --out "$out/odd3" --alternatives --json
file design odd3/design.json
run sized design design $t/g1_ellipse.csv --out "$out/sized" --module auto --loads assets/loads/rotor.toml --json
file design sized/design.json
file loads sized/loads/loads.json
run pair pair pair "phi - 0.08*sin(2*phi)" --teeth 24 --module 1.5 --out "$out/pair" --json
file pair pair/pair.json
run simulate simulate simulate "$out/kidney/design.json" --out "$out/simulate" --spacing 140 --json
file simulate simulate/simulate.json
for scene in assets/dynamics/*.toml; do
  n=$(basename "$scene" .toml)
  # A rotor scene (`model = "rotor"`) writes the rotor's report (dynamics_rotor.schema.json).
  schema=dynamics
  if grep -q '^model *= *"rotor"' "$scene"; then schema=dynamics_rotor; fi
  run "dyn_$n" "$schema" dynamics "$scene" --out "$out/dyn_$n" --json
  file "$schema" "dyn_$n/dynamics.json"
done
run sweep dynamics dynamics assets/dynamics/backlash_oscillator.toml --sweep 0.6:1.0:0.05 --out "$out/sweep" --json
file dynamics sweep/dynamics.json
run tolerance tolerance tolerance assets/tolerance/paper_3k.toml --samples 2000 --seed 1 --out "$out/tolerance" --json
file tolerance tolerance/tolerance.json
run transplanter transplanter tolerance assets/transplanter/g1_design.json --errors assets/transplanter/g1_errors.toml --samples 500 --seed 1 --out "$out/transplanter" --json
file transplanter transplanter/transplanter.json
run loads loads loads assets/loads/g1_rotor.toml --out "$out/loads" --json
file loads loads/loads.json
run tradeoff tradeoff tradeoff $t/designer_kidney.csv --out "$out/tradeoff" --json
file tradeoff tradeoff/tradeoff.json
for spec in assets/synthesis/*.toml; do
  n=$(basename "$spec" .toml)
  run "synth_$n" synthesis synthesize "$spec" --out "$out/synth_$n" --json
  file synthesis "synth_$n/synthesis.json"
  file design "synth_$n/design.json"
done
run orbit_model orbit_model orbit model assets/orbit/model.toml --json
run orbit_measure orbit_measure orbit measure assets/orbit/signals.csv --model assets/orbit/model.toml --frame derotate --json
run orbit_identify orbit_identify orbit identify --model assets/orbit/model.toml --signals assets/orbit/signals.csv --frame derotate --json
run compare compare compare assets/compare/g1_track.csv --design assets/transplanter/g1_design.json --fps 500 --px-per-mm 3.2 --spacing 140 --out "$out/compare" --json
file compare compare/compare.json
"$venv/bin/python" scripts/check_schemas.py docs/schemas "${pairs[@]}"

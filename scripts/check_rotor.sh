#!/usr/bin/env bash
# Checks `ncgear dynamics` on rotor scenes against an independent model of the rotor's dynamics
# (scripts/check_rotor.py: Lagrange's equations in momentum form, its own mesh geometry, contact
# modes switched at located events, scipy's DOP853; the kinematics of scripts/check_loads.py;
# no code shared with the crate). Designs trains with `ncgear design` into
# target/check-rotor/CASE/design (or takes the bundled one), writes dynamics scenes and the loads
# scenes of the same tables beside them, runs `ncgear dynamics` and `ncgear loads` on each, and
# compares each mesh's dynamic force, the tip's deviation from its static path and the
# contact-loss intervals on the report's samples.
#
# Cases: g1_m2 (the bundled G1 design at module 2, assets/loads/g1_m2_design.json), cw_m2
# (assets/cases/exact_cw_offset.csv clockwise at its own axis, --module 2: the idler off the line),
# kidney (the designer-drawn kidney, --module 2), own (scripts/check_loads.sh's forward-model
# trajectory, no teeth), cw_m2_slide (cw_m2's design with the knock scene: with a damper on
# the flanks' relative speed, before 2026-12-02, the planet mesh slid along the dead zone's
# edge at 105–112° of travel and ncgear's integration failed at rtol 1e-10; docs/dynamics.md
# "The rotor" → "Verified").
# Scenes: knock (constant mesh stiffness 14000 N/mm/mm, backlash 0.0752 mm: contact loss and
# impacts; the planting needle, gravity, two arms, mesh and vibration damping), smooth (the same
# without backlash: flank changes at the force's zeros, no dead zone), pairs (per-mesh
# stiffness, damping and backlash, a needle force table, slanted gravity, one arm, 250 r/min),
# iso_knock (knock with ISO 6336-1 stiffness, pairs "mean", and the teeth's backlash), iso_smooth
# (ISO × 3, pairs "mean", per-mesh damping, no backlash).
#
# Python: target/pyvenv-rotor if it has numpy and scipy, else a python3 that has them, else a venv
# target/pyvenv-rotor with numpy and scipy from PyPI; without any it prints a WARNING and skips
# (exit 0), as scripts/check_loads.sh does. Exit 1 when any case fails.
# Usage: scripts/check_rotor.sh [--no-build] [CASE ...]     (NCGEAR=path overrides the binary)
set -euo pipefail
cd "$(dirname "$0")/.."

build=1
cases=()
for arg in "$@"; do
  case "$arg" in
    --no-build) build=0 ;;
    -h | --help)
      sed -n '2,27p' "$0"
      exit 0
      ;;
    *) cases+=("$arg") ;;
  esac
done

# ---- python with numpy and scipy -------------------------------------------------------------
has_mods() { "$1" -c "import numpy, scipy.integrate, tomllib" 2> /dev/null; }
py=""
for cand in target/pyvenv-rotor/bin/python "$(command -v python3 || true)"; do
  if [ -n "$cand" ] && [ -x "$cand" ] && has_mods "$cand"; then
    py="$cand"
    break
  fi
done
if [ -z "$py" ]; then
  sys_py="$(command -v python3 || true)"
  if [ -z "$sys_py" ]; then
    echo "check_rotor: WARNING no python3 found; rotor check skipped" >&2
    exit 0
  fi
  if ! "$sys_py" -c "import tomllib" 2> /dev/null; then
    echo "check_rotor: WARNING $sys_py is older than 3.11 (no tomllib); rotor check skipped" >&2
    exit 0
  fi
  venv=target/pyvenv-rotor
  mkdir -p target
  if ! "$sys_py" -m venv "$venv" > /dev/null 2>&1; then
    echo "check_rotor: WARNING cannot create a Python venv ($sys_py -m venv); rotor check skipped" >&2
    exit 0
  fi
  if ! "$venv/bin/pip" install --quiet --disable-pip-version-check numpy scipy > "$venv/pip.log" 2>&1; then
    echo "check_rotor: WARNING pip could not install numpy and scipy (no network?); see $venv/pip.log; check skipped" >&2
    exit 0
  fi
  py="$venv/bin/python"
fi
"$py" -c "import numpy, scipy, sys; print('check_rotor: python', sys.version.split()[0], 'numpy', numpy.__version__, 'scipy', scipy.__version__)"

# ---- the binary ------------------------------------------------------------------------------
ncgear="${NCGEAR:-target/release/ncgear}"
if [ -z "${NCGEAR:-}" ] && [ "$build" = 1 ]; then
  echo "check_rotor: cargo build --release"
  if ! cargo build --release --quiet; then
    echo "check_rotor: ERROR cargo build --release failed (--no-build checks the binary there is)" >&2
    exit 1
  fi
fi
if [ ! -x "$ncgear" ]; then
  echo "check_rotor: ERROR no binary at $ncgear" >&2
  exit 1
fi
if ! "$ncgear" dynamics --help > /dev/null 2>&1; then
  echo "check_rotor: ERROR $ncgear has no \`dynamics\` command" >&2
  exit 1
fi

out=target/check-rotor
mkdir -p "$out"

# The forward-model trajectory of scripts/check_loads.sh (its function, read from there).
eval "$(sed -n '/^make_own_trajectory() {/,/^}/p' scripts/check_loads.sh)"

# ---- cases -----------------------------------------------------------------------------------
cw_traj=assets/cases/exact_cw_offset.csv
cw_center="$(sed -n 's/^# center: *//p' "$cw_traj" | head -1)"
cw_center="${cw_center:-0,0}"
all_cases=(g1_m2 cw_m2 cw_m2_slide kidney own)
[ ${#cases[@]} -eq 0 ] && cases=("${all_cases[@]}")

design_case() { # CASE -> $out/CASE/design/design.json
  local name="$1" dir="$out/$1" traj opts=()
  mkdir -p "$dir"
  case "$name" in
    g1_m2)
      rm -rf "$dir/design"
      mkdir -p "$dir/design"
      cp assets/loads/g1_m2_design.json "$dir/design/design.json"
      echo "check_rotor: g1_m2: the bundled design assets/loads/g1_m2_design.json"
      return 0
      ;;
    cw_m2 | cw_m2_slide) traj="$cw_traj" opts=("--center=$cw_center" --module 2) ;;
    kidney) traj=assets/trajectories/designer_kidney.csv opts=(--module 2) ;;
    own)
      traj="$dir/trajectory.csv"
      make_own_trajectory "$traj" | sed 's/^check_loads:/check_rotor:/'
      ;;
    *)
      echo "check_rotor: ERROR unknown case $name (known: ${all_cases[*]})" >&2
      return 1
      ;;
  esac
  rm -rf "$dir/design"
  local rc=0
  "$ncgear" design "$traj" --out "$dir/design" "${opts[@]}" > "$dir/design.log" 2>&1 || rc=$?
  if [ ! -f "$dir/design/design.json" ]; then
    echo "check_rotor: ERROR ncgear design $traj ${opts[*]} wrote no design.json (exit $rc); see $dir/design.log" >&2
    return 1
  fi
  # exit 3 = a design whose checks failed (a drawn path it cannot trace exactly): still a train
  "$py" - "$dir/design/design.json" "$name" "$rc" << 'EOF'
import json, sys
d = json.load(open(sys.argv[1]))
eps = float(d.get("idler_offset_deg") or 0.0)
teeth = d.get("teeth") or {}
print(f"check_rotor: {sys.argv[2]}: designed (exit {sys.argv[3]}), "
      f"{'CCW' if d['carrier']['direction'] > 0 else 'CW'}, a = {d['center_distance_mm']:.4f} mm, "
      f"idler offset {eps:.3f}°, teeth: {'m = %g, z = %s' % (teeth['module_mm'], teeth['z']) if teeth else 'none'}")
if sys.argv[2].startswith("cw_m2") and (d["carrier"]["direction"] != -1 or abs(eps) < 1e-9):
    sys.exit("check_rotor: cw_m2 was meant to be clockwise with the idler off the line")
EOF
}

write_scenes() { # NAME DIR SCENE -> DIR/SCENE.toml (dynamics) and DIR/SCENE.loads.toml (loads)
  local name="$1" dir="$2" scene="$3" rpm=300.0 arms=2 gravity="[0.0, -1.0]"
  local needle='profile = "planting"' effects
  case "$scene" in
    knock)
      effects='mesh_stiffness = { kind = "constant", c_n_per_mm_mm = 14000.0 }
mesh_damping = { zeta = 0.05 }
backlash = 0.0752
vibration_damping = { zeta = 0.05 }'
      ;;
    smooth)
      effects='mesh_stiffness = { kind = "constant", c_n_per_mm_mm = 14000.0 }
mesh_damping = { zeta = 0.05 }
vibration_damping = { zeta = 0.05 }'
      ;;
    iso_knock)
      effects='mesh_stiffness = { kind = "iso", pairs = "mean" }
mesh_damping = { zeta = 0.05 }
backlash = "teeth"
vibration_damping = { zeta = 0.05 }'
      ;;
    iso_smooth)
      effects='mesh_stiffness = { kind = "iso", pairs = "mean", scale = 3.0 }
mesh_damping = { zeta = [0.04, 0.06] }
vibration_damping = { zeta = 0.05 }'
      ;;
    pairs)
      rpm=250.0 arms=1 gravity="[0.6, -0.8]"
      needle='force_N = [[0, 0, 0], [150, 0, 0], [165, 4, 25], [175, -3, 30], [185, 0, 0]]'
      effects='mesh_stiffness = { kind = "constant", c_n_per_mm_mm = [12000.0, 16000.0] }
mesh_damping = { zeta = [0.03, 0.07] }
backlash = [0.05, 0.1]
vibration_damping = { zeta = 0.08 }'
      ;;
  esac
  local tables="[operation]
carrier_rpm = $rpm
arms = $arms
gravity = $gravity
[arm]
mass_kg = 0.55
com_mm = [35.0, -70.0]
inertia_kg_mm2 = 2100.0
[gears]
face_width_mm = 25.0
density_kg_m3 = 7100.0
bore_mm = 10.0
[needle]
$needle"
  {
    echo '[scene]'
    echo "name = \"${name}_$scene\""
    echo 'model = "rotor"'
    echo 'design = "design/design.json"'
    echo "$tables"
    echo '[effects]'
    echo "$effects"
    echo '[solver]'
    echo 'rtol = 1e-10'
    echo 'atol = 1e-14'
    echo '[steady]'
    echo 'poincare_tol = 1e-6'
    echo 'max_turns = 12'
  } > "$dir/$scene.toml"
  {
    echo 'design = "design/design.json"'
    echo "$tables"
  } > "$dir/$scene.loads.toml"
}

# case: its scenes
plan=(
  "g1_m2 knock smooth pairs iso_knock"
  "cw_m2 smooth iso_smooth"
  "cw_m2_slide knock"
  "kidney knock"
  "own knock"
)

failures=()
summary=()
for name in "${cases[@]}"; do
  scenes=""
  for line in "${plan[@]}"; do
    read -r c rest <<< "$line"
    [ "$c" = "$name" ] && scenes="$rest"
  done
  if ! design_case "$name"; then
    failures+=("$name: design")
    continue
  fi
  dir="$out/$name"
  for scene in $scenes; do
    write_scenes "$name" "$dir" "$scene"
    rm -rf "$dir/dyn_$scene" "$dir/loads_$scene"
    rc=0
    "$ncgear" loads "$dir/$scene.loads.toml" --out "$dir/loads_$scene" > "$dir/loads_$scene.log" 2>&1 || rc=$?
    if [ ! -f "$dir/loads_$scene/loads.json" ]; then
      echo "check_rotor: FAIL $name/$scene: ncgear loads wrote no loads.json (exit $rc); see $dir/loads_$scene.log"
      failures+=("$name/$scene: ncgear loads")
      continue
    fi
    rc=0
    start=$(date +%s.%N)
    "$ncgear" dynamics "$dir/$scene.toml" --out "$dir/dyn_$scene" > "$dir/dyn_$scene.log" 2>&1 || rc=$?
    took=$(echo "$(date +%s.%N) - $start" | bc 2> /dev/null || echo "?")
    if [ ! -f "$dir/dyn_$scene/dynamics.json" ]; then
      echo "check_rotor: FAIL $name/$scene: ncgear dynamics wrote no dynamics.json (exit $rc); see $dir/dyn_$scene.log"
      failures+=("$name/$scene: ncgear dynamics")
      continue
    fi
    [ "$rc" = 0 ] || echo "check_rotor: note $name/$scene: ncgear dynamics exited $rc (see $dir/dyn_$scene.log)"
    echo "== $name/$scene (ncgear dynamics: exit $rc, ${took} s)"
    if "$py" scripts/check_rotor.py "$dir/design/design.json" "$dir/$scene.toml" \
      "$dir/dyn_$scene/dynamics.json" "$dir/loads_$scene/loads.json" --case "$name/$scene" \
      > "$dir/check_$scene.txt" 2>&1; then
      verdict="ok  "
    else
      verdict="FAIL"
      failures+=("$name/$scene")
    fi
    cat "$dir/check_$scene.txt"
    key="$(sed -n 's/^check_rotor: key: //p' "$dir/check_$scene.txt")"
    summary+=("$verdict $(printf '%-18s' "$name/$scene") ${key:-see $dir/check_$scene.txt}")
  done
done

echo
echo "check_rotor: summary"
for s in "${summary[@]}"; do echo "  $s"; done
if [ ${#failures[@]} -gt 0 ]; then
  echo "check_rotor: FAILED: ${failures[*]}"
  exit 1
fi
echo "check_rotor: all cases passed"

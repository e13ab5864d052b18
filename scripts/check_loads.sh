#!/usr/bin/env bash
# Checks `ncgear loads` against an independent rigid-body model (scripts/check_loads.py, numpy
# only, no code shared with the crate). Designs several families with `ncgear design` into
# target/check-loads/CASE/design, writes scenes beside them (300 rpm, one and two arms, gravity on
# and off, an arm with an offset centre of mass, a needle table), runs `ncgear loads` on each and
# checks its loads.json; also checks that without gravity and needle load, doubling the rpm
# multiplies the carrier torque by 4.
#
# Cases: g1 (the bundled exact target, collinear idler), g1_m2 (--module 2: the idler off the
# line), kidney (designer-drawn), kidney_m15 (--module 1.5), cw (assets/cases/exact_cw_offset.csv
# at its own carrier axis, clockwise), cw_m2 (the same with --module 2: clockwise and off-line), own
# (a trajectory made here by a small forward model of a collinear train: sun
# r(θ) = R0(1 + Σ a_k cos kθ + b_k sin kθ), its conjugate intermediate, the planet a copy of the sun).
#
# Python: target/pyvenv if it has numpy, else a venv target/pyvenv-loads with numpy from PyPI;
# without either it prints a WARNING and skips (exit 0), as scripts/check_dxf.sh does.
# Usage: scripts/check_loads.sh [--no-build] [CASE ...]     (NCGEAR=path overrides the binary)
set -euo pipefail
cd "$(dirname "$0")/.."

build=1
cases=()
for arg in "$@"; do
  case "$arg" in
    --no-build) build=0 ;;
    -h | --help)
      sed -n '2,18p' "$0"
      exit 0
      ;;
    *) cases+=("$arg") ;;
  esac
done

# ---- python with numpy -----------------------------------------------------------------------
py=""
for cand in target/pyvenv/bin/python target/pyvenv-loads/bin/python; do
  if [ -x "$cand" ] && "$cand" -c "import numpy, tomllib" 2> /dev/null; then
    py="$cand"
    break
  fi
done
if [ -z "$py" ]; then
  sys_py="$(command -v python3 || true)"
  if [ -z "$sys_py" ]; then
    echo "check_loads: WARNING no python3 found; loads check skipped" >&2
    exit 0
  fi
  if ! "$sys_py" -c "import tomllib" 2> /dev/null; then
    echo "check_loads: WARNING $sys_py is older than 3.11 (no tomllib); loads check skipped" >&2
    exit 0
  fi
  venv=target/pyvenv-loads
  mkdir -p target
  if ! "$sys_py" -m venv "$venv" > /dev/null 2>&1; then
    echo "check_loads: WARNING cannot create a Python venv ($sys_py -m venv); loads check skipped" >&2
    exit 0
  fi
  if ! "$venv/bin/pip" install --quiet --disable-pip-version-check numpy > "$venv/pip.log" 2>&1; then
    echo "check_loads: WARNING pip could not install numpy (no network?); see $venv/pip.log; check skipped" >&2
    exit 0
  fi
  py="$venv/bin/python"
fi
"$py" -c "import numpy, sys; print('check_loads: python', sys.version.split()[0], 'numpy', numpy.__version__)"

# ---- the binary ------------------------------------------------------------------------------
ncgear="${NCGEAR:-target/release/ncgear}"
if [ -z "${NCGEAR:-}" ] && [ "$build" = 1 ]; then
  echo "check_loads: cargo build --release"
  if ! cargo build --release --quiet; then
    echo "check_loads: ERROR cargo build --release failed (--no-build checks the binary there is)" >&2
    exit 1
  fi
fi
if [ ! -x "$ncgear" ]; then
  echo "check_loads: ERROR no binary at $ncgear" >&2
  exit 1
fi
if ! "$ncgear" loads --help > /dev/null 2>&1; then
  echo "check_loads: ERROR $ncgear has no \`loads\` command" >&2
  exit 1
fi

out=target/check-loads
mkdir -p "$out"

# ---- our own trajectory: a small forward model of a collinear train --------------------------
make_own_trajectory() {
  "$py" - "$1" << 'EOF'
import math, sys
import numpy as np

out = sys.argv[1]
R0, l3, beta0 = 22.0, 165.0, -1.2  # sun mean radius, needle length (mm), needle angle at t = 0
harm = [(1, 0.10, 0.03), (2, 0.025, -0.01), (3, 0.0, -0.012)]  # (k, a_k, b_k)
N = 360 * 256
t = 2 * math.pi * np.arange(N) / N
r = R0 * (1 + sum(a * np.cos(k * t) + b * np.sin(k * t) for k, a, b in harm))
lo, hi = r.max() * (1 + 1e-9), 4 * r.max()
for _ in range(200):  # the conjugate closes: mean of r/(a − r) is 1
    a = 0.5 * (lo + hi)
    if np.mean(r / (a - r)) > 1:
        lo = a
    else:
        hi = a
i21 = r / (a - r)  # intermediate over sun, at sun contact angle t
c = np.fft.rfft(i21 - 1.0)
k = np.arange(len(c))
ci = np.zeros_like(c)
ci[1:] = c[1:] / (1j * k[1:])
p = np.fft.irfft(ci, n=N)
Phi = t + p - p[0]  # intermediate rotation ∫_0^t i21
T3 = np.concatenate([t - 2 * math.pi, t, t + 2 * math.pi, [4 * math.pi]])
P3 = np.concatenate([Phi - 2 * math.pi, Phi, Phi + 2 * math.pi, [Phi[0] + 4 * math.pi]])
idx = np.arange(360) * (N // 360)
tk = t[idx]
S = np.interp(Phi[idx] + math.pi, P3, T3)  # planet contact on the sun's copy: Φ⁻¹(Φ + π)
beta = beta0 + tk - (S - S[0])  # needle direction
l1 = 2 * a
x = l1 * np.cos(tk) + l3 * np.cos(beta)
y = l1 * np.sin(tk) + l3 * np.sin(beta)
with open(out, "w") as fh:
    fh.write("x_mm,y_mm\n")
    for xi, yi in zip(x, y):
        fh.write(f"{xi:.9f},{yi:.9f}\n")
print(f"check_loads: own trajectory {out}: a = {a:.6f}, l1 = {l1:.6f}, l3 = {l3} mm, "
      f"i21 in [{i21.min():.3f}, {i21.max():.3f}]")
EOF
}

# ---- cases -----------------------------------------------------------------------------------
cw_traj=assets/cases/exact_cw_offset.csv
cw_center="$(sed -n 's/^# center: *//p' "$cw_traj" | head -1)"
cw_center="${cw_center:-0,0}"
all_cases=(g1 g1_m2 kidney kidney_m15 cw cw_m2 own)
[ ${#cases[@]} -eq 0 ] && cases=("${all_cases[@]}")

design_case() { # CASE -> writes $out/CASE/design/design.json
  local name="$1" dir="$out/$1" traj opts=()
  case "$name" in
    g1) traj=assets/trajectories/g1_ellipse.csv ;;
    g1_m2) traj=assets/trajectories/g1_ellipse.csv opts=(--module 2) ;;
    kidney) traj=assets/trajectories/designer_kidney.csv ;;
    kidney_m15) traj=assets/trajectories/designer_kidney.csv opts=(--module 1.5) ;;
    cw) traj="$cw_traj" opts=("--center=$cw_center") ;;
    cw_m2) traj="$cw_traj" opts=("--center=$cw_center" --module 2) ;;
    own)
      traj="$dir/trajectory.csv"
      mkdir -p "$dir"
      make_own_trajectory "$traj"
      ;;
    *)
      echo "check_loads: ERROR unknown case $name (known: ${all_cases[*]})" >&2
      return 1
      ;;
  esac
  rm -rf "$dir/design"
  mkdir -p "$dir"
  local rc=0
  "$ncgear" design "$traj" --out "$dir/design" "${opts[@]}" > "$dir/design.log" 2>&1 || rc=$?
  if [ ! -f "$dir/design/design.json" ]; then
    echo "check_loads: ERROR ncgear design $traj ${opts[*]} wrote no design.json (exit $rc); see $dir/design.log" >&2
    return 1
  fi
  # exit 3 = a design whose checks failed (e.g. a drawn path it cannot trace exactly): still a train
  "$py" - "$dir/design/design.json" "$name" "$rc" << 'EOF'
import json, sys
d = json.load(open(sys.argv[1]))
eps = float(d.get("idler_offset_deg") or 0.0)
print(f"check_loads: {sys.argv[2]}: designed (exit {sys.argv[3]}), "
      f"{'CCW' if d['carrier']['direction'] > 0 else 'CW'}, a = {d['center_distance_mm']:.4f} mm, "
      f"idler offset {eps:.3f}°, round trip {d['roundtrip']['max_deviation_mm']:.2g} mm")
if sys.argv[2] in ("g1_m2", "kidney_m15", "cw_m2") and abs(eps) < 1e-9:
    sys.exit(f"check_loads: {sys.argv[2]} was meant to put the idler off the line, ε = 0")
if sys.argv[2].startswith("cw") and d["carrier"]["direction"] != -1:
    sys.exit(f"check_loads: {sys.argv[2]} was meant to be clockwise")
EOF
}

write_scene() { # FILE RPM ARMS GRAVITY WITH_ARM WITH_NEEDLE
  local file="$1" rpm="$2" arms="$3" gravity="$4" with_arm="$5" with_needle="$6"
  {
    echo 'design = "design/design.json"'
    echo '[operation]'
    echo "carrier_rpm = $rpm"
    echo "arms = $arms"
    echo "gravity = $gravity"
    if [ "$with_arm" = 1 ]; then
      echo '[arm]'
      echo 'mass_kg = 0.55'
      echo 'com_mm = [35.0, -70.0]'
      echo 'inertia_kg_mm2 = 2100.0'
    fi
    echo '[gears]'
    echo 'face_width_mm = 12.0'
    echo 'density_kg_m3 = 7850.0'
    echo 'bore_mm = 10.0'
    if [ "$with_needle" = 1 ]; then
      echo '[needle]'
      echo 'force_N = [[0, 0, 0], [150, 0, 0], [165, 4, 25], [175, -3, 30], [185, 0, 0]]'
    fi
  } > "$file"
}

# scene name, rpm, arms, gravity, arm, needle
scenes=(
  "inertia 300.0 1 [0.0,0.0] 1 0"
  "inertia_x2 600.0 1 [0.0,0.0] 1 0"
  "field 300.0 2 [0.0,-1.0] 1 1"
  "slanted 300.0 1 [0.6,-0.8] 0 1"
  "twin_inertia 300.0 2 [0.0,0.0] 1 0"
)

failures=()
summary=()
for name in "${cases[@]}"; do
  if ! design_case "$name"; then
    failures+=("$name: design")
    continue
  fi
  dir="$out/$name"
  for line in "${scenes[@]}"; do
    read -r sname rpm arms gravity with_arm with_needle <<< "$line"
    scene="$dir/$sname.toml"
    write_scene "$scene" "$rpm" "$arms" "$gravity" "$with_arm" "$with_needle"
    rm -rf "$dir/loads_$sname"
    rc=0
    "$ncgear" loads "$scene" --out "$dir/loads_$sname" > "$dir/loads_$sname.log" 2>&1 || rc=$?
    if [ ! -f "$dir/loads_$sname/loads.json" ]; then
      echo "check_loads: FAIL $name/$sname: ncgear loads wrote no loads.json (exit $rc); see $dir/loads_$sname.log"
      failures+=("$name/$sname: ncgear loads")
      continue
    fi
    echo "== $name/$sname (rpm $rpm, arms $arms, gravity $gravity, arm $with_arm, needle $with_needle)"
    if "$py" scripts/check_loads.py "$dir/design/design.json" "$scene" "$dir/loads_$sname/loads.json" \
      > "$dir/check_$sname.txt" 2>&1; then
      verdict="ok  "
    else
      verdict="FAIL"
      failures+=("$name/$sname")
    fi
    errors="$(sed -n 's/^check_loads: errors \/ peak: //p' "$dir/check_$sname.txt")"
    summary+=("$verdict $(printf '%-24s' "$name/$sname") ${errors:-see $dir/check_$sname.txt}")
    cat "$dir/check_$sname.txt"
  done
  # doubling the rpm multiplies the carrier torque by 4 (no gravity, no needle)
  if [ -f "$dir/loads_inertia/loads.json" ] && [ -f "$dir/loads_inertia_x2/loads.json" ]; then
    if "$py" - "$dir/loads_inertia/loads.json" "$dir/loads_inertia_x2/loads.json" << 'EOF'; then
import json, sys
import numpy as np
a = np.asarray(json.load(open(sys.argv[1]))["carrier_torque_Nm"], dtype=float)
b = np.asarray(json.load(open(sys.argv[2]))["carrier_torque_Nm"], dtype=float)
peak = float(np.max(np.abs(4 * a)))
err = float(np.max(np.abs(b - 4 * a))) / peak if a.shape == b.shape and peak > 0 else float("inf")
ok = err <= 1e-6
print(f"check_loads: {'ok  ' if ok else 'FAIL'} rpm x2 -> carrier torque x4: max |T600 - 4 T300| / peak = {err:.3e} (limit 1e-6)")
sys.exit(0 if ok else 1)
EOF
      summary+=("ok   $(printf '%-24s' "$name/rpm-scaling") T(600 rpm) = 4·T(300 rpm)")
    else
      failures+=("$name/rpm-scaling")
      summary+=("FAIL $(printf '%-24s' "$name/rpm-scaling") T(600 rpm) ≠ 4·T(300 rpm)")
    fi
  fi
done

echo
echo "check_loads: summary"
for s in "${summary[@]}"; do echo "  $s"; done
if [ ${#failures[@]} -gt 0 ]; then
  echo "check_loads: FAILED: ${failures[*]}"
  exit 1
fi
echo "check_loads: all cases passed"

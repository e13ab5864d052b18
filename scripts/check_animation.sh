#!/usr/bin/env bash
# Proves that the animated SVG of `ncgear simulate` opens and plays in headless Chromium
# (Debian package `chromium`): two screenshots at different virtual times must both show the
# mechanism and must differ. Usage: scripts/check_animation.sh [OUT_DIR]
# Also used to regenerate the README frame: cp OUT_DIR/frame_1500.png assets/readme/animation_frame.png
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-target/anim-check}"
browser="$(command -v chromium || command -v chromium-browser || command -v google-chrome || true)"
if [ -z "$browser" ]; then
  echo "check_animation: no Chromium found (apt-get install chromium); skipped" >&2
  exit 0
fi
mkdir -p "$out"
abs="$(cd "$out" && pwd)"   # OUT_DIR may be relative or absolute
cargo run --release --quiet -- design assets/trajectories/g1_ellipse.csv --out "$out/design" > /dev/null
cargo run --release --quiet -- simulate "$out/design/design.json" --out "$out/sim" > /dev/null
svg="$out/sim/animation.svg"
# Size in mm → CSS px (96/25.4), rendered at 0.5 device scale.
root=$(tr '\n' ' ' < "$svg" | grep -o '<svg[^>]*>' | head -1)
w=$(sed -n 's/.* width="\([0-9.]*\)mm".*/\1/p' <<< "$root")
h=$(sed -n 's/.* height="\([0-9.]*\)mm".*/\1/p' <<< "$root")
pw=$(awk -v v="$w" 'BEGIN{printf "%d", v*96/25.4*0.5+2}')
ph=$(awk -v v="$h" 'BEGIN{printf "%d", v*96/25.4*0.5+2}')
for t in 100 1500; do
  "$browser" --headless --no-sandbox --disable-gpu --hide-scrollbars --force-device-scale-factor=0.5 \
    --window-size="$((pw * 2)),$((ph * 2))" --virtual-time-budget="$t" \
    --screenshot="$abs/frame_$t.png" "file://$abs/sim/animation.svg" > /dev/null 2>&1
  size=$(stat -c %s "$out/frame_$t.png")
  [ "$size" -gt 5000 ] || { echo "check_animation: frame at ${t} ms is empty ($size bytes)" >&2; exit 1; }
done
if cmp -s "$out/frame_100.png" "$out/frame_1500.png"; then
  echo "check_animation: the animation does not move (frames at 100 ms and 1500 ms are identical)" >&2
  exit 1
fi
echo "check_animation: animation.svg renders and plays in $(basename "$browser") (frames differ)"

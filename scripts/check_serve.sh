#!/usr/bin/env bash
# The interactive designer (`ncgear serve`) driven in headless Chromium by Playwright for
# Python (scripts/check_serve.py). Installs Debian's chromium when it is missing and this runs as
# root with apt (CI); Playwright comes from PyPI into a venv under target/ (its own browser
# download is not used: the system Chromium is). Needs target/release/ncgear.
# Usage: scripts/check_serve.sh [SCREENSHOT_DIR]   (the README's pictures: docs/img)
set -euo pipefail
cd "$(dirname "$0")/.."
browser="$(command -v chromium || true)"
if [ -z "$browser" ] && [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
  (apt-get install -y --no-install-recommends chromium > /dev/null 2>&1 \
    || { apt-get update > /dev/null 2>&1 && apt-get install -y --no-install-recommends chromium > /dev/null 2>&1; }) || true
  browser="$(command -v chromium || true)"
fi
if [ -z "$browser" ]; then
  echo "check_serve: no Chromium (apt-get install chromium) — the browser test cannot run" >&2
  exit 1
fi
venv=target/serve-venv
[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
"$venv/bin/pip" install -q "playwright==1.*"
"$venv/bin/python" scripts/check_serve.py target/release/ncgear "$browser" "$@"
# The server under load (scripts/serve_load.py, standard library only, loopback): 4 clients
# dragging like the page for 15 s after an 8 s single-client reference, abandoned requests
# alongside; no 5xx or dropped connection, no abandoned request drawn or answered, resident memory
# flat after the first 7 s, p95 under load within 4× one client's (the goal, 2×, is measured
# over 2 minutes: docs/serve.md, "Under load"). Bounded: 55 s at most (≈ 32 s).
python3 scripts/serve_load.py --bin target/release/ncgear --clients 4 --single 8 --disconnects 3 \
  --duration 15 --warmup 7 --max-requests 300 --timeout 55 --check \
  --max-ratio 4 --max-growth-mb 24 --max-abandoned-cost 1.5

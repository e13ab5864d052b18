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

#!/usr/bin/env bash
# Proves that every DXF the tests wrote (target/test-dxf) is readable by an independent program:
# installs the Python `ezdxf` package (PyPI) into a venv under target/pyvenv and runs
# tests/ezdxf_check.py (closed LWPOLYLINEs in mm, no SPLINE, vertices on the outline point lists).
# Without Python or without network access to PyPI it prints a warning and skips (exit 0);
# a DXF that fails the check fails the script. Usage: scripts/check_dxf.sh [DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
dir="${1:-target/test-dxf}"
py="$(command -v python3 || true)"
if [ -z "$py" ]; then
  echo "check_dxf: WARNING no python3 found; ezdxf check skipped" >&2
  exit 0
fi
venv=target/pyvenv
if [ ! -x "$venv/bin/python" ] || ! "$venv/bin/python" -c "import ezdxf" 2> /dev/null; then
  if ! "$py" -m venv "$venv" > /dev/null 2>&1; then
    echo "check_dxf: WARNING cannot create a Python venv ($py -m venv); ezdxf check skipped" >&2
    exit 0
  fi
  if ! "$venv/bin/pip" install --quiet --disable-pip-version-check ezdxf > "$venv/pip.log" 2>&1; then
    echo "check_dxf: WARNING pip could not install ezdxf (no network?); see $venv/pip.log; check skipped" >&2
    exit 0
  fi
fi
"$venv/bin/python" -c "import ezdxf; print('check_dxf: ezdxf', ezdxf.__version__)"
"$venv/bin/python" tests/ezdxf_check.py "$dir"

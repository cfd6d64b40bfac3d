#!/usr/bin/env bash
# Creates .venv/ with the real programs the export tests run against
# (tests/clients/requirements.txt: Blender's bpy with Cycles, the OpenEXR
# bindings, MaterialX, PyYAML, SciPy). Does nothing when .venv already holds
# exactly those versions. Needs Python 3.11 (bpy 5.0 is built for it).
set -euo pipefail
cd "$(dirname "$0")/.."
req=tests/clients/requirements.txt
stamp=.venv/.requirements
if [ -x .venv/bin/python ] && cmp -s "$req" "$stamp"; then
    exit 0
fi
py=""
for cand in python3.11 python3; do
    if command -v "$cand" >/dev/null 2>&1 &&
        "$cand" -c 'import sys; sys.exit(sys.version_info[:2] != (3, 11))' 2>/dev/null; then
        py=$cand
        break
    fi
done
if [ -z "$py" ]; then
    echo "tools/python-env.sh: Python 3.11 is needed for Blender's bpy 5.0 (Debian: apt-get install python3.11 python3.11-venv)" >&2
    exit 1
fi
echo "tools/python-env.sh: installing $(grep -vc '^#' "$req") packages into .venv (bpy is ~370 MB)" >&2
rm -rf .venv
"$py" -m venv .venv
.venv/bin/python -m pip install --quiet --disable-pip-version-check -r "$req"
cp "$req" "$stamp"

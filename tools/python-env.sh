#!/usr/bin/env bash
# Creates the virtual environments the export tests run the real programs
# in: .venv/ (tests/clients/requirements.txt: Blender 5.0's bpy with
# Cycles, the OpenEXR bindings, MaterialX, PyYAML, godot-parser, SciPy) and
# .venv-blender4/ (requirements-blender4.txt: Blender 4.5 LTS, for the 4.x
# check; one Python holds one bpy). Leaves a venv alone when it already
# holds exactly those versions. Needs Python 3.11 (bpy 4.5 and 5.0 are
# built for it).
set -euo pipefail
cd "$(dirname "$0")/.."
py=""
for cand in python3.11 python3; do
    if command -v "$cand" >/dev/null 2>&1 &&
        "$cand" -c 'import sys; sys.exit(sys.version_info[:2] != (3, 11))' 2>/dev/null; then
        py=$cand
        break
    fi
done
make_venv() {
    local dir=$1 req=$2
    if [ -x "$dir/bin/python" ] && cmp -s "$req" "$dir/.requirements"; then
        return 0
    fi
    if [ -z "$py" ]; then
        echo "tools/python-env.sh: Python 3.11 is needed for Blender's bpy (Debian: apt-get install python3.11 python3.11-venv)" >&2
        exit 1
    fi
    echo "tools/python-env.sh: installing $(grep -vc '^#' "$req") packages into $dir (bpy is ~370 MB)" >&2
    rm -rf "$dir"
    "$py" -m venv "$dir"
    "$dir/bin/python" -m pip install --quiet --disable-pip-version-check -r "$req"
    cp "$req" "$dir/.requirements"
}
make_venv .venv tests/clients/requirements.txt
make_venv .venv-blender4 tests/clients/requirements-blender4.txt

#!/usr/bin/env bash
# Installs the npm packages the glTF export tests run, at the versions
# tests/clients/node/package-lock.json pins, into tests/clients/node/
# node_modules/ (as tools/python-env.sh does for Python): Khronos'
# gltf-validator and Babylon.js's core and loaders. Leaves them alone when
# they already hold exactly those versions. Needs node and npm
# (tools/setup-debian.sh installs Debian's).
set -euo pipefail
cd "$(dirname "$0")/../tests/clients/node"
if ! command -v npm >/dev/null 2>&1; then
    echo "tools/node-env.sh: npm is missing (Debian: apt-get install nodejs npm, or run tools/setup-debian.sh)" >&2
    exit 1
fi
if [ -d node_modules ] && cmp -s package-lock.json node_modules/.scatterlab-lock; then
    exit 0
fi
echo "tools/node-env.sh: installing gltf-validator and Babylon.js (about 110 MB) into tests/clients/node/node_modules" >&2
rm -rf node_modules
npm ci --no-audit --no-fund --loglevel=error
cp package-lock.json node_modules/.scatterlab-lock

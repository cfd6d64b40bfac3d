#!/usr/bin/env bash
# Installs what the editor and the tests need beyond the Rust toolchain on a
# Debian or Ubuntu machine, and nothing when it is all there:
# - lavapipe (Mesa's CPU Vulkan driver) and the Vulkan loader: the renderer
#   runs on it where there is no GPU, and the GPU tests are never skipped;
# - Mesa's EGL and llvmpipe GL: a test renders on wgpu's GL backend too;
# - Xvfb, xdotool and the X client libraries winit loads: the window tests run the
#   real editor under Xvfb and type into it, and tools/soak.sh drives it;
# - the libraries Blender's bpy links (libGL, X) and Python 3.11 with venv:
#   tools/python-env.sh installs the real programs the export tests run;
# - Node.js and npm (Debian's nodejs and npm) where the machine has no
#   node: tools/node-env.sh installs Khronos' glTF validator and Babylon.js,
#   which the glTF export tests run.
# As root it runs apt-get; otherwise it uses sudo if that needs no password,
# and else prints the one command to run and fails. On a system without
# dpkg it only says what it would need.
set -euo pipefail

# The test command runs rustfmt and clippy first: add them to a toolchain
# installed without them (rustup's minimal profile).
if command -v rustup >/dev/null 2>&1; then
    for c in rustfmt clippy; do
        if ! cargo "${c/rustfmt/fmt}" --version >/dev/null 2>&1; then
            rustup component add "$c"
        fi
    done
fi

if ! command -v dpkg >/dev/null 2>&1; then
    echo "tools/setup-debian.sh: not a Debian system; make sure a Vulkan driver, Xvfb and Python 3.11 with venv are installed" >&2
    exit 0
fi

need=()
[ -e /usr/share/vulkan/icd.d/lvp_icd.x86_64.json ] || [ -e /usr/share/vulkan/icd.d/lvp_icd.json ] ||
    [ -e /usr/share/vulkan/icd.d/lvp_icd.aarch64.json ] || need+=(mesa-vulkan-drivers)
for pkg in libvulkan1 xvfb xdotool libx11-6 libx11-xcb1 libxcursor1 libxrandr2 libxi6 libxkbcommon-x11-0 \
    libxkbcommon0 libxrender1 libxfixes3 libxext6 libsm6 libice6 libgl1 libegl1 libegl-mesa0 \
    libgl1-mesa-dri; do
    dpkg -s "$pkg" >/dev/null 2>&1 || need+=("$pkg")
done
command -v cc >/dev/null 2>&1 || need+=(build-essential)
command -v node >/dev/null 2>&1 || need+=(nodejs)
command -v npm >/dev/null 2>&1 || need+=(npm)
if ! { command -v python3.11 >/dev/null 2>&1 && python3.11 -c 'import venv, ensurepip' >/dev/null 2>&1; }; then
    need+=(python3.11 python3.11-venv)
fi
[ ${#need[@]} -eq 0 ] && exit 0

if [ "$(id -u)" -eq 0 ]; then
    run=()
elif command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then
    run=(sudo -n)
else
    echo "tools/setup-debian.sh: missing packages; run: sudo apt-get install -y --no-install-recommends ${need[*]}" >&2
    exit 1
fi
echo "tools/setup-debian.sh: installing ${need[*]}" >&2
export DEBIAN_FRONTEND=noninteractive
"${run[@]}" apt-get update -qq
"${run[@]}" apt-get install -y -qq --no-install-recommends "${need[@]}" >/dev/null

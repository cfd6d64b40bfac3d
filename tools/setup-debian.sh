#!/usr/bin/env bash
# Installs what the editor and the tests need beyond the Rust toolchain on a
# Debian or Ubuntu machine, and nothing when it is all there:
# - lavapipe (Mesa's CPU Vulkan driver), version 25 or newer, and the Vulkan
#   loader: the renderer runs on it where there is no GPU, and the GPU tests
#   are never skipped. Mesa 25's lavapipe is faster than Debian 12's 22.3 on
#   the live viewport and offers ray queries (docs/rendering.md, "Drivers").
#   Debian 12 ships 22.3.6: there it comes from Debian's own
#   bookworm-backports, added with the archive address this machine's apt
#   sources already use (no host is written here), and only
#   mesa-vulkan-drivers and the libdrm it needs are taken from it, by name.
#   Elsewhere the release's newest is installed; where that is older than
#   25 the renderer still runs on it, and names it;
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
    echo "tools/setup-debian.sh: not a Debian system; make sure a Vulkan driver (Mesa's lavapipe 25 or newer where there is no GPU), Xvfb and Python 3.11 with venv are installed" >&2
    exit 0
fi

LAVAPIPE_MIN=25
# The installed lavapipe's package version ("" when none is installed).
lavapipe_version() {
    local v
    v="$(dpkg-query -W -f='${Status} ${Version}' mesa-vulkan-drivers 2>/dev/null || true)"
    if [[ "$v" == "install ok installed "* ]]; then echo "${v##* }"; fi
}
lavapipe_is_new() {
    local v
    v="$(lavapipe_version)"
    [ -n "$v" ] && dpkg --compare-versions "$v" ge "$LAVAPIPE_MIN~"
}
# Debian 12 (bookworm) has lavapipe >= 25 in its backports suite.
codename=""
if [ -r /etc/os-release ]; then
    codename="$(. /etc/os-release && if [ "${ID:-}" = debian ]; then echo "${VERSION_CODENAME:-}"; fi)"
fi
backports=""
[ "$codename" = bookworm ] && backports="bookworm-backports"

need=()
lavapipe=()
if ! lavapipe_is_new; then
    if [ -n "$backports" ]; then
        # By name from the backports suite: the driver and the libdrm its
        # package depends on (libdrm2 and libdrm-amdgpu1 >= 2.4.121, where
        # Debian 12 has 2.4.114); everything else stays Debian 12's.
        lavapipe=("mesa-vulkan-drivers/$backports" "libdrm2/$backports" "libdrm-common/$backports"
            "libdrm-amdgpu1/$backports")
    else
        lavapipe=(mesa-vulkan-drivers)
    fi
fi
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
[ ${#need[@]} -eq 0 ] && [ ${#lavapipe[@]} -eq 0 ] && exit 0

# The address of the Debian archive this machine's apt already uses for the
# suite $1, from deb822 .sources files or one-line .list files, with its
# Signed-By key where one is given: prints "URI<TAB>KEY".
archive_of() {
    local suite="$1" f
    for f in /etc/apt/sources.list.d/*.sources; do
        [ -r "$f" ] || continue
        # Stanzas are separated by blank lines: the first enabled "deb"
        # stanza whose Suites list the suite.
        awk -v suite="$suite" '
            function flush() {
                if (!found && (" " types " ") ~ / deb / && enabled != "no" && (" " suites " ") ~ (" " suite " ") && uris != "") {
                    split(uris, u, " "); print u[1] "\t" key; found = 1
                }
                types = ""; suites = ""; uris = ""; key = ""; enabled = ""
            }
            /^[ \t]*$/ { flush(); next }
            /^[ \t]*#/ { next }
            tolower($1) == "types:" { $1 = ""; types = $0 }
            tolower($1) == "suites:" { $1 = ""; suites = $0 }
            tolower($1) == "uris:" { $1 = ""; uris = $0 }
            tolower($1) == "enabled:" { enabled = tolower($2) }
            tolower($1) == "signed-by:" { key = $2 }
            END { flush() }
        ' "$f" | head -1 | grep . && return 0
    done
    for f in /etc/apt/sources.list /etc/apt/sources.list.d/*.list; do
        [ -r "$f" ] || continue
        # deb [option=value ...] URI suite component...
        awk -v suite="$suite" '
            $1 == "deb" {
                i = 2; key = ""
                if ($2 ~ /^\[/) {
                    for (; i <= NF; i++) {
                        o = $i; sub(/^\[/, "", o); sub(/\]$/, "", o)
                        if (o ~ /^signed-by=/) { key = o; sub(/^signed-by=/, "", key) }
                        if ($i ~ /\]$/) { i++; break }
                    }
                }
                if ($(i + 1) == suite) { print $i "\t" key; exit }
            }' "$f" | head -1 | grep . && return 0
    done
    return 1
}
# Whether an apt source already names the suite $1.
has_suite() {
    local f
    for f in /etc/apt/sources.list /etc/apt/sources.list.d/*.list /etc/apt/sources.list.d/*.sources; do
        [ -r "$f" ] && grep -v '^[[:space:]]*#' "$f" | grep -qE "(^|[[:space:]])$1([[:space:]]|$)" && return 0
    done
    return 1
}

if [ "$(id -u)" -eq 0 ]; then
    run=()
elif command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then
    run=(sudo -n)
elif [ ${#lavapipe[@]} -gt 0 ] && [ -n "$backports" ]; then
    echo "tools/setup-debian.sh: missing packages (${need[*]} ${lavapipe[*]}; lavapipe >= $LAVAPIPE_MIN from Debian's $backports); run it as root: sudo tools/setup-debian.sh" >&2
    exit 1
else
    echo "tools/setup-debian.sh: missing packages; run: sudo apt-get install -y --no-install-recommends ${need[*]} ${lavapipe[*]}" >&2
    exit 1
fi
export DEBIAN_FRONTEND=noninteractive
if [ ${#lavapipe[@]} -gt 0 ] && [ -n "$backports" ] && ! has_suite "$backports"; then
    if ! line="$(archive_of "$codename")"; then
        echo "tools/setup-debian.sh: lavapipe >= $LAVAPIPE_MIN comes from Debian's $backports, but no apt source for $codename was found to take the archive's address from; add $backports to /etc/apt/sources.list.d/ and run this again" >&2
        exit 1
    fi
    uri="${line%%$'\t'*}"
    key="${line#*$'\t'}"
    list="/etc/apt/sources.list.d/$backports.sources"
    echo "tools/setup-debian.sh: adding Debian's $backports from $uri ($list), for lavapipe >= $LAVAPIPE_MIN" >&2
    {
        echo "# Added by scatterlab's tools/setup-debian.sh for Mesa's lavapipe >= $LAVAPIPE_MIN."
        echo "# apt takes nothing from backports unless it is named (priority 100)."
        echo "Types: deb"
        echo "URIs: $uri"
        echo "Suites: $backports"
        echo "Components: main"
        if [ -n "$key" ]; then echo "Signed-By: $key"; fi
    } | "${run[@]}" tee "$list" >/dev/null
fi
echo "tools/setup-debian.sh: installing $(echo "${need[@]}" "${lavapipe[@]}")" >&2
"${run[@]}" apt-get update -qq
"${run[@]}" apt-get install -y -qq --no-install-recommends "${need[@]}" "${lavapipe[@]}" >/dev/null
if ! lavapipe_is_new; then
    echo "tools/setup-debian.sh: note: lavapipe is Mesa $(lavapipe_version), older than $LAVAPIPE_MIN and the newest this release's archive has: the renderer runs on it, slower and without ray queries" >&2
fi

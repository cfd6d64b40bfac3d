#!/usr/bin/env bash
# Measures how live the editor's viewport is, as an artist uses it: the
# release editor under Xvfb at its default window (1500×900), driven by
# xdotool. It drags an orbit, then the red scattering distance (a drag
# value in the Look panel), each for DRAG_S seconds, and reads the frame
# log the editor writes (SCATTERLAB_FRAME_LOG: one line per viewport frame
# with its kind — preview, refining, converged — and one per UI frame).
#
# Reports, for each drag: viewport frames per second while dragging (the
# previews), UI frames per second, the previews' resolution, and the time
# from releasing the mouse to the "converged" frame.
#
# Then the ground truth: a second editor on the default skin with the
# method `reference`; after an orbit drag, the time from release to the
# first frame of ground-truth tiles (full resolution, over burley's frame)
# and to the full truth, and how far the time left the status bar showed
# was from the time it then took (each tiles frame with over 1 s left).
#
#   tools/measure_live.sh [--out FILE.md]
#
# Needs Xvfb (tools/setup-debian.sh installs it), xdotool and ImageMagick
# (apt-get install xdotool imagemagick). docs/rendering.md records its
# figures.
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=""
if [[ "${1:-}" == "--out" ]]; then OUT="$2"; fi
DRAG_S="${DRAG_S:-4}"
for t in Xvfb xdotool import python3; do
    command -v "$t" >/dev/null || { echo "error: $t is missing (apt-get install xvfb xdotool imagemagick python3)" >&2; exit 1; }
done
cargo build --release --quiet
BIN="$PWD/target/release/scatterlab"
WORK="$(mktemp -d)"
DISP=":$((90 + RANDOM % 100))"
cleanup() {
    [[ -n "${EDITOR_PID:-}" ]] && kill "$EDITOR_PID" 2>/dev/null || true
    [[ -n "${XVFB_PID:-}" ]] && kill "$XVFB_PID" 2>/dev/null || true
    # KEEP_LOG=FILE keeps the frame log.
    [[ -n "${KEEP_LOG:-}" && -f "${LOG:-}" ]] && cp "$LOG" "$KEEP_LOG"
    rm -rf "$WORK"
}
trap cleanup EXIT
Xvfb "$DISP" -screen 0 1600x1000x24 >/dev/null 2>&1 &
XVFB_PID=$!
sleep 1
mkdir -p "$WORK/run" "$WORK/data" "$WORK/config"
chmod 700 "$WORK/run"
LOG="$WORK/frames.log"
# METHOD=<preset variant> (e.g. TextureSpace) measures the drags with that
# method instead of the default skin's.
PRESET_ARGS=()
if [[ -n "${METHOD:-}" ]]; then
    sed "s|^    profile: |    rendering: (method: $METHOD),\n    profile: |" presets/skin_default.ron >"$WORK/method.ron"
    grep -q "method: $METHOD" "$WORK/method.ron" || { echo "error: could not write the $METHOD preset" >&2; exit 1; }
    PRESET_ARGS=(--preset "$WORK/method.ron")
fi
# A fresh state directory: the default window size and layout.
DISPLAY="$DISP" XDG_RUNTIME_DIR="$WORK/run" XDG_DATA_HOME="$WORK/data" \
    XDG_CONFIG_HOME="$WORK/config" SCATTERLAB_FRAME_LOG="$LOG" \
    "$BIN" edit "${PRESET_ARGS[@]}" >"$WORK/editor.out" 2>&1 &
EDITOR_PID=$!
export DISPLAY="$DISP"

wait_for() { # wait_for <regex> <after-time> <timeout-s>
    local deadline=$((SECONDS + $3))
    while ((SECONDS < deadline)); do
        if [[ -f "$LOG" ]] && awk -v t="$2" -v re="$1" '$1 > t && $0 ~ re {f=1} END {exit !f}' "$LOG"; then
            return 0
        fi
        sleep 0.1
    done
    echo "error: no '$1' frame after $2 within $3 s; the editor said:" >&2
    cat "$WORK/editor.out" >&2
    exit 1
}
now() { date +%s.%N; }

wait_for "converged" 0 180
WID="$(xdotool search --sync --name scatterlab | head -1)"
xdotool windowactivate --sync "$WID" 2>/dev/null || true
# Let start-up work (skin maps, the analysis thread) finish.
sleep 3
wait_for "converged" 0 60

# drag <x> <y> <dx per step>: press, move in 30 ms steps for DRAG_S, release.
drag() {
    xdotool mousemove --window "$WID" "$1" "$2"
    sleep 0.3
    xdotool mousedown 1
    local steps=$((DRAG_S * 1000 / 30))
    DOWN="$(now)"
    for ((i = 0; i < steps; i++)); do
        xdotool mousemove_relative -- "$3" 0
        sleep 0.03
    done
    UP="$(now)"
    xdotool mouseup 1
}

# The orbit: the viewport's middle (window coordinates at 1500×900).
drag 730 480 3
ORBIT=("$DOWN" "$UP")
wait_for "converged" "$UP" 30
sleep 1
# The red scattering distance: its drag value in the Look panel (1 px =
# 0.01 mm; 1 px a step keeps it in 0.76–1.9 mm over the drag).
drag 173 161 1
SLIDER=("$DOWN" "$UP")
wait_for "converged" "$UP" 30
sleep 0.5
import -window root "$WORK/after.png" 2>/dev/null || true
[[ -n "${KEEP_AFTER:-}" ]] && cp "$WORK/after.png" "$KEEP_AFTER"

# The ground truth as the viewport's method: the default skin with
# method Reference, in a second editor with its own state.
kill "$EDITOR_PID" 2>/dev/null || true
wait "$EDITOR_PID" 2>/dev/null || true
sed 's|^    profile: |    rendering: (method: Reference),\n    profile: |' presets/skin_default.ron >"$WORK/truth.ron"
grep -q "method: Reference" "$WORK/truth.ron" || { echo "error: could not write the reference preset" >&2; exit 1; }
TRUTH_LOG="$WORK/truth.log"
mkdir -p "$WORK/data2" "$WORK/config2"
DISPLAY="$DISP" XDG_RUNTIME_DIR="$WORK/run" XDG_DATA_HOME="$WORK/data2" \
    XDG_CONFIG_HOME="$WORK/config2" SCATTERLAB_FRAME_LOG="$TRUTH_LOG" \
    "$BIN" edit --preset "$WORK/truth.ron" >"$WORK/editor2.out" 2>&1 &
EDITOR_PID=$!
LOG="$TRUTH_LOG"
wait_for "converged.*method=reference" 0 300
WID="$(xdotool search --sync --name scatterlab | head -1)"
xdotool windowactivate --sync "$WID" 2>/dev/null || true
sleep 1
drag 730 480 3
TRUTH=("$DOWN" "$UP")
wait_for "converged.*method=reference" "$UP" 300
import -window root "$WORK/truth.png" 2>/dev/null || true
[[ -n "${KEEP_SHOT:-}" ]] && cp "$WORK/truth.png" "$KEEP_SHOT"

python3 - "$WORK/frames.log" "${ORBIT[@]}" "${SLIDER[@]}" "$OUT" "$TRUTH_LOG" "${TRUTH[@]}" <<'EOF'
import sys, statistics
log, o0, o1, s0, s1, out = sys.argv[1], *map(float, sys.argv[2:6]), sys.argv[6]
truth_log, t0, t1 = sys.argv[7], float(sys.argv[8]), float(sys.argv[9])
rows = [l.split() for l in open(log)]
def report(name, t0, t1):
    # Skip the first 0.3 s (the drag threshold and the first preview).
    a = t0 + 0.3
    prev = [r for r in rows if r[1] == "frame" and r[2] == "preview" and a < float(r[0]) <= t1]
    ui = [r for r in rows if r[1] == "ui" and a < float(r[0]) <= t1]
    conv = [float(r[0]) for r in rows if r[1] == "frame" and r[2] == "converged" and float(r[0]) > t1]
    refine = [r for r in rows if r[1] == "frame" and r[2] == "refining" and t1 < float(r[0]) <= conv[0]]
    span = t1 - a
    px = sorted((int(r[3].split("x")[0]) * int(r[3].split("x")[1]), r[3]) for r in prev)
    sizes = [px[0][1], px[-1][1]] if px else ["none"]
    ms = [float(r[5].split("=")[1]) for r in prev]
    full = [r[3] for r in rows if r[1] == "frame" and r[2] == "converged" and float(r[0]) > t1][0]
    return (f"| {name} | {len(prev)/span:.1f} | {len(ui)/span:.1f} | {' to '.join(sizes)} "
            f"| {statistics.median(ms) if ms else float('nan'):.0f} | {full} "
            f"| {conv[0]-t1:.2f} | {len(refine)+1} |")
lines = [
    "| drag | viewport frames/s while dragging | UI frames/s | preview sizes | median preview render (ms) | full size | release → converged (s) | full-size frames |",
    "|---|---|---|---|---|---|---|---|",
    report("orbit", o0, o1),
    report("scattering distance", s0, s1),
]
truth = [l.split() for l in open(truth_log)]
def first(kind):
    hits = [r for r in truth if r[1] == "frame" and r[2] == kind and float(r[0]) > t1
            and "method=reference" in r]
    return (float(hits[0][0]) - t1, hits[0][3]) if hits else (float("nan"), "none")
tiles, full = first("truth-tiles"), first("converged")
# Each tiles frame that showed a time left: that against the time the
# truth then took (frames with over 1 s still to go).
done_at = t1 + full[0]
errors = []
for r in truth:
    if r[1] == "frame" and r[2] == "truth-tiles" and float(r[0]) > t1:
        left = [f.split("=")[1] for f in r if f.startswith("left_s=")]
        if left and left[0] != "none" and done_at - float(r[0]) > 1.0:
            actual = done_at - float(r[0])
            errors.append(abs(float(left[0]) - actual) / actual)
errors.sort()
median = errors[len(errors) // 2] if errors else float("nan")
worst = errors[-1] if errors else float("nan")
lines += [
    "",
    "| ground truth after an orbit | release → first tiles (s) | tiles' size | release → full truth (s) | full size | time left shown: median / worst error |",
    "|---|---|---|---|---|---|",
    f"| reference | {tiles[0]:.2f} | {tiles[1]} | {full[0]:.2f} | {full[1]} | {100*median:.0f} % / {100*worst:.0f} % ({len(errors)} frames) |",
]
print("\n".join(lines))
if out:
    open(out, "w").write("\n".join(lines) + "\n")
EOF

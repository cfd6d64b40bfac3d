#!/usr/bin/env bash
# Screenshots of the editor for docs/images: its compare views (split, side
# by side and difference) at 1280×720 and at the default window
# (1500×900), B the same look without SSS (`none`), and the editor alone
# at the default window (editor.png, the README's). The release editor
# under Xvfb, a fresh state directory each time; each shot is taken once
# the viewport reports "converged" in its frame log.
#
#   tools/editor_screenshots.sh [OUT_DIR]    (default docs/images)
set -euo pipefail
cd "$(dirname "$0")/.."
OUT="${1:-docs/images}"
mkdir -p "$OUT"
cargo build --release --quiet
BIN="$PWD/target/release/scatterlab"
# shot <WxH> <compare mode or "off"> <out.png>
shot() {
    local size="$1" mode="$2" out="$3"
    local W="${size%x*}" H="${size#*x}"
    local WORK DISP XVFB ED WID RESIZED
    WORK="$(mktemp -d)"
    DISP=":$((200 + RANDOM % 100))"
    Xvfb "$DISP" -screen 0 "${W}x${H}x24" >/dev/null 2>&1 &
    XVFB=$!
    sleep 1
    mkdir -p "$WORK/run"; chmod 700 "$WORK/run"
    local args=(edit)
    if [[ "$mode" != off ]]; then args+=(--compare "$mode" --compare-b none); fi
    DISPLAY="$DISP" XDG_RUNTIME_DIR="$WORK/run" XDG_DATA_HOME="$WORK/data" \
        XDG_CONFIG_HOME="$WORK/config" SCATTERLAB_FRAME_LOG="$WORK/frames.log" \
        "$BIN" "${args[@]}" >"$WORK/out" 2>&1 &
    ED=$!
    WID="$(DISPLAY="$DISP" xdotool search --sync --name scatterlab | head -1)"
    DISPLAY="$DISP" xdotool windowsize "$WID" "$W" "$H"
    RESIZED="$(date +%s.%N)"
    # Converged after the resize (earlier frames may be the old size).
    for _ in $(seq 600); do
        sleep 0.2
        if awk -v t="$RESIZED" '$1 > t && $3 == "converged" {f=1} END {exit !f}' \
            "$WORK/frames.log" 2>/dev/null; then
            break
        fi
    done
    # The pointer off the viewport: its tooltip would cover the status bar.
    DISPLAY="$DISP" xdotool mousemove 2 "$((H - 2))"
    sleep 1
    DISPLAY="$DISP" import -window root "$out"
    echo "wrote $out"
    kill "$ED" "$XVFB" 2>/dev/null || true
    wait "$ED" 2>/dev/null || true
    rm -rf "$WORK"
}

for size in 1280x720 1500x900; do
    for mode in split side-by-side difference; do
        shot "$size" "$mode" "$OUT/editor_compare_${mode}_${size}.png"
    done
done
# The README's picture: the default window, no compare.
shot 1500x900 off "$OUT/editor.png"

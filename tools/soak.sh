#!/usr/bin/env bash
# Drives the real editor under Xvfb with random artist input for a while and
# reports what an hour of use would show: frames drawn, peak and final
# resident memory, memory growth after the first minute, and panics.
#
#   tools/soak.sh [MINUTES] [OUT_DIR]     (default 20 minutes, /tmp/scatterlab-soak)
#
# Needs Xvfb and xdotool (tools/setup-debian.sh installs both) and a release
# build (built here if missing). The window is 1280×720; the actions are
# the editor's own controls at fixed places in that layout (checked against
# screenshots): orbit and light drags over the viewport, drags on the
# parameter panel's fields (random edits), undo/redo, the before/after
# flicker, the compare modes and "refine to the truth", switching presets
# (File → New from preset), loading a scan in its own units and going back
# to the default head (File → Load mesh…, its units prompt, File → Default
# head) and exporting (Export → one of the 14 formats → a new file).
# Exit status: 0 when no panic was seen and the editor ran to the end; the
# figures go to OUT_DIR/soak.md and OUT_DIR/rss.csv.
set -euo pipefail
cd "$(dirname "$0")/.."
minutes="${1:-20}"
out="${2:-/tmp/scatterlab-soak}"
bin="${SCATTERLAB_BIN:-target/release/scatterlab}"
if [ ! -x "$bin" ]; then
    echo "tools/soak.sh: building $bin"
    cargo build --release --bin scatterlab
fi
for tool in Xvfb xdotool; do
    command -v "$tool" >/dev/null || { echo "tools/soak.sh: $tool is missing (tools/setup-debian.sh installs it)" >&2; exit 2; }
done
rm -rf "$out"
mkdir -p "$out/home/run" "$out/export"
chmod 700 "$out/home/run"
# Someone else's mesh (a photogrammetry scan, glTF, its own maps).
mesh="$PWD/assets/scan/LeePerrySmith.glb"
display=":$((300 + RANDOM % 200))"
Xvfb "$display" -screen 0 1280x720x24 -nolisten tcp -noreset >/dev/null 2>&1 &
xvfb=$!
editor=""
cleanup() {
    [ -n "$editor" ] && kill "$editor" 2>/dev/null || true
    kill "$xvfb" 2>/dev/null || true
}
trap cleanup EXIT
sleep 1
export DISPLAY="$display"
HOME="$out/home" XDG_RUNTIME_DIR="$out/home/run" XDG_DATA_HOME="$out/home/data" \
    XDG_CONFIG_HOME="$out/home/config" SCATTERLAB_FRAME_LOG="$out/frames.log" RUST_BACKTRACE=1 \
    "$bin" edit >"$out/editor.log" 2>&1 &
editor=$!
wid="$(timeout 120 xdotool search --sync --name scatterlab | head -n 1)"
xdotool windowsize "$wid" 1280 720
xdotool windowmove "$wid" 0 0
xdotool windowfocus --sync "$wid"
sleep 5

rss_kb() { awk '/^VmRSS:/ {print $2}' "/proc/$editor/status" 2>/dev/null || echo 0; }
rand() { echo $((RANDOM % ($2 - $1 + 1) + $1)); }
drag() { # button x0 y0 dx dy
    xdotool mousemove "$2" "$3" mousedown "$1"
    for _ in 1 2 3 4 5; do xdotool mousemove_relative -- $(($4 / 5)) $(($5 / 5)); sleep 0.05; done
    xdotool mouseup "$1"
}
click() { xdotool mousemove "$1" "$2" click 1; sleep 0.4; }
type_path() { # the file dialog's File name field (its x range in every dialog), then Enter
    click 550 515
    xdotool key ctrl+a
    xdotool type --delay 5 "$1"
    xdotool key Return
    sleep 1
}

declare -a counts=(0 0 0 0 0 0 0 0 0 0)
names=(orbit light edit undo flicker compare preset mesh export wait)
# act N [CHOICE]: artist action N (an index into names), with a random
# choice within it unless CHOICE is given.
act() {
    local a=$1 c=${2:-}
    case $a in
    0) drag 1 "$(rand 420 800)" "$(rand 150 640)" "$(rand -200 200)" "$(rand -80 80)" ;;
    1) drag 3 "$(rand 420 800)" "$(rand 150 640)" "$(rand -150 150)" "$(rand -60 60)" ;;
    2) drag 1 "$(rand 60 300)" "$(rand 80 600)" "$(rand -40 40)" 0 ;;
    3) xdotool key --clearmodifiers "$([ $((RANDOM % 2)) -eq 0 ] && echo ctrl+z || echo ctrl+shift+z)" ;;
    4) xdotool key --clearmodifiers f ;;
    5)
        # Compare: off, split, side by side, difference, SSS only, or
        # "refine to the truth" (the ground truth) on or off.
        local xs=(445 490 560 646 788 672)
        local x=${xs[${c:-$(rand 0 5)}]}
        if [ "$x" -eq 672 ]; then
            click 672 66
            truth=$((1 - truth))
        else click "$x" 43; fi
        ;;
    6)
        # File → New from preset → one of the 17 shipped looks.
        click 19 12; xdotool mousemove 60 62; sleep 0.3; xdotool mousemove 240 62; sleep 0.3
        local dirty=no
        case "$(xdotool getwindowname "$wid")" in "*"*) dirty=yes ;; esac
        click "$(rand 180 380)" "${c:-$(rand 62 430)}"
        # Unsaved changes: the prompt's second button, Discard changes.
        if [ "$dirty" = yes ]; then sleep 0.5; xdotool key Tab Tab Return; fi
        ;;
    7)
        if [ "${c:-$((RANDOM % 2))}" -eq 0 ]; then
            # File → Load mesh…, a scan in its own units: the units prompt
            # suggests 0.0462 m/unit; take it, OK.
            click 19 12; click 60 255; type_path "$mesh"; sleep 5
            click 620 412; click 493 430
        else
            click 19 12; click 60 278 # File → Default head
        fi
        ;;
    8)
        # Export → one of the 14 formats → a new file name (no overwrite
        # prompt; the dialog adds the extension).
        click 96 12; click 160 $((36 + 28 * ${c:-$(rand 0 13)})); sleep 1
        type_path "$out/export/soak_${counts[8]}"; sleep 2
        ;;
    *) sleep 2 ;;
    esac
    counts[$a]=$((counts[$a] + 1))
    xdotool key Escape 2>/dev/null || true
    sleep 0.$(rand 1 6)
}
sample() {
    local now frames
    now=$(date +%s)
    frames=$(grep -c " frame " "$out/frames.log" 2>/dev/null || echo 0)
    echo "$((now - start)),$(rss_kb),$frames" >>"$out/rss.csv"
}
truth=0
# The state the baseline and the final figure are taken in: the default
# head, compare off, the ground truth off, the pointer still.
settle() {
    [ "$truth" -eq 1 ] && act 5 5
    act 5 0; act 7 1; sleep 10
}
start=$(date +%s)
end=$((start + minutes * 60))
echo "seconds,rss_kb,frames" >"$out/rss.csv"
sample
# Warm-up: every kind of work once (the scan and its units, the default
# head, each compare mode, the ground truth on both meshes, the slowest
# exports, a preset), so the caches it fills (the renderer keeps the last
# ground truth's cells, bounded by the largest mesh) are in the baseline. The baseline (after
# the warm-up and at least a minute) and the final figure are both taken
# in the same state (settle): what grows between them is a leak.
act 7 0; sleep 5; act 0; act 5 5; sleep 15; act 5 5
act 7 1; sleep 3; act 5 5; sleep 20; act 5 5
act 5 1; act 5 2; act 5 3; act 5 4; act 5 0
act 8 7; sleep 4; act 8 9; act 8 12; act 6 200; act 2; act 3; act 4; act 4
while [ $(($(date +%s) - start)) -lt 50 ]; do act 0; done
settle
sample
warm_s=$(($(date +%s) - start))
rss_base=$(rss_kb)
next_sample=$(($(date +%s) + 10))
while [ "$(date +%s)" -lt "$end" ]; do
    if ! kill -0 "$editor" 2>/dev/null; then
        echo "tools/soak.sh: the editor exited after $(($(date +%s) - start)) s" >&2
        break
    fi
    if [ "$(date +%s)" -ge "$next_sample" ]; then
        sample
        next_sample=$(($(date +%s) + 10))
    fi
    k=$(rand 0 99)
    if [ "$k" -lt 25 ]; then act 0
    elif [ "$k" -lt 35 ]; then act 1
    elif [ "$k" -lt 55 ]; then act 2
    elif [ "$k" -lt 62 ]; then act 3
    elif [ "$k" -lt 66 ]; then act 4
    elif [ "$k" -lt 76 ]; then act 5
    elif [ "$k" -lt 82 ]; then act 6
    elif [ "$k" -lt 86 ]; then act 7
    elif [ "$k" -lt 90 ]; then act 8
    else act 9; fi
done
settle
sample
final_rss=$(rss_kb)
alive=yes
kill -0 "$editor" 2>/dev/null || alive=no
panics=$(grep -c "panicked" "$out/editor.log" || true)
recovered=$(grep -c "^warning: the .* thread failed\|^warning: the GPU device was lost" "$out/editor.log" || true)
frames=$(grep -c " frame " "$out/frames.log" 2>/dev/null || echo 0)
ui_frames=$(grep -c " ui " "$out/frames.log" 2>/dev/null || echo 0)
peak=$(awk -F, 'NR > 1 && $2 > m {m = $2} END {print m + 0}' "$out/rss.csv")
growth=$(awk -v a="$rss_base" -v b="$final_rss" 'BEGIN {if (a > 0) printf "%.1f", 100 * (b - a) / a; else print "?"}')
actions=""
for i in "${!names[@]}"; do actions="$actions ${names[$i]} ${counts[$i]},"; done
{
    echo "# Soak ($(date -u +%Y-%m-%d), $minutes min, $(git rev-parse --short HEAD 2>/dev/null || echo '?'))"
    echo
    echo "| Figure | Value |"
    echo "| --- | --- |"
    echo "| Minutes | $minutes |"
    echo "| Actions |${actions%,} |"
    echo "| Viewport frames | $frames |"
    echo "| UI frames | $ui_frames |"
    echo "| RSS after the warm-up ($warm_s s) | $((rss_base / 1024)) MB |"
    echo "| Peak RSS | $((peak / 1024)) MB |"
    echo "| Final RSS | $((final_rss / 1024)) MB |"
    echo "| Growth after the warm-up | $growth % |"
    echo "| Panics | $panics |"
    echo "| Recoveries | $recovered |"
    echo "| Editor alive at the end | $alive |"
} | tee "$out/soak.md"
[ "$panics" -eq 0 ] && [ "$alive" = yes ]

#!/usr/bin/env bash
# Measures how live the editor's viewport is, as an artist uses it: the
# editor under Xvfb, driven by xdotool with a real pointer. For each window
# size and head it drags an orbit in the viewport, then the red scattering
# distance (a drag value in the Look panel), each for DRAG_S seconds, and
# reads the frame log the editor writes (SCATTERLAB_FRAME_LOG: one line per
# viewport frame with its kind — preview, refining, converged — and one per
# UI frame).
#
# It finds what it drags by what it is, never by window coordinates: the
# editor writes its AccessKit tree with each control's rectangle
# (SCATTERLAB_WIDGET_MAP, src/app/widget_map.rs), and the tool takes the
# control whose role and label it names (the viewport: Canvas "Viewport";
# the distance: SpinButton "R: mm"). It fails, naming what is missing, when
# it cannot find a control, when a drag changes nothing (no preview frame
# while orbiting; the distance's value unchanged) or when no converged
# frame follows a drag. It never judges a timing: the figures are a
# benchmark.
#
# Reports, for each drag: viewport frames per second while dragging (the
# previews), UI frames per second, the previews' sizes, and the time from
# releasing the mouse to the "converged" frame. Then (unless --quick) the
# ground truth: an editor on the default skin with the method `reference`;
# after an orbit drag, the time from release to the first frame of
# ground-truth tiles and to the full truth, and how far the time left the
# status bar showed was from the time it then took.
#
#   tools/measure_live.sh [--out FILE.md] [--quick] [--sizes 1500x900,1280x720]
#                         [--heads scan,procedural]
#
# --quick: drags of 1 s and no ground truth (the CI check, tests/window.rs).
# Environment: BIN (the editor; default: a release build made here),
# DRAG_S (seconds a drag; 4, quick 1), METHOD (a preset variant such as
# TextureSpace for the drags), CONTROL (the distance's label, "R: mm"),
# TRUTH_SIZES (sizes the ground truth is measured at; default the first),
# KEEP=DIR (keep each run's frame log, widget map and editor output).
# VK_ICD_FILENAMES picks the Vulkan driver as usual; the report names the
# driver the editor used.
#
# Needs Xvfb, xdotool and python3 (tools/setup-debian.sh installs them).
# docs/rendering.md records its figures.
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=""
QUICK=0
SIZES="1500x900,1280x720"
HEADS="scan,procedural"
while [[ $# -gt 0 ]]; do
    case "$1" in
        --out) OUT="$2"; shift 2 ;;
        --quick) QUICK=1; shift ;;
        --sizes) SIZES="$2"; shift 2 ;;
        --heads) HEADS="$2"; shift 2 ;;
        *) echo "error: unknown argument $1 (see the top of $0)" >&2; exit 2 ;;
    esac
done
DRAG_S="${DRAG_S:-$([[ $QUICK == 1 ]] && echo 1 || echo 4)}"
CONTROL="${CONTROL:-R: mm}"
TRUTH_SIZES="${TRUTH_SIZES:-${SIZES%%,*}}"
for t in Xvfb xdotool python3; do
    command -v "$t" >/dev/null || { echo "error: $t is missing (tools/setup-debian.sh installs it)" >&2; exit 1; }
done
if [[ -z "${BIN:-}" ]]; then
    cargo build --release --quiet
    BIN="$PWD/target/release/scatterlab"
fi
WORK="$(mktemp -d)"
EDITOR_PID=""
cleanup() {
    [[ -n "$EDITOR_PID" ]] && kill "$EDITOR_PID" 2>/dev/null || true
    [[ -n "${XVFB_PID:-}" ]] && kill "$XVFB_PID" 2>/dev/null || true
    if [[ -n "${KEEP:-}" ]]; then mkdir -p "$KEEP" && cp -r "$WORK"/runs "$KEEP"/ 2>/dev/null || true; fi
    rm -rf "$WORK"
}
trap cleanup EXIT
trap "exit 130" INT TERM HUP PIPE
# A display of its own: a free number from a random start, taken when
# our Xvfb is still running half a second later and answers (an Xvfb that
# finds the number taken exits; Xvfb's own -displayfd raced between two
# tools started at once).
XVFB_PID=""
for ((n = 100 + RANDOM % 800, tries = 0; ; n++, tries++)); do
    ((tries < 20)) || { echo "error: no free X display for Xvfb (tried :$((n - 20))–:$((n - 1)))" >&2; exit 1; }
    [[ -e "/tmp/.X$n-lock" || -e "/tmp/.X11-unix/X$n" ]] && continue
    Xvfb ":$n" -screen 0 1600x1000x24 -nolisten tcp >/dev/null 2>&1 &
    XVFB_PID=$!
    for ((i = 0; i < 50; i++)); do
        sleep 0.1
        kill -0 "$XVFB_PID" 2>/dev/null || break
        if ((i >= 5)) && DISPLAY=":$n" xdpyinfo >/dev/null 2>&1; then break 2; fi
    done
    kill "$XVFB_PID" 2>/dev/null || true
    XVFB_PID=""
done
DISP=":$n"
export DISPLAY="$DISP"
mkdir -p "$WORK/run" "$WORK/runs"
chmod 700 "$WORK/run"

preset_with_method() { # preset_with_method <Method> <out.ron>
    sed "s|^    profile: |    rendering: (method: $1),\n    profile: |" presets/skin_default.ron >"$2"
    grep -q "method: $1" "$2" || { echo "error: could not write the $1 preset" >&2; exit 1; }
}
now() { date +%s.%N; }
die() { # die <message>: says what the editor said, then fails
    echo "error: $1" >&2
    kill -0 "${XVFB_PID:-0}" 2>/dev/null || echo "(its X server, Xvfb $DISP, is not running)" >&2
    if [[ -f "${RUN:-}/editor.out" ]]; then
        echo "--- the editor said:" >&2
        tail -20 "$RUN/editor.out" >&2
    fi
    exit 1
}

# wait_for <regex> <after-time> <timeout-s>: a frame-log line newer than
# <after-time> that matches.
wait_for() {
    local deadline=$((SECONDS + $3))
    while ((SECONDS < deadline)); do
        if [[ -f "$LOG" ]] && awk -v t="$2" -v re="$1" '$1 > t && $0 ~ re {f=1} END {exit !f}' "$LOG"; then
            return 0
        fi
        kill -0 "$EDITOR_PID" 2>/dev/null || die "the editor exited while waiting for '$1'"
        sleep 0.1
    done
    die "no '$1' frame after $2 within $3 s"
}

# wait_settled <timeout-s>: the newest viewport frame is a converged one
# and nothing was drawn for a second (start-up work, a new window size).
wait_settled() {
    local deadline=$((SECONDS + $1))
    while ((SECONDS < deadline)); do
        if [[ -f "$LOG" ]] && awk -v now="$(now)" '$2 == "frame" {k = $3; t = $1} END {exit !(k == "converged" && now - t > 1)}' "$LOG"; then
            return 0
        fi
        kill -0 "$EDITOR_PID" 2>/dev/null || die "the editor exited before its view settled"
        sleep 0.2
    done
    die "the view did not settle on a converged frame within $1 s"
}

# locate <role> <label>: "x y value" of the control's centre (window pixels),
# from a widget map written after this call began. Moves the pointer a
# pixel back and forth over the window's corner meanwhile, so that the
# editor draws frames (it writes the map on frames).
locate() {
    local since deadline out
    since="$(now)"
    deadline=$((SECONDS + 20))
    while ((SECONDS < deadline)); do
        if out="$(python3 - "$MAP" "$since" "$1" "$2" "$W" "$H" 2>"$WORK/locate.err" <<'EOF'
import os, sys
path, since, role, label = sys.argv[1], float(sys.argv[2]), sys.argv[3], sys.argv[4]
width, height = float(sys.argv[5]), float(sys.argv[6])
if not os.path.exists(path) or os.path.getmtime(path) <= since:
    sys.exit(3)
hits = []
for line in open(path, encoding="utf-8"):
    if line.startswith("#"):
        continue
    r, l, v, box = line.rstrip("\n").split("\t")
    if r == role and l == label:
        x0, y0, x1, y1 = map(float, box.split())
        hits.append((x0, y0, x1, y1, v))
if len(hits) != 1:
    print(f"{len(hits)} controls are {role} '{label}'", file=sys.stderr)
    sys.exit(4)
x0, y0, x1, y1, v = hits[0]
if x1 - x0 < 4 or y1 - y0 < 4:
    print(f"{role} '{label}' is {x1-x0:.0f}×{y1-y0:.0f} px: not on screen", file=sys.stderr)
    sys.exit(4)
# A control scrolled out of its panel keeps its place in the tree.
if not (0 <= (x0 + x1) / 2 < width and 0 <= (y0 + y1) / 2 < height):
    print(f"{role} '{label}' is at {x0:.0f},{y0:.0f}–{x1:.0f},{y1:.0f}, outside the {width:.0f}×{height:.0f} window (scrolled out of view?)", file=sys.stderr)
    sys.exit(4)
print(f"{(x0 + x1) / 2:.0f} {(y0 + y1) / 2:.0f} {v}")
EOF
        )" && [[ "$out" =~ ^[0-9]+\ [0-9]+ ]]; then
            echo "$out"
            return 0
        fi
        xdotool mousemove --window "$WID" 2 2 mousemove --window "$WID" 3 3
        sleep 0.2
    done
    python3 - "$MAP" "$1" "$2" <<'EOF' >&2 || true
import sys
path, role, label = sys.argv[1:4]
print(f"--- the editor's controls like {role} '{label}':")
for line in open(path, encoding="utf-8"):
    if line.split("\t")[0] == role or label.split(":")[0] in line:
        print(line.rstrip())
EOF
    cat "$WORK/locate.err" >&2
    die "cannot find the $1 '$2' in the editor's widget map, or it is not on screen ($W×$H, $HEAD)"
}

# drag <x> <y> <dx per move> <net px>: press, move every STEP_MS for
# DRAG_S, release; DOWN and UP are the times. The moves go forward, then
# back, so that the drag ends <net px> from where it began whatever its
# length (the view, or the value, the figures after it are measured at);
# a drag too short for that goes forward only. The moves are one xdotool
# process with its own sleeps: an xdotool started for each move took about
# 10 ms to start, so moves meant every 30 ms came 25 times a second, below
# the frame rates measured.
STEP_MS="${STEP_MS:-16}"
drag() {
    xdotool mousemove --window "$WID" "$1" "$2"
    sleep 0.3
    xdotool mousedown 1
    local steps=$((DRAG_S * 1000 / STEP_MS)) net=$(($4 / $3)) chain=() i forward
    forward=$(((steps + net) / 2))
    ((forward > steps)) && forward=$steps
    for ((i = 0; i < steps; i++)); do
        local dx="$3"
        ((i >= forward)) && dx=$((-$3))
        chain+=(mousemove_relative -- "$dx" 0 sleep "0.$(printf %03d "$STEP_MS")")
    done
    DOWN="$(now)"
    xdotool "${chain[@]}"
    UP="$(now)"
    xdotool mouseup 1
}

# start_editor <name> [args...]: an editor with its own fresh state (the
# default window and layout), its frame log and widget map, at $W×$H.
start_editor() {
    local name="$1" attempt
    shift
    RUN="$WORK/runs/$name"
    LOG="$RUN/frames.log"
    MAP="$RUN/widgets.tsv"
    for attempt in 1 2 3; do
        rm -rf "$RUN"
        mkdir -p "$RUN/data" "$RUN/config"
        XDG_RUNTIME_DIR="$WORK/run" XDG_DATA_HOME="$RUN/data" XDG_CONFIG_HOME="$RUN/config" \
            SCATTERLAB_FRAME_LOG="$LOG" SCATTERLAB_WIDGET_MAP="$MAP" \
            "$BIN" edit "$@" >"$RUN/editor.out" 2>&1 &
        EDITOR_PID=$!
        local deadline=$((SECONDS + 120))
        WID=""
        while [[ -z "$WID" ]]; do
            ((SECONDS < deadline)) || die "the editor's window did not open within 120 s"
            if ! kill -0 "$EDITOR_PID" 2>/dev/null; then
                # Seen about once in ten starts with two of these tools
                # running at once, with the X server answering xdpyinfo
                # before and after: Xlib's XOpenDisplay failed. Start again.
                if grep -q "connection to X server" "$RUN/editor.out" && ((attempt < 3)); then
                    echo "note: the editor could not connect to $DISP (attempt $attempt); starting it again" >&2
                    sleep 1
                    continue 2
                fi
                die "the editor exited before its window opened"
            fi
            WID="$(xdotool search --name 'scatterlab' 2>/dev/null | head -1 || true)"
            sleep 0.2
        done
        break
    done
    xdotool windowmove "$WID" 0 0
    xdotool windowsize "$WID" "$W" "$H"
    xdotool windowactivate --sync "$WID" 2>/dev/null || xdotool windowfocus "$WID" 2>/dev/null || true
}

stop_editor() {
    kill "$EDITOR_PID" 2>/dev/null || true
    wait "$EDITOR_PID" 2>/dev/null || true
    EDITOR_PID=""
}

RESULTS="$WORK/results.tsv"
: >"$RESULTS"
IFS=, read -r -a size_list <<<"$SIZES"
IFS=, read -r -a head_list <<<"$HEADS"
for size in "${size_list[@]}"; do
    W="${size%x*}"
    H="${size#*x}"
    for HEAD in "${head_list[@]}"; do
        case "$HEAD" in
            scan) head_args=() ;;
            procedural) head_args=(--procedural-head) ;;
            *) die "unknown head $HEAD (scan or procedural)" ;;
        esac
        args=("${head_args[@]}")
        if [[ -n "${METHOD:-}" ]]; then
            preset_with_method "$METHOD" "$WORK/method.ron"
            args+=(--preset "$WORK/method.ron")
        fi
        start_editor "${W}x${H}-$HEAD" "${args[@]}"
        wait_for "converged" 0 300
        # Let start-up work (skin maps, the analysis thread) and the new
        # window size settle.
        wait_settled 120
        pos="$(locate Canvas Viewport)"
        read -r vx vy _ <<<"$pos"
        # 3 px a move (180 px a second), ending 400 px from the start.
        drag "$vx" "$vy" 3 400
        ORBIT=("$DOWN" "$UP")
        wait_for "converged" "$UP" 60
        sleep 1
        pos="$(locate SpinButton "$CONTROL")"
        read -r cx cy before <<<"$pos"
        # 1 px a move (60 px a second), ending 133 px from the start: from
        # 0.757 mm to about 1.4 mm. egui's drag value snaps to round
        # numbers, so not every move changes it: the table's requests/s
        # says how often the editor had a new value to draw.
        drag "$cx" "$cy" 1 133
        SLIDER=("$DOWN" "$UP")
        wait_for "converged" "$UP" 60
        pos="$(locate SpinButton "$CONTROL")"
        read -r _ _ after <<<"$pos"
        [[ "$before" != "$after" ]] || die "dragging the SpinButton '$CONTROL' left it at $before"
        printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$W" "$H" "$HEAD" "$LOG" "${ORBIT[@]}" "${SLIDER[@]}" \
            "$before → $after" >>"$RESULTS"
        stop_editor

        # The ground truth as the viewport's method, in an editor of its own.
        if [[ $QUICK == 0 && ",$TRUTH_SIZES," == *",$size,"* ]]; then
            preset_with_method Reference "$WORK/truth.ron"
            start_editor "${W}x${H}-$HEAD-truth" "${head_args[@]}" --preset "$WORK/truth.ron"
            wait_for "converged.*method=reference" 0 300
            wait_settled 300
            pos="$(locate Canvas Viewport)"
        read -r vx vy _ <<<"$pos"
            drag "$vx" "$vy" 3 400
            wait_for "converged.*method=reference" "$UP" 300
            printf 'truth\t%s\t%s\t%s\t%s\t%s\t%s\n' "$W" "$H" "$HEAD" "$LOG" "$DOWN" "$UP" >>"$RESULTS"
            stop_editor
        fi
    done
done

python3 - "$RESULTS" "$OUT" <<'EOF'
import statistics, sys
results, out = sys.argv[1], sys.argv[2]
def frames(log):
    return [l.split() for l in open(log)]
def driver(rows):
    d = [" ".join(r[2:]) for r in rows if len(r) > 2 and r[1] == "driver"]
    return d[0] if d else "not logged"
def report(rows, name, t0, t1):
    # Skip the first 0.3 s (the drag threshold and the first preview).
    a = t0 + 0.3
    prev = [r for r in rows if r[1] == "frame" and r[2] == "preview" and a < float(r[0]) <= t1]
    # What the render thread was asked for: a viewport at the rate of its
    # requests is keeping up with the input.
    reqs = [r for r in rows if r[1] == "request" and a < float(r[0]) <= t1]
    ui = [r for r in rows if r[1] == "ui" and a < float(r[0]) <= t1]
    conv = [r for r in rows if r[1] == "frame" and r[2] == "converged" and float(r[0]) > t1]
    refine = [r for r in rows if r[1] == "frame" and r[2] == "refining" and t1 < float(r[0]) <= float(conv[0][0])]
    if not prev:
        sys.exit(f"error: no preview frame while dragging the {name}: the drag did nothing")
    span = t1 - a
    px = sorted((int(r[3].split("x")[0]) * int(r[3].split("x")[1]), r[3]) for r in prev)
    ms = [float(r[5].split("=")[1]) for r in prev]
    return (f"{len(prev)/span:.1f} | {len(reqs)/span:.1f} | {len(ui)/span:.1f} | {px[0][1]} to {px[-1][1]} "
            f"| {statistics.median(ms):.0f} | {conv[0][3]} | {float(conv[0][0])-t1:.2f} | {len(refine)+1}")
lines = [
    "| window | head | drag | viewport frames/s while dragging | requests/s | UI frames/s | preview sizes | median preview render (ms) | full size | release → converged (s) | full-size frames |",
    "|---|---|---|---|---|---|---|---|---|---|---|",
]
truth_lines = []
drivers = set()
for line in open(results):
    f = line.rstrip("\n").split("\t")
    if f[0] == "truth":
        _, w, h, head, log, t0, t1 = f
        rows, t1 = frames(log), float(t1)
        drivers.add(driver(rows))
        def first(kind):
            hits = [r for r in rows if r[1] == "frame" and r[2] == kind and float(r[0]) > t1 and "method=reference" in r]
            return (float(hits[0][0]) - t1, hits[0][3]) if hits else (float("nan"), "none")
        tiles, full = first("truth-tiles"), first("converged")
        done_at = t1 + full[0]
        errors = []
        for r in rows:
            if r[1] == "frame" and r[2] == "truth-tiles" and float(r[0]) > t1:
                left = [x.split("=")[1] for x in r if x.startswith("left_s=")]
                if left and left[0] != "none" and done_at - float(r[0]) > 1.0:
                    actual = done_at - float(r[0])
                    errors.append(abs(float(left[0]) - actual) / actual)
        errors.sort()
        med = errors[len(errors) // 2] if errors else float("nan")
        worst = errors[-1] if errors else float("nan")
        truth_lines.append(f"| {w}×{h} | {head} | {tiles[0]:.2f} | {tiles[1]} | {full[0]:.2f} | {full[1]} "
                           f"| {100*med:.0f} % / {100*worst:.0f} % ({len(errors)} frames) |")
        continue
    w, h, head, log, o0, o1, s0, s1, moved = f
    rows = frames(log)
    drivers.add(driver(rows))
    lines.append(f"| {w}×{h} | {head} | orbit | " + report(rows, "orbit", float(o0), float(o1)) + " |")
    lines.append(f"| {w}×{h} | {head} | scattering distance ({moved}) | "
                 + report(rows, "scattering distance", float(s0), float(s1)) + " |")
lines = [f"Driver: {', '.join(sorted(drivers))}", ""] + lines
if truth_lines:
    lines += [
        "",
        "| ground truth after an orbit | head | release → first tiles (s) | tiles' size | release → full truth (s) | full size | time left shown: median / worst error |",
        "|---|---|---|---|---|---|---|",
    ] + truth_lines
print("\n".join(lines))
if out:
    open(out, "w").write("\n".join(lines) + "\n")
EOF

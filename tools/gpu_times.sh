#!/usr/bin/env bash
# Times every SSS method and the ground truth on this machine's GPU at
# 1920×1080 (the budgets docs/rendering.md states: burley < 0.5 ms,
# separable < 0.3 ms on a real GPU), and writes a Markdown table.
#
#   tools/gpu_times.sh [--out FILE.md] [--size WxH] [--bin PATH]
#
# For each method: `render --frames 5 --stats`, the fifth identical frame
# (the editor's steady state: shadow map and tables reused): its SSS passes'
# GPU time and the whole frame's (timestamp queries), both in ms. Then the
# ground truth, `reference`, gathered on the CPU and on the GPU
# (`--reference-gpu`), each run twice: the first pays for the cells and,
# on the GPU, for compiling the gather's shader (llvmpipe compiles at the
# first dispatch; a driver's shader cache serves the second run); the table
# keeps the second run's wall time of the gather (`reference_cpu_ms`: the
# cells and the gather; on the GPU, the points the GPU did not finish are
# gathered on the CPU and counted). The adapter's name is in every row: a
# figure from lavapipe (llvmpipe) is the CPU's, not a GPU's.
#
# Needs python3 and a release build (built here if missing).
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=""
SIZE="1920x1080"
BIN=""
while [[ $# -gt 0 ]]; do
    case "$1" in
        --out) OUT="$2"; shift 2 ;;
        --size) SIZE="$2"; shift 2 ;;
        --bin) BIN="$2"; shift 2 ;;
        *) echo "usage: tools/gpu_times.sh [--out FILE.md] [--size WxH] [--bin PATH]" >&2; exit 2 ;;
    esac
done
W="${SIZE%x*}"
H="${SIZE#*x}"
if [[ -z "$BIN" ]]; then
    cargo build --release --quiet
    BIN="$PWD/target/release/scatterlab"
fi
WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT

# The methods, as `render --method` lists them (clap's possible values).
METHODS=$("$BIN" render --help | awk '/--method </ {on=1; next} on && /^ *- [a-z]+:/ {sub(/^ *- /, ""); sub(/:.*/, ""); printf "%s ", $0; next} on && /^ *--/ {exit}')
[[ -n "$METHODS" ]] || { echo "error: could not read the methods from render --help" >&2; exit 1; }

rows=()
for m in $METHODS; do
    [[ "$m" == "reference" ]] && continue
    "$BIN" render --method "$m" --width "$W" --height "$H" --frames 5 \
        --stats "$WORK/$m.json" --out "$WORK/$m.png" >"$WORK/$m.log" 2>&1 || {
        echo "error: render --method $m failed:" >&2; cat "$WORK/$m.log" >&2; exit 1; }
    rows+=("$m:$WORK/$m.json")
done
for how in cpu gpu; do
    flag=""
    [[ "$how" == gpu ]] && flag="--reference-gpu"
    for run in 1 2; do
        # shellcheck disable=SC2086
        "$BIN" render --method reference $flag --width "$W" --height "$H" \
            --stats "$WORK/truth-$how-$run.json" --out "$WORK/truth-$how.png" \
            >"$WORK/truth-$how.log" 2>&1 || {
            echo "error: render --method reference $flag failed:" >&2; cat "$WORK/truth-$how.log" >&2; exit 1; }
    done
    rows+=("reference ($how):$WORK/truth-$how-2.json")
done

python3 - "$OUT" "$SIZE" "${rows[@]}" <<'EOF'
import json, sys
out, size, rows = sys.argv[1], sys.argv[2], sys.argv[3:]
lines = [
    f"| method ({size}) | SSS GPU (ms) | frame GPU (ms) | ground truth wall (ms) | points the GPU left to the CPU | adapter; driver |",
    "|---|---|---|---|---|---|",
]
for row in rows:
    name, path = row.rsplit(":", 1)
    s = json.load(open(path))
    frame = sum(p["gpu_ms"] or 0.0 for p in s["passes"]) if all(p["gpu_ms"] is not None for p in s["passes"]) else None
    fmt = lambda v: "—" if v is None else f"{v:.3f}"
    truth = s.get("reference_cpu_ms")
    left = s.get("reference_gpu_unfinished")
    lines.append(
        f"| {name} | {fmt(s['sss_gpu_ms'])} | {fmt(frame)} | {'—' if truth is None else f'{truth:.0f}'} "
        f"| {'—' if left is None else left} | {s['adapter']}; {s.get('driver', 'driver not named')} |"
    )
text = "\n".join(lines)
print(text)
if out:
    open(out, "w").write(text + "\n")
EOF

#!/usr/bin/env bash
# Every live and GPU-path figure on two Vulkan drivers, one after the other
# in one run, with the same release binary: the lavapipe installed here (by
# tools/setup-debian.sh: Mesa >= 25) and an older one loaded through
# VK_ICD_FILENAMES without installing it (default: Debian 12's own Mesa
# 22.3.6, fetched with `apt-get download` and unpacked into a temporary
# folder). docs/rendering.md ("Drivers") records its figures.
#
#   tools/compare_drivers.sh [--out FILE.md] [--old-icd FILE.json] [--skip STEPS]
#
# Steps (each on both drivers, the old one first), all by default:
#   live   tools/measure_live.sh, both window sizes and heads, the ground
#          truth at 1500×900 on both heads;
#   bench  `scatterlab bench` (full, 6–7 min a driver): each method's
#          frame time and its ratio to `none`'s, medians over the scenes;
#   truth  `render --method reference --reference-gpu` at 320×180, cold
#          (an empty Mesa shader cache: the gather's shader is compiled)
#          and warm (the same cache again), and the CPU truth;
#   gtest  the test binary of tests/ground_truth_gpu.rs, wall time;
#   tests  the whole `cargo test` (CI's longest part), wall time.
# Both test steps start from an empty Mesa shader cache, as CI does.
# --skip takes a comma-separated list of steps to leave out.
#
# Needs what tools/measure_live.sh needs, cargo, and (for the default old
# driver) Debian's bookworm archive in apt's sources.
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=""
OLD_ICD=""
SKIP=""
while [[ $# -gt 0 ]]; do
    case "$1" in
        --out) OUT="$2"; shift 2 ;;
        --old-icd) OLD_ICD="$2"; shift 2 ;;
        --skip) SKIP=",$2,"; shift 2 ;;
        *) echo "error: unknown argument $1 (see the top of $0)" >&2; exit 2 ;;
    esac
done
want() { [[ "$SKIP" != *",$1,"* ]]; }
WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT

# The installed lavapipe's ICD file.
NEW_ICD=""
for f in /usr/share/vulkan/icd.d/lvp_icd.json /usr/share/vulkan/icd.d/lvp_icd.x86_64.json \
    /usr/share/vulkan/icd.d/lvp_icd.aarch64.json; do
    [[ -e "$f" ]] && NEW_ICD="$f" && break
done
[[ -n "$NEW_ICD" ]] || { echo "error: no lavapipe installed (tools/setup-debian.sh installs it)" >&2; exit 1; }
if [[ -z "$OLD_ICD" ]]; then
    (cd "$WORK" && apt-get download mesa-vulkan-drivers=22.3.6-1+deb12u2 >/dev/null 2>&1) || {
        echo "error: could not download Debian 12's mesa-vulkan-drivers 22.3.6 (give --old-icd FILE.json)" >&2
        exit 1
    }
    dpkg-deb -x "$WORK"/mesa-vulkan-drivers_*.deb "$WORK/old"
    lib="$(find "$WORK/old" -name libvulkan_lvp.so | head -1)"
    json="$(find "$WORK/old" -name 'lvp_icd*.json' | head -1)"
    sed "s|\"library_path\": *\"[^\"]*\"|\"library_path\": \"$lib\"|" "$json" >"$WORK/old_icd.json"
    OLD_ICD="$WORK/old_icd.json"
fi

cargo build --release --quiet
BIN="$PWD/target/release/scatterlab"
driver_of() { # driver_of <icd>: the driver as render names it
    VK_ICD_FILENAMES="$1" "$BIN" render --width 64 --height 36 --out "$WORK/probe.png" \
        --stats "$WORK/probe.json" >/dev/null 2>&1
    python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["driver"])' "$WORK/probe.json"
}
declare -A NAME
NAME[old]="$(driver_of "$OLD_ICD")"
NAME[new]="$(driver_of "$NEW_ICD")"
[[ "${NAME[old]}" != "${NAME[new]}" ]] || { echo "error: both ICD files load ${NAME[new]}" >&2; exit 1; }
echo "old: ${NAME[old]} ($OLD_ICD)" >&2
echo "new: ${NAME[new]} ($NEW_ICD)" >&2
declare -A ICD=([old]="$OLD_ICD" [new]="$NEW_ICD")
REPORT="$WORK/report.md"
{
    echo "Drivers: old = ${NAME[old]}; new = ${NAME[new]}. Same release binary ($(git rev-parse --short HEAD)), $(nproc) cores, $(date -u +%Y-%m-%d)."
    echo
} >"$REPORT"
secs() { python3 -c 'import sys,time; print(f"{float(sys.argv[2]) - float(sys.argv[1]):.1f}")' "$1" "$2"; }

if want live; then
    for d in old new; do
        echo "live: $d" >&2
        VK_ICD_FILENAMES="${ICD[$d]}" BIN="$BIN" TRUTH_SIZES=1500x900 \
            tools/measure_live.sh --out "$WORK/live-$d.md" >/dev/null
    done
    {
        echo "### tools/measure_live.sh"
        for d in old new; do
            echo
            echo "**${NAME[$d]}**"
            echo
            cat "$WORK/live-$d.md"
        done
        echo
    } >>"$REPORT"
fi

if want truth; then
    {
        echo "### The ground truth at 320×180 (render --method reference)"
        echo
        echo "| driver | GPU truth, cold cache (s) | GPU truth, warm (s) | CPU truth (s) |"
        echo "|---|---|---|---|"
    } >>"$REPORT"
    for d in old new; do
        echo "truth: $d" >&2
        cache="$WORK/cache-$d"
        row=()
        for run in cold warm cpu; do
            flag=(--reference-gpu)
            [[ $run == cpu ]] && flag=()
            t0="$(date +%s.%N)"
            MESA_SHADER_CACHE_DIR="$cache" VK_ICD_FILENAMES="${ICD[$d]}" "$BIN" render --method reference \
                "${flag[@]}" --width 320 --height 180 --out "$WORK/truth-$d-$run.png" >/dev/null 2>&1
            row+=("$(secs "$t0" "$(date +%s.%N)")")
        done
        echo "| ${NAME[$d]} | ${row[0]} | ${row[1]} | ${row[2]} |" >>"$REPORT"
    done
    echo >>"$REPORT"
fi

if want gtest || want tests; then
    cargo test --no-run --quiet 2>/dev/null
fi
if want gtest; then
    gt="$(cargo test --no-run --test ground_truth_gpu --message-format=json 2>/dev/null |
        python3 -c 'import json,sys
for l in sys.stdin:
    m = json.loads(l)
    if m.get("reason") == "compiler-artifact" and m.get("executable") and m["target"]["name"] == "ground_truth_gpu":
        print(m["executable"])')"
    {
        echo "### tests/ground_truth_gpu.rs (dev profile, as CI builds it)"
        echo
        echo "| driver | wall time (s) | result |"
        echo "|---|---|---|"
    } >>"$REPORT"
    for d in old new; do
        echo "gtest: $d" >&2
        t0="$(date +%s.%N)"
        result=passed
        MESA_SHADER_CACHE_DIR="$WORK/gtest-cache-$d" VK_ICD_FILENAMES="${ICD[$d]}" "$gt" >"$WORK/gtest-$d.log" 2>&1 ||
            result="failed"
        echo "| ${NAME[$d]} | $(secs "$t0" "$(date +%s.%N)") | $result |" >>"$REPORT"
    done
    echo >>"$REPORT"
fi

if want tests; then
    {
        echo "### cargo test (every test; CI adds set-up, fmt, clippy and the fuzz targets)"
        echo
        echo "| driver | wall time (s) | result |"
        echo "|---|---|---|"
    } >>"$REPORT"
    for d in old new; do
        echo "tests: $d" >&2
        t0="$(date +%s.%N)"
        result=passed
        MESA_SHADER_CACHE_DIR="$WORK/tests-cache-$d" VK_ICD_FILENAMES="${ICD[$d]}" cargo test --quiet >"$WORK/tests-$d.log" 2>&1 ||
            result="failed: $(grep -E '^    [a-z_:]+$' "$WORK/tests-$d.log" | tr -d ' ' | tr '\n' ' ')"
        echo "| ${NAME[$d]} | $(secs "$t0" "$(date +%s.%N)") | $result |" >>"$REPORT"
        cp "$WORK/tests-$d.log" "${OUT:-/tmp/compare_drivers}.tests-$d.log" 2>/dev/null || true
    done
    echo >>"$REPORT"
fi

if want bench; then
    for d in old new; do
        echo "bench: $d" >&2
        VK_ICD_FILENAMES="${ICD[$d]}" "$BIN" bench --out "$WORK/bench-$d" >"$WORK/bench-$d.log" 2>&1
    done
    python3 - "$WORK/bench-old/results.csv" "$WORK/bench-new/results.csv" "${NAME[old]}" "${NAME[new]}" >>"$REPORT" <<'EOF'
import csv, statistics, sys
old, new, name_old, name_new = sys.argv[1:5]
def read(path):
    ratio, ms, none = {}, {}, {}
    for r in csv.DictReader(open(path)):
        none[r["scene"]] = float(r["none_frame_ms"])
        if r["method"] in ("none", "reference") or r["timing"] == "cpu-wall-clock":
            continue
        key = (r["method"], r["variant"], r["count"])
        ratio.setdefault(key, []).append(float(r["frame_time_ratio"]))
        ms.setdefault(key, []).append(float(r["frame_ms"]))
    med = lambda d: {k: statistics.median(v) for k, v in d.items()}
    return med(ratio), med(ms), statistics.median(none.values())
(a, ams, anone), (b, bms, bnone) = read(old), read(new)
print("### bench: frame time over `none`'s (median over the scenes)")
print()
print(f"`none`'s frame, median over the scenes: {anone:.1f} ms on {name_old}, {bnone:.1f} ms on {name_new} "
      f"({anone / bnone:.2f}× faster).")
print()
print(f"| method | variant | count | {name_old}: ms, × none | {name_new}: ms, × none | ratio new / old | time new / old |")
print("|---|---|---|---|---|---|---|")
for k in sorted(set(a) & set(b)):
    print(f"| {k[0]} | {k[1] or '—'} | {k[2]} | {ams[k]:.1f}, {a[k]:.2f} | {bms[k]:.1f}, {b[k]:.2f} "
          f"| {b[k] / a[k]:.2f} | {bms[k] / ams[k]:.2f} |")
print()
EOF
fi

cat "$REPORT"
if [[ -n "$OUT" ]]; then cp "$REPORT" "$OUT"; fi

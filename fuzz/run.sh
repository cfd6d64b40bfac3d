#!/usr/bin/env bash
# Builds the fuzz targets and runs each for a bounded number of inputs.
#   fuzz/run.sh [SCALE]          (default 1: 10–20 s per target on 2 cores)
#   fuzz/run.sh --long [MINUTES] (each target for MINUTES, default 10, with no
#                                 input limit; writes fuzz/long-report.md)
# Runs are seeded and bounded by input count, but not bit-for-bit
# reproducible (hash-map order in the parsers varies per process), so CI
# explores a little differently from a local run; what it finds is real and
# goes to fuzz/regressions/. To search further, run a target for longer, e.g. `fuzz/target/<host>/release/mesh_gltf fuzz/corpus/mesh_gltf
# -max_total_time=600`, and copy any crash into fuzz/regressions/.
# The targets are ordinary cargo-fuzz targets (`cargo fuzz run preset`
# works where cargo-fuzz is installed); this script builds them with the
# instrumentation flags cargo-fuzz passes (libFuzzer's coverage counters,
# `--cfg fuzzing`, debug assertions and overflow checks), so CI needs no
# cargo-fuzz install. No sanitizer: the code is safe Rust, and we hunt
# panics, hangs, runaway memory and the targets' own assertions (NaN, errors
# that do not name the file). Seeds: fuzz/seeds/<target>/, copied into a
# scratch corpus so committed files never change. A crash fails the run and
# leaves its input in fuzz/artifacts/.
set -euo pipefail
cd "$(dirname "$0")"
scale="${1:-1}"
long_minutes=0
if [ "${1:-}" = "--long" ]; then
    long_minutes="${2:-10}"
    scale=1
fi
triple="$(rustc -vV | sed -n 's/^host: //p')"
# The binaries are looked for under fuzz/target, whatever the caller's
# CARGO_TARGET_DIR says (a shared target dir would hide them).
export CARGO_TARGET_DIR="$PWD/target"
export RUSTC_BOOTSTRAP=1
export RUSTFLAGS="-Cpasses=sancov-module -Cllvm-args=-sanitizer-coverage-level=4 \
-Cllvm-args=-sanitizer-coverage-inline-8bit-counters -Cllvm-args=-sanitizer-coverage-pc-table \
-Cllvm-args=-sanitizer-coverage-trace-compares --cfg fuzzing \
-Cllvm-args=-simplifycfg-branch-fold-threshold=0 -Cdebug-assertions -Coverflow-checks"
targets=(preset mesh_obj mesh_gltf image unity_asset unreal_text materialx godot_tres blender_py gltf_material)
# Inputs per target at scale 1 (10–20 s each here; `fuzz/run.sh 10` searches ten
# times longer).
declare -A runs=([preset]=30000 [mesh_obj]=300000 [mesh_gltf]=60000 [image]=40000
    [unity_asset]=60000 [unreal_text]=800000 [materialx]=500000 [godot_tres]=400000 [blender_py]=500000 [gltf_material]=300000)
echo "building the fuzz targets"
if ! cargo build --release --target "$triple" --bins >build.log 2>&1; then
    tail -n 40 build.log >&2
    echo "fuzz build failed" >&2
    exit 1
fi
mkdir -p artifacts
crashed=0
if [ "$long_minutes" -gt 0 ]; then
    {
        echo "# Long fuzz run ($(date -u +%Y-%m-%d), $long_minutes min a target, $(git rev-parse --short HEAD 2>/dev/null || echo '?'))"
        echo
        echo "| Target | Seconds | Inputs run | Coverage (edges) | Crash |"
        echo "| --- | --- | --- | --- | --- |"
    } >long-report.md
fi
for t in "${targets[@]}"; do
    corpus="corpus/$t"
    mkdir -p "$corpus"
    cp -n seeds/"$t"/* "$corpus"/ 2>/dev/null || true
    status=0
    n=$((runs[$t] * scale))
    limit=300
    if [ "$long_minutes" -gt 0 ]; then
        # Time-bound: as many inputs as the minutes allow.
        n=-1
        limit=$((long_minutes * 60))
    fi
    start=$SECONDS
    if [ ! -x "target/$triple/release/$t" ]; then
        echo "fuzz/run.sh: target/$triple/release/$t was not built" >&2
        exit 1
    fi
    "target/$triple/release/$t" "$corpus" -seed=1 -runs="$n" -max_total_time="$limit" \
        -rss_limit_mb=2048 -timeout=10 -artifact_prefix="artifacts/$t-" \
        -print_final_stats=1 >"run-$t.log" 2>&1 || status=$?
    done_n=$(sed -n 's/^stat::number_of_executed_units: *//p' "run-$t.log")
    echo "fuzzed $t: ${done_n:-?} inputs in $((SECONDS - start)) s, exit $status"
    if [ "$long_minutes" -gt 0 ]; then
        cov=$(grep -oE "cov: [0-9]+" "run-$t.log" | tail -n 1 | cut -d' ' -f2)
        echo "| $t | $((SECONDS - start)) | ${done_n:-?} | ${cov:-?} | $([ "$status" -eq 0 ] && echo none || echo "exit $status, see fuzz/artifacts/") |" >>long-report.md
    fi
    if [ "$status" -ne 0 ]; then
        grep -E "panicked|ERROR|SUMMARY|Test unit written" "run-$t.log" >&2 || tail -n 30 "run-$t.log" >&2
        echo "fuzz target $t found a crash (input in fuzz/artifacts/)" >&2
        crashed=$((crashed + 1))
        # A long run goes on to the other targets and fails at the end.
        [ "$long_minutes" -gt 0 ] || exit 1
    fi
done
if [ "$crashed" -gt 0 ]; then
    echo "fuzzing: $crashed target(s) crashed" >&2
    exit 1
fi
echo "fuzzing: no crashes"

#!/usr/bin/env bash
# Builds the cargo-fuzz targets and runs each for a bounded time.
#   fuzz/run.sh [SECONDS_PER_TARGET]   (default 45)
# Installs cargo-fuzz when it is missing. The toolchain is stable, so
# RUSTC_BOOTSTRAP=1 lets cargo-fuzz pass its instrumentation flags; no
# sanitizer is used (Rust is memory-safe; we hunt panics, hangs, NaN
# assertions and runaway memory). Seeds: fuzz/seeds/<target>/, copied into
# the working corpus so the committed files are never modified. Any crash
# fails the run and leaves its input under fuzz/artifacts/<target>/.
set -euo pipefail
cd "$(dirname "$0")"
seconds="${1:-45}"
export RUSTC_BOOTSTRAP=1
if ! cargo fuzz --version >/dev/null 2>&1; then
    echo "installing cargo-fuzz"
    cargo install --locked cargo-fuzz
fi
targets=(preset mesh_obj mesh_gltf image)
if ! cargo fuzz build --sanitizer none >build.log 2>&1; then
    tail -n 40 build.log >&2
    echo "fuzz build failed" >&2
    exit 1
fi
for t in "${targets[@]}"; do
    corpus="corpus/$t"
    mkdir -p "$corpus"
    if [ -d "seeds/$t" ]; then
        cp -n seeds/"$t"/* "$corpus"/ 2>/dev/null || true
    fi
    echo "fuzzing $t for ${seconds}s"
    status=0
    cargo fuzz run --sanitizer none "$t" "$corpus" -- \
        -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=10 \
        -print_final_stats=1 >"run-$t.log" 2>&1 || status=$?
    grep -E "stat::number_of_executed_units|stat::peak_rss_mb|DONE|panicked|ERROR|SUMMARY|Test unit written" "run-$t.log" || true
    if [ "$status" -ne 0 ]; then
        tail -n 30 "run-$t.log" >&2
        echo "fuzz target $t found a crash (see fuzz/artifacts/$t)" >&2
        exit 1
    fi
done
echo "fuzzing: no crashes"

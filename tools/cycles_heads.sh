#!/usr/bin/env bash
# The ground truth against Blender's Cycles on whole heads (issue 53, item 3):
# for each head (the scan, the procedural head) and view (front-lit,
# side-lit, the back-lit ear), scatterlab renders `none` and `reference`
# (linear EXR, --ior 1, no environment, transmission off: the unscattered
# frame is Lambert under the key alone, as Cycles' no-subsurface render is),
# writes the camera and mesh (--stats, --scene-obj), and
# tests/clients/blender_head.py renders the same shot in Cycles
# (Christensen-Burley and Random Walk, two seeds each) and prints the
# figures by region. The last lines are a table for docs/accuracy.md.
#
# Usage: tools/cycles_heads.sh [SIZE] [SAMPLES] [OUT_DIR] [VIEWS]
#   defaults: 160 256 target/cycles_heads, and every view; VIEWS is a
#   comma-separated subset of scan_front, scan_side, scan_backlit_ear,
#   head_front, head_side, head_backlit_ear.
# About 30 s a view at the defaults on 2 cores (release build), 3 minutes in all.
set -euo pipefail
cd "$(dirname "$0")/.."
size=${1:-160}
samples=${2:-256}
out=${3:-target/cycles_heads}
views=${4:-scan_front,scan_side,scan_backlit_ear,head_front,head_side,head_backlit_ear}
tools/python-env.sh >&2
py=.venv/bin/python
cargo build --release --quiet
bin=target/release/scatterlab
mkdir -p "$out"
"$bin" export --format blender --out "$out/snippet.py" >/dev/null

# blender_head.py's own log goes to blender.log beside its figures, and is
# shown when it fails.
cycles() {
    local dir=$1
    shift
    "$py" tests/clients/blender_head.py "$out/snippet.py" "$dir/none.json" "$dir/mesh.obj" \
        "$dir/none.exr" "$dir/reference.exr" "$dir" --samples "$samples" --random-walk "$@" \
        >"$dir/blender.log" 2>&1 || { tail -n 20 "$dir/blender.log" >&2; exit 1; }
    grep '^{' "$dir/blender.log" | tail -n 1 >"$dir/figures.json"
}

# Random Walk's (and Christensen-Burley's) radiance over the no-subsurface
# render on a flat plane 0.2 m across, seen and lit at several angles from
# its normal. Seen and lit square on, it is the reflectance the heads'
# Random Walk figures are also given divided by.
printf 'v -100 -100 0\nv 100 -100 0\nv 100 100 0\nv -100 100 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n' >"$out/plane.obj"
for angles in "0 0" "45 0" "70 0" "0 60"; do
    read -r seen lit <<<"$angles"
    plane="$out/plane_seen${seen}_lit${lit}"
    mkdir -p "$plane"
    for m in none reference; do
        "$bin" render --mesh "$out/plane.obj" --metres-per-unit 0.001 --camera-yaw "$seen" \
            --camera-pitch 0 --camera-distance 0.1 --light-azimuth "$lit" --light-elevation 0 \
            --no-lod --ior 1 --transmission off --environment-intensity 0 --deterministic \
            --width 64 --height 64 --method "$m" --out "$plane/$m.exr" --stats "$plane/$m.json" \
            --scene-obj "$plane/mesh.obj" >/dev/null
    done
    cycles "$plane"
    "$py" -c "
import json
d = json.load(open('$plane/figures.json'))
r = d['regions']['skin']
print('plane seen at $seen deg, lit at $lit deg: Random Walk / no subsurface',
      [round(v, 4) for v in d['random_walk_over_no_sss']],
      '; reference effect %+.2f %%, Cycles C-B effect %+.2f %% of the lit level'
      % (100 * r['effect_reference'], 100 * r['effect_cycles']))" >&2
done
flat=$("$py" -c "import json; print(','.join(f'{v:.4f}' for v in json.load(open('$out/plane_seen0_lit0/figures.json'))['random_walk_over_no_sss']))")

# head: mesh arguments; view: camera yaw, light azimuth, light elevation.
declare -A mesh=(
    [scan]="--mesh assets/scan/LeePerrySmith.glb --metres-per-unit 0.0462 --camera-distance 0.6"
    [head]="--mesh assets/head/head.obj --metres-per-unit 0.1 --camera-distance 0.55"
)
declare -A view=(
    [front]="20 50 25"
    [side]="20 100 10"
    [backlit_ear]="65 200 10"
)
for h in scan head; do
    for v in front side backlit_ear; do
        [[ ",$views," == *",${h}_$v,"* ]] || continue
        read -r yaw az el <<<"${view[$v]}"
        dir="$out/${h}_$v"
        mkdir -p "$dir"
        common=(${mesh[$h]} --camera-yaw "$yaw" --light-azimuth "$az" --light-elevation "$el"
            --no-lod --ior 1 --transmission off --environment-intensity 0 --deterministic
            --width "$size" --height "$size")
        for m in none reference; do
            "$bin" render "${common[@]}" --method "$m" --out "$dir/$m.exr" \
                --stats "$dir/$m.json" --scene-obj "$dir/mesh.obj" >/dev/null
        done
        cycles "$dir" --random-walk-reflectance "$flat"
        echo "${h}_$v: $(cut -c1-200 "$dir/figures.json")" >&2
    done
done
"$py" - "$out" <<'EOF'
import json, os, sys
out = sys.argv[1]
print("| view | region | pixels | none - no-SSS | effect, Cycles C-B | effect, reference | RMS reference - C-B | C-B seeds' noise | effect, Random Walk | RMS RW - C-B | effect, RW / plane | RMS RW / plane - C-B |")
print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
for name in sorted(os.listdir(out)):
    f = os.path.join(out, name, "figures.json")
    if name.startswith("plane") or not os.path.exists(f):
        continue
    d = json.load(open(f))
    for region, r in d["regions"].items():
        pct = lambda x: f"{100 * x:+.2f} %"
        print(f"| {name} | {region} | {r['pixels']} | {pct(r['none_minus_no_sss'])} | {pct(r['effect_cycles'])} | "
              f"{pct(r['effect_reference'])} | {100 * r['rms_reference_minus_cycles']:.2f} % | "
              f"{100 * r['noise']:.2f} % | {pct(r['effect_random_walk'])} | "
              f"{100 * r['rms_random_walk_minus_burley']:.2f} % | {pct(r['effect_random_walk_flat'])} | "
              f"{100 * r['rms_random_walk_flat_minus_burley']:.2f} % |")
EOF

#!/usr/bin/env bash
# A side-lit sphere of the default skin rendered by scatterlab's ground truth
# and by Cycles' Christensen-Burley, both against a quadrature of the
# integral they compute (tools/sphere_quadrature.py; issue 53, item 3).
#
# Usage: tools/cycles_sphere.sh [RADIUS_MM] [OUT_DIR]   (default 10 target/cycles_sphere)
# About a minute (release build, 160², 256 samples).
set -euo pipefail
cd "$(dirname "$0")/.."
rho=${1:-10}
out=${2:-target/cycles_sphere}
tools/python-env.sh >&2
py=.venv/bin/python
cargo build --release --quiet
bin=target/release/scatterlab
mkdir -p "$out"
# A UV sphere, 96 x 48 quads, in millimetres, facing outward.
"$py" - "$rho" "$out/sphere.obj" <<'EOF'
import math, sys
r, path = float(sys.argv[1]), sys.argv[2]
nu, nv = 96, 48
lines = []
for j in range(nv + 1):
    th = math.pi * j / nv
    for i in range(nu + 1):
        ph = 2 * math.pi * i / nu
        lines.append(f"v {r*math.sin(th)*math.cos(ph)} {r*math.cos(th)} {r*math.sin(th)*math.sin(ph)}")
for j in range(nv + 1):
    for i in range(nu + 1):
        lines.append(f"vt {i/nu} {1-j/nv}")
k = lambda i, j: j * (nu + 1) + i + 1
for j in range(nv):
    for i in range(nu):
        a, b, c, d = k(i, j), k(i + 1, j), k(i + 1, j + 1), k(i, j + 1)
        if j > 0:
            lines.append(f"f {a}/{a} {b}/{b} {c}/{c}")
        if j < nv - 1:
            lines.append(f"f {a}/{a} {c}/{c} {d}/{d}")
open(path, "w").write("\n".join(lines) + "\n")
EOF
# The sphere fills most of the frame: 4 diameters away, a 30° view.
distance=$("$py" -c "print(max(0.05, 4 * 2 * $rho / 1000))")
fov=$("$py" -c "import math; print(min(30, math.degrees(2 * math.atan(0.6 * 2 * $rho / 1000 / $distance))))")
common=(--mesh "$out/sphere.obj" --metres-per-unit 0.001 --camera-yaw 0 --camera-pitch 0
    --camera-distance "$distance" --fov "$fov" --light-azimuth 70 --light-elevation 0
    --no-lod --ior 1 --transmission off --environment-intensity 0 --deterministic
    --width 160 --height 160)
for m in none reference; do
    "$bin" render "${common[@]}" --method "$m" --out "$out/$m.exr" --stats "$out/$m.json" \
        --scene-obj "$out/mesh.obj" >/dev/null
done
"$bin" export --format blender --out "$out/snippet.py" >/dev/null
"$py" tests/clients/blender_head.py "$out/snippet.py" "$out/none.json" "$out/mesh.obj" \
    "$out/none.exr" "$out/reference.exr" "$out" --samples 256 >"$out/blender.log" 2>&1 ||
    { tail -n 20 "$out/blender.log" >&2; exit 1; }
"$py" tools/sphere_quadrature.py "$out" "$rho"

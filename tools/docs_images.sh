#!/bin/bash
# Re-renders docs/images/ from the current build (lavapipe or any adapter).
# Needs ImageMagick's `montage`. Usage: tools/docs_images.sh [path/to/scatterlab]
set -euo pipefail
bin=${1:-target/debug/scatterlab}
out=docs/images
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
r() { "$bin" render --deterministic "$@" >/dev/null; }

# Six methods, front-left key light with a hard shadow from the nose.
for m in none preintegrated separable gaussians burley reference; do
  r --method "$m" --width 384 --height 384 --light-azimuth 50 --light-elevation 25 \
    --out "$tmp/$m.png"
done
montage -label '%t' -font DejaVu-Sans -pointsize 16 \
  "$tmp"/{none,preintegrated,separable,gaussians,burley,reference}.png \
  -tile 3x2 -geometry +4+4 -background '#202428' -fill white "$out/methods.png"

# Back-lit ear: thin-object transmission, off, and thick-object.
for t in thin off thick; do
  r --method burley --width 384 --height 384 --camera-yaw 65 --camera-distance 0.4 \
    --light-azimuth 200 --light-elevation 10 --transmission "$t" --out "$tmp/ear_$t.png"
done
r --method burley --diff --width 384 --height 384 --out "$tmp/diff.png"
montage -label '%t' -font DejaVu-Sans -pointsize 16 \
  "$tmp"/ear_thin.png "$tmp"/ear_off.png "$tmp"/ear_thick.png "$tmp"/diff.png \
  -tile 4x1 -geometry +4+4 -background '#202428' -fill white "$out/transmission_and_diff.png"

# Split view: burley | separable.
r --method burley --compare separable --split 0.5 --width 512 --height 512 \
  --out "$out/compare_burley_separable.png"

# Close-up, side light: burley | none; the terminator softens and reddens.
r --method burley --compare none --split 0.5 --width 512 --height 512 \
  --camera-distance 0.32 --camera-yaw 25 --light-azimuth 75 --light-elevation 20 \
  --out "$out/closeup_burley_vs_none.png"
# The default head from the front and its eyes in close-up (sclera, iris,
# pupil, the cornea's highlight).
r --method burley --width 512 --height 640 --camera-yaw 0 --light-azimuth 35 \
  --light-elevation 25 --out "$out/head_front.png"
r --method burley --width 640 --height 320 --camera-yaw 12 --camera-distance 0.16 \
  --light-azimuth 35 --light-elevation 20 --out "$out/head_eyes_closeup.png"

# The look's colour is the head's colour: four presets on the default head.
for p in skin_default ketchup_jensen2001 marble_jensen2001 skin_jimenez2012_demo; do
  r --preset "presets/$p.ron" --width 256 --height 320 --camera-yaw 0 --light-azimuth 35 \
    --out "$tmp/look_$p.png"
done
montage -label '%t' -font DejaVu-Sans -pointsize 14 "$tmp"/look_*.png \
  -tile 4x1 -geometry +4+4 -background '#202428' -fill white "$out/looks.png"
# Every method beside the ground truth (`reference`, object space) and its
# |method − ground truth| on one scale: the front-lit head, and the
# back-lit ear with thin and with thick transmission. All on the
# finest mesh (--no-lod), as the ground truth integrates it.
views=(
  "front|--light-azimuth 50 --light-elevation 25"
  "ear_thin|--camera-yaw 65 --camera-distance 0.4 --light-azimuth 200 --light-elevation 10 --transmission thin"
  "ear_thick|--camera-yaw 65 --camera-distance 0.4 --light-azimuth 200 --light-elevation 10 --transmission thick"
)
for v in "${views[@]}"; do
  name=${v%%|*}
  read -r -a args <<<"${v#*|}"
  r --method reference --no-lod "${args[@]}" --width 256 --height 256 --out "$tmp/gt_$name.png"
  for m in none preintegrated separable gaussians burley; do
    r --method "$m" --no-lod "${args[@]}" --width 256 --height 256 --out "$tmp/${m}_$name.png"
    r --method "$m" --compare reference --diff --diff-scale 10 --no-lod "${args[@]}" \
      --width 256 --height 256 --out "$tmp/${m}_${name}_diff.png"
  done
  montage -label '%t' -font DejaVu-Sans -pointsize 14 \
    "$tmp/gt_$name.png" "$tmp"/{none,preintegrated,separable,gaussians,burley}_"$name".png \
    null: "$tmp"/{none,preintegrated,separable,gaussians,burley}_"${name}"_diff.png \
    -tile 6x2 -geometry +3+3 -background '#202428' -fill white "$out/ground_truth_$name.png"
done
echo "wrote $out/{methods,transmission_and_diff,compare_burley_separable,closeup_burley_vs_none,head_front,head_eyes_closeup,looks,ground_truth_front,ground_truth_ear_thin,ground_truth_ear_thick}.png"

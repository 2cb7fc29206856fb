#!/usr/bin/env bash
# Method 2 on a photographed focus sweep: the real handheld keyboard sweep in
# ../shared/data (32 phone frames, far focus to near, not aligned, no focus
# metadata) when present, else a focus stack of the generated scene rendered
# by the ray tracer. --depth-from-focus aligns the frames and finds each
# pixel's sharpest one; the aligned stack then composites two focal planes
# with the sweep's own optical blur. Writes the README's picture
# docs/images/focus_sweep.png: a frame of the sweep, the all-in-focus plate,
# its depth (white = near), the two-plane composite.
#
#   examples/focus_sweep/run.sh        (GDOF_BUILD_DIR: build folder, GDOF_OUT: output folder)
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
build="${GDOF_BUILD_DIR:-$root/build}"
out="${GDOF_OUT:-$root/out}/focus_sweep"
gdof="$build/cli/gdof"
keyboard="${GDOF_KEYBOARD_DIR:-$root/../shared/data/focalstack/keyboard}"
rm -rf "$out"
mkdir -p "$out" "$root/docs/images"

if [ -f "$keyboard/00.jpg" ]; then
    echo "== real handheld sweep: $keyboard" >&2
    sweep="$keyboard/##.jpg"
    field="$here/two_planes_index.json"
    lens=(--focal-length-mm 26)   # a camera for the rays (a phone's; the field is in frame indices)
    middle="$keyboard/15.jpg"     # frame 16 of 32, the one the others are aligned to
    index_scale=0.03125           # 1 / 32 frames
else
    echo "== no keyboard sweep under $keyboard: rendering a focus stack of the generated scene" >&2
    sed 's/\[640, 360\]/[320, 180]/' "$root/examples/render/generated.json" > "$out/scene.json"
    cp "$root/examples/render/generated.obj" "$root/examples/render/generated.mtl" "$out/"
    "$gdof" --render "$out/scene.json" --spp 24 --stack "$here/render_stack.json" -o "$out/sweep/ref.####.exr"
    sweep="$out/sweep/manifest.json"
    field="$here/two_planes_metric.json"
    lens=()
    middle="$out/sweep/ref.0004.exr"
    index_scale=0.125             # 1 / 8 frames
fi

echo "== --depth-from-focus -> $out/plate.exr, aligned stack -> $out/aligned" >&2
"$gdof" --stats --aligned-stack "$out/aligned/ref.####.exr" --depth-from-focus "$sweep" -o "$out/plate.exr"
echo "== two focal planes from the aligned stack -> $out/two_planes.exr" >&2
"$gdof" "$out/plate.exr" "${lens[@]}" --blurfield "$field" --composite "$out/aligned/manifest.json" --stats \
        -o "$out/two_planes.exr"

echo "== picture -> docs/images/focus_sweep.png" >&2
"$gdof" "$middle" --ch R,G,B -o "$out/frame.png"
"$gdof" "$out/plate.exr" --ch R,G,B -o "$out/all_in_focus.png"
# The depth as the frame index, white = the last frame (the nearest in the
# keyboard sweep, the farthest in the rendered one).
"$gdof" "$out/plate.exr" --ch R=focus.index,G=focus.index,B=focus.index --mulc "$index_scale" \
        --ocolorspace linear -o "$out/depth.png"
"$gdof" "$out/two_planes.exr" --ch R,G,B -o "$out/two_planes.png"
oiiotool "$out/frame.png" "$out/all_in_focus.png" "$out/depth.png" "$out/two_planes.png" --mosaic 2x2 \
         -o "$root/docs/images/focus_sweep.png"
echo "wrote $root/docs/images/focus_sweep.png" >&2

#!/usr/bin/env bash
# Method 2, light-field stacks: extracts a focus/aperture stack by
# shift-and-add from the real Lytro views in ../shared/data (when present),
# else from a generated light field, and writes PNG previews of a few
# refocused references to docs/images/lightfield_*.png.
#
#   examples/lightfield/run.sh        (GDOF_BUILD_DIR: build folder, GDOF_OUT: output folder)
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
build="${GDOF_BUILD_DIR:-$root/build}"
out="${GDOF_OUT:-$root/out}/lightfield"
gdof="$build/cli/gdof"
lytro="${GDOF_LYTRO_DIR:-$root/../shared/data/lightfield/lytro_2067}"
mkdir -p "$out" "$root/docs/images"

if [ -f "$lytro/2067_05_05.png" ]; then
    echo "== real Lytro views: $lytro" >&2
    views="$lytro/2067_%02d_%02d.png"
    lf="$here/lf.json"
    stack="$here/stack.json"
    # references: disparities (-0.2 0 0.2 ... 1.2) x apertures (1 2 3): index = 3 * i_disparity + i_aperture + 1
    previews="6:far 12:mid 21:near"       # d = 0.0, 0.4, 1.0 at aperture 3
    pinhole="$lytro/2067_05_05.png"
else
    echo "== no Lytro views under $lytro: generating a light field" >&2
    "$build/examples/gdof_example_lightfield" -o "$out/views"
    views="$out/views/view_%02d_%02d.png"
    lf="$out/views/lf.json"
    stack="$here/stack_generated.json"
    previews="3:far 9:mid 15:near"        # d = 0.25, 1.0, 2.0 at aperture 3
    pinhole="$out/views/view_02_02.png"
fi

echo "== extracting the stack -> $out/stack" >&2
rm -rf "$out/stack"
"$gdof" --lightfield "$views" --lf "$lf" --stack "$stack" --stats -o "$out/stack/ref.####.exr"
echo "== manifest: $out/stack/manifest.json" >&2

echo "== previews -> docs/images/lightfield_*.png" >&2
"$gdof" "$pinhole" -o "$root/docs/images/lightfield_central.png"
for p in $previews; do
    i="${p%%:*}"
    name="${p##*:}"
    "$gdof" "$out/stack/ref.$(printf %04d "$i").exr" -o "$root/docs/images/lightfield_$name.png"
done
if [ -f "$lytro/2067_05_05.png" ]; then
    echo "== method 2: per-pixel composite with a tilted plane of focus -> docs/images/lightfield_composite_tilt.png" >&2
    "$gdof" --composite "$out/stack/manifest.json" --surfaces "$here/surfaces_tilt.json" --aovs --stats \
            -o "$out/composite_tilt.exr"
    "$gdof" "$out/composite_tilt.exr" --ch R,G,B -o "$root/docs/images/lightfield_composite_tilt.png"
fi
ls "$root"/docs/images/lightfield_*.png >&2

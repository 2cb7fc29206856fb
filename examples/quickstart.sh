#!/usr/bin/env bash
# One command from a fresh Debian bookworm machine (as root): installs the
# packages, builds gdof, generates the bundled example scene and runs the
# main job on it. Results land in ./out (EXR + PNG previews).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="${GDOF_OUT:-$root/out}"
build="${GDOF_BUILD_DIR:-$root/build}"
bash "$root/.ci/install-deps"
GDOF_BUILD_DIR="$build" bash "$root/.ci/build" -DGDOF_BUILD_TESTS=OFF
gdof="$build/cli/gdof"
mkdir -p "$out"

echo "== generating the example scene (RGBA, Z, P, N, id + camera) -> $out/scene.exr" >&2
"$build/examples/gdof_example_scene" --size 640x360 -o "$out/scene.exr" --deep "$out/scene_deep.exr"
"$gdof" --info "$out/scene.exr"

echo "== the blur field (two focal planes) evaluated on the scene -> $out/blur.exr" >&2
"$gdof" "$out/scene.exr" --blurfield "$root/examples/scene/two_planes.json" --eval-blur \
        -o "$out/blur.exr"

echo "== PNG previews" >&2
"$gdof" "$out/scene.exr" --ch R,G,B -o "$out/scene.png"
"$gdof" "$out/blur.exr" --ch R=blur,G=blur,B=blur --mulc 0.1 --ocolorspace linear -o "$out/blur.png"
echo "wrote $out/scene.exr $out/scene_deep.exr $out/blur.exr $out/scene.png $out/blur.png" >&2

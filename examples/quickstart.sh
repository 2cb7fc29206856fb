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

echo "== the main job: generalized defocus by heat diffusion (two focal planes) -> $out/defocus.exr" >&2
"$gdof" "$out/scene.exr" --blurfield "$root/examples/scene/two_planes.json" --diffuse --stats \
        -o "$out/defocus.exr"
"$gdof" "$out/scene_deep.exr" --blurfield "$root/examples/scene/sphere_of_focus.json" --diffuse \
        -o "$out/defocus_sphere_from_deep.exr"

echo "== PNG previews" >&2
"$gdof" "$out/scene.exr" --ch R,G,B -o "$out/scene.png"
"$gdof" "$out/blur.exr" --ch R=blur,G=blur,B=blur --mulc 0.1 --ocolorspace linear -o "$out/blur.png"
"$gdof" "$out/defocus.exr" --ch R,G,B -o "$out/defocus.png"
"$gdof" "$out/defocus_sphere_from_deep.exr" --ch R,G,B -o "$out/defocus_sphere_from_deep.png"
echo "wrote $(cd "$out" && ls)" >&2

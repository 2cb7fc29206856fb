#!/usr/bin/env bash
# Regenerates the pictures in the README (docs/images/) from the bundled
# example scene. Needs a build (bash .ci/build, or examples/quickstart.sh).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${GDOF_BUILD_DIR:-$root/build}"
gdof="$build/cli/gdof"
img="$root/docs/images"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$img"
"$build/examples/gdof_example_scene" --size 640x360 -o "$tmp/scene.exr" --deep "$tmp/deep.exr"
"$gdof" "$tmp/scene.exr" --ch R,G,B -o "$img/example_scene.png"
# The blur field of examples/scene/two_planes.json on the scene: white = 10 px.
"$gdof" "$tmp/scene.exr" --blurfield "$root/examples/scene/two_planes.json" --eval-blur \
        --ch R=blur,G=blur,B=blur --mulc 0.1 --ocolorspace linear -o "$img/example_blur_two_planes.png"
"$gdof" "$tmp/scene.exr" --blurfield "$root/examples/scene/sphere_of_focus.json" --eval-blur \
        --ch R=blur,G=blur,B=blur --mulc 0.1 --ocolorspace linear -o "$img/example_blur_sphere.png"
# Method 3 (heat diffusion): the same two fields applied to the scene.
"$gdof" "$tmp/scene.exr" --blurfield "$root/examples/scene/two_planes.json" --diffuse \
        --ch R,G,B -o "$img/diffusion_two_planes.png"
"$gdof" "$tmp/deep.exr" --blurfield "$root/examples/scene/sphere_of_focus.json" --diffuse \
        --ch R,G,B -o "$img/diffusion_sphere_from_deep.png"
# The OpenFX plugin: "gdof Defocus" on the same scene in the test host of
# tests/ofx (a build with -DGDOF_BUILD_OFX=ON), the Source and the effect's
# output side by side as in a host's viewer.
ofx_picture="$build/tests/gdof_ofx_readme_picture"
ofx_bundle="$build/ofx_plugin/gdof.ofx.bundle/Contents/Linux-x86-64/gdof.ofx"
if [[ -x "$ofx_picture" && -f "$ofx_bundle" ]]; then
  "$ofx_picture" "$ofx_bundle" "$tmp/scene.exr" "$img/ofx_defocus_before_after.png"
else
  echo "skipping the OFX picture: build with -DGDOF_BUILD_OFX=ON (needs $ofx_picture)" >&2
fi
# Method 1 (nonlinear ray tracing): the generated render scene with two focal planes.
"$gdof" --render "$root/examples/render/generated.json" --blurfield "$root/examples/render/generated_two_planes.json" \
        --spp 32 -o "$tmp/render.exr"
"$gdof" "$tmp/render.exr" --ch R,G,B -o "$img/raytrace_two_planes.png"
# Bokeh (--bokeh, --aperture): the highlights scene's deep all-in-focus render
# defocused with a Gaussian (--diffuse), a disc and a 6-blade iris, next to
# the ray tracer's render with the same iris. Exposure 1/2 shows the shapes.
hl="$root/examples/render/highlights.json"
"$gdof" --render "$hl" --pinhole --deep --spp 64 -o "$tmp/hl_deep.exr"
"$gdof" --render "$hl" --aperture polygon:6:15 --spp 256 --ch R,G,B --mulc 0.5 -o "$img/bokeh_raytraced_hexagon.png"
"$gdof" "$tmp/hl_deep.exr" --diffuse --ch R,G,B --mulc 0.5 -o "$img/bokeh_diffuse.png"
"$gdof" "$tmp/hl_deep.exr" --bokeh --ch R,G,B --mulc 0.5 -o "$img/bokeh_disc.png"
"$gdof" "$tmp/hl_deep.exr" --aperture polygon:6:15 --bokeh --ch R,G,B --mulc 0.5 -o "$img/bokeh_hexagon.png"
"$gdof" "$tmp/hl_deep.exr" --aperture disc,squeeze=1.8,cats_eye=0.6 --bokeh --ch R,G,B --mulc 0.5 \
        -o "$img/bokeh_anamorphic_cats_eye.png"
# Method 4 (--vibrate): the same deep render through the PSF field, the
# thin-lens special case (defocus, disc) and a swirl (examples/psf_fields).
"$gdof" "$tmp/hl_deep.exr" --psf-samples 128 --vibrate --ch R,G,B --mulc 0.5 -o "$img/psf_disc.png"
"$gdof" "$tmp/hl_deep.exr" --psf-field "$root/examples/psf_fields/swirl.json" --psf-samples 128 --vibrate \
        --ch R,G,B --mulc 0.5 -o "$img/psf_swirl.png"
# Live action: a real RGB-D frame (TUM: colour PNG + uint16 depth PNG, metres =
# counts / 5000, 19% holes), plate and depth map as two files, focus picked on
# the yellow chair. Skipped when ../shared/data is absent.
tum="$root/../shared/data/rgbd/tum"
if [[ -f "$tum/color.png" && -f "$tum/depth.png" ]]; then
  "$gdof" "$tum/color.png" --ch R,G,B -o "$img/live_tum_plate.png"
  "$gdof" "$tum/color.png" --depth-channel Y --depth-encoding scaled --depth-scale 13.107 --depth "$tum/depth.png" \
          --focal-length-mm 50 --sensor-width-mm 36 --f-number 0.7 --focus-at 470,270 --probe 470,270 \
          --diffuse --ch R,G,B -o "$img/live_tum_defocus.png"
else
  echo "skipping the live-action pictures: no $tum" >&2
fi
# Method 2 on a photographed focus sweep (the real keyboard sweep when
# ../shared/data is there, else a rendered focus stack): docs/images/focus_sweep.png.
GDOF_BUILD_DIR="$build" GDOF_OUT="$tmp" bash "$root/examples/focus_sweep/run.sh"
echo "wrote $(ls "$img")" >&2

#!/usr/bin/env bash
# Regenerates the kept seed corpora (tests/fuzz/corpus/<harness>) and the
# JSON dictionaries (tests/fuzz/dict): small files made here (oiiotool for
# the EXRs) and the repository's own examples. Real data from ../shared/data
# is not copied into the repository: .ci/fuzz adds it to its working corpus.
# Usage: bash tests/fuzz/make_corpus.sh   (needs oiiotool)
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
c="$here/corpus"
rm -rf "$c"
mkdir -p "$c"/{exr,blur_field,psf_field,stack_json,focus_surfaces,scene,obj,lightfield,lens_table,frames,cli_args,defocus} "$here/dict"

# ---- EXR: flat, float + Z, windows, tiled, mip-mapped, multipart, deep, attributes
o=(oiiotool --nosoftwareattrib)
e="$c/exr"
"${o[@]}" --pattern checker 4x3 4 --chnames R,G,B,A -d half -o "$e/flat_rgba_half.exr"
"${o[@]}" --pattern fill:top=0.1,0.2,0.3,1,2:bottom=1,1,1,1,9 4x4 5 --chnames R,G,B,A,Z -d float --compression none -o "$e/flat_rgbaz_float.exr"
"${o[@]}" --pattern constant:color=0.5,0.5,0.5,1 3x2 4 --chnames R,G,B,A --origin +2+1 --fullsize 8x6 --compression rle -o "$e/data_window.exr"
"${o[@]}" --pattern checker 8x8 4 --chnames R,G,B,A --tile 4 4 --compression zip -o "$e/tiled.exr"
"${o[@]}" --pattern checker 8x8 3 --tile 4 4 -o:mipmap=1 --compression piz "$e/mipmap.exr" 2>/dev/null ||
  "${o[@]}" --pattern checker 8x8 3 --tile 4 4 --compression piz -o "$e/mipmap.exr"
"${o[@]}" --pattern checker 4x4 4 --chnames R,G,B,A --attrib oiio:subimagename beauty \
  --pattern constant:color=3 4x4 1 --chnames Z --attrib oiio:subimagename depth --siappend -o "$e/multipart.exr"
"${o[@]}" --pattern fill:top=0.2,0.3,0.4,1,1:bottom=0.5,0.5,0.5,1,4 4x3 5 --chnames R,G,B,A,Z --deepen -o "$e/deep.exr"
"${o[@]}" --pattern constant:color=1,0,0,1,5 3x3 5 --chnames R,G,B,A,Z --deepen --tile 2 2 -o "$e/deep_tiled.exr"
"${o[@]}" --pattern checker 2x2 4 --chnames R,G,B,A \
  --attrib:type=matrix worldToCamera "1,0,0,0,0,1,0,0,0,0,1,0,0,0,0,1" \
  --attrib:type=matrix worldToNDC "1,0,0,0,0,1,0,0,0,0,-1,-1,0,0,-0.1,0" \
  --attrib:type=float focalLength 50 --attrib:type=float aperture 2.8 --attrib:type=float focus 3 \
  --sattrib chromaticities none --attrib:type=int gdof:emptyDataWindow 0 --sattrib view left \
  -o "$e/attributes.exr"

# ---- JSON and text from the repository's examples
cp "$root"/examples/blurfields/*.json "$c/blur_field/"
cp "$root"/examples/psf_fields/*.json "$c/psf_field/"
cp "$root"/examples/scene/*.json "$c/blur_field/" 2>/dev/null || true
cp "$root"/examples/stack/*.json "$root"/examples/lightfield/surfaces_tilt.json "$c/focus_surfaces/"
cp "$root"/examples/render/*.json "$c/scene/"
cp "$root"/examples/lightfield/stack*.json "$c/stack_json/"
cat > "$c/stack_json/listed.json" <<'J'
{"references": [{"file": "a.exr", "focus_distance": 2, "f_number": 2.8, "focal_length_mm": 50},
                {"file": "b.exr", "focus_distance": 4, "f_number": 2.8, "focal_length_mm": 50}],
 "coc_px": 1, "sensor_width_mm": 36, "image_width_px": 64}
J
cat > "$c/stack_json/pattern.json" <<'J'
{"pattern": "ref.####.exr", "frames": "1-3", "lens_table": "lens.csv", "coc_px": 1}
J
printf '%s\n' '{"focus_distances": [1, 2, 4], "f_numbers": [2.8], "focal_length_mm": 50, "sensor_width_mm": 36}' > "$c/stack_json/render.json"
cp "$root"/examples/lightfield/lf.json "$c/lightfield/"
printf 'v_%%02d_%%02d.png\n{"baseline": 0.1, "focal_length_mm": 50, "sensor_width_mm": 36}\n' > "$c/lightfield/pattern"
printf '.\n{"disparity_at_infinity": 0.5}\n' > "$c/lightfield/folder"
printf 'frame,focus_distance,f_number,focal_length_mm\n1,2.0,2.8,50\n2,4,2.8,50\n3,inf,2.8,50\n' > "$c/lens_table/frames.csv"
printf 'file,focus_distance,f_number,focal_length_mm,near,far\n"a b.exr",2,2.8,50,1.5,3\nc.exr,10,8,35,5,inf\n' > "$c/lens_table/files.csv"
printf '1-10x2,15,20-18\nshot.####.exr\n' > "$c/frames/hash"
printf '3\nshot.%%04d.exr\n' > "$c/frames/printf"
printf '1,3,7-9\nshot.@@@.exr\n' > "$c/frames/at"
cp "$root"/examples/render/generated.mtl "$c/obj/generated.mtl.txt"
{ head -c 1500 "$root/examples/render/highlights.obj" | sed '$d'; printf '\n#MTL\n'; cat "$root/examples/render/highlights.mtl"; } > "$c/obj/highlights"
printf 'mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nusemtl lamp\nf 1//1 2//1 3//1 4//1\nf -1 -2 -3\n#MTL\nnewmtl lamp\nKd 0.5 0.5 0.5\nKe 4 4 4\n' > "$c/obj/quad"
printf 'in.exr\n-o\nout.exr\n' > "$c/cli_args/copy"
printf 'in.exr\n--blurfield\nf.json\n--diffuse\n--layers\nauto\n-o\nout.####.exr\n--frames\n1-3\n' > "$c/cli_args/diffuse"
printf -- '--render\nscene.json\n--deep\n--stack\ns.json\n-o\nstack/ref.####.exr\n--threads\n2\n' > "$c/cli_args/render"
printf -- '--composite\nm.json\n--surfaces\ns.json\n-o\nout.exr\n--colorconvert\nACES2065-1\nscene_linear\n' > "$c/cli_args/composite"
printf 'in.exr\n--bokeh\n--aperture\npolygon:6:roundness=0.3\n--focal-length\n50\n--fstop\n2.8\n--focus\n3\n-o\nout.exr\n' > "$c/cli_args/bokeh"

# ---- small plates and deep images for the post-process core
python3 "$here/defocus_seeds.py" "$c/defocus"

# ---- dictionaries: every quoted key the JSON parsers look for, and JSON syntax
keys() { grep -ohE '"[a-z_][a-z0-9_]*"' "$@" | sort -u; }
syntax='"{"
"}"
"["
"]"
":"
","
"true"
"false"
"null"
"1e308"
"-0"
"NaN"
"Infinity"'
{ echo "$syntax"; keys "$root"/lib/src/blur_field/blur_field_parse.cpp "$root"/lib/src/blur_field/blur_field_leaves.cpp "$root"/lib/src/blur_field/blur_field_combinators.cpp; } > "$here/dict/blur_field.dict"
# A PSF field's blend weights are blur-field nodes: both parsers' keys.
{ echo "$syntax"; keys "$root"/lib/src/psf_field/psf_field_parse.cpp "$root"/lib/src/blur_field/blur_field_parse.cpp "$root"/lib/src/blur_field/blur_field_leaves.cpp "$root"/lib/src/blur_field/blur_field_combinators.cpp; } > "$here/dict/psf_field.dict"
{ echo "$syntax"; keys "$root"/lib/src/stack/focal_stack_manifest.cpp "$root"/lib/io/src/stack/stack_sources.cpp "$root"/lib/src/raytrace/render_stack.cpp "$root"/lib/io/src/stack/lightfield_json.cpp; } > "$here/dict/stack_json.dict"
{ echo "$syntax"; keys "$root"/lib/src/stack/focus_surfaces.cpp; } > "$here/dict/focus_surfaces.dict"
{ echo "$syntax"; keys "$root"/lib/src/raytrace/scene_parse.cpp; } > "$here/dict/scene.dict"
{ echo "$syntax"; keys "$root"/lib/io/src/stack/lightfield_json.cpp; echo '"%02d"'; echo '"out_"'; } > "$here/dict/lightfield.dict"
printf '"v "\n"vn "\n"vt "\n"f "\n"mtllib "\n"usemtl "\n"newmtl "\n"Kd "\n"Ke "\n"o "\n"g "\n"#MTL"\n"-1"\n"nan"\n"inf"\n' > "$here/dict/obj.dict"
printf '"frame"\n"file"\n"focus_distance"\n"f_number"\n"focal_length_mm"\n"near"\n"far"\n"inf"\n","\n"\\""\n"\\x0a"\n' > "$here/dict/lens_table.dict"
printf '"#"\n"@"\n"%%0"\n"d"\n"-"\n"x"\n","\n"2147483647"\n"-2147483648"\n' > "$here/dict/frames.dict"
# The CLI's flags, from the command table's rows, each with the newline that ends an argument.
grep -ohE '\.names = \{[^}]*\}' "$root"/cli/ops/*.cpp | grep -oE '"-[^"]*"' | sort -u | sed 's/"$/\\x0a"/' > "$here/dict/cli_args.dict"
echo "corpora in $c, dictionaries in $here/dict"

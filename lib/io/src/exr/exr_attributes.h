// OpenEXR header attributes <-> gdof::Metadata (internal to gdof::io).
//
// Every attribute keeps its EXR name. Types are OIIO-style strings:
//   int float double string            scalars
//   string[N]                          stringvector (text: items joined by '\0')
//   float[N]                           floatvector; "chromaticities" is float[8]
//   vector2i vector2 vector2d          v2i v2f v2d
//   vector3i vector  vector3d          v3i v3f v3d
//   matrix33 matrix33d matrix matrixd  m33f m33d m44f m44d (row-major)
//   box2i box2                         box2i box2f as (xmin, ymin, xmax, ymax), inclusive
//   rational timecode keycode          (n, d) / (timeAndFlags, userData) / 7 ints
//   int with text "exr:<type>"         envmap, deepImageState, lineOrder enums (an
//                                      int named like one of those without the
//                                      text is written with that type too)
//   uint8[N] with text "exr:<type>"    any other type (preview, idmanifest, opaque
//                                      user types): the raw attribute bytes, so it
//                                      is written back exactly as it came
// Structural attributes (channels, dataWindow, displayWindow, compression,
// tiles, name, view, type, version, chunkCount) live elsewhere in the model.
#pragma once

#include <memory>
#include <string>

#include <OpenEXR/ImfAttribute.h>
#include <OpenEXR/ImfHeader.h>

#include "gdof/export.h"
#include "gdof/metadata.h"

namespace gdof::io::detail {

GDOF_API bool is_structural_exr_attribute(const std::string& name);
// Adds every non-structural header attribute to `md`.
GDOF_API void exr_header_to_metadata(const Imf::Header& header, Metadata& md);
// Inserts the metadata attributes into the header (skipping structural ones,
// OIIO bookkeeping "oiio:*" and types that have no EXR equivalent).
GDOF_API void metadata_to_exr_header(const Metadata& md, Imf::Header& header);
// One attribute; nullptr if it has no EXR form.
GDOF_API std::unique_ptr<Imf::Attribute> to_exr_attribute(const Attribute& a);

}  // namespace gdof::io::detail

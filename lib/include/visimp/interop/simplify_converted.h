// What both adapters' simplify_in_place share: visimp::simplify on a mesh converted from
// another library, VG taking V from the face property the conversion put in face_quality.
#pragma once

#include <string>

#include "visimp/core/errors.h"
#include "visimp/core/mesh.h"
#include "visimp/simplify/simplify.h"

namespace visimp::interop {

/// `property` names where V was looked for, for the error when VG finds none.
inline Simplified simplify_converted(const Mesh& in, SimplifyOptions options, const std::string& property) {
  if (options.method == SimplifyMethod::vg && options.face_visibility.empty()) {
    if (!in.has_face_quality()) throw UsageError("simplify_in_place: VG needs the face property " + property);
    options.face_visibility = in.face_quality;
  }
  return simplify(in, options);
}

}  // namespace visimp::interop

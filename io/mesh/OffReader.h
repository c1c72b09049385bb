// skelseg: the OFF reader (internal to io/mesh/; readMesh() in MeshIO.h
// dispatches to it by extension). Accepts the [ST][C][N]OFF
// variants with 3 dimensions, counts on the keyword line, the next one or one
// per line, files that leave the keyword out, and a colour after a face's
// indices (ignored); "OFF BINARY" in Geomview's layout and in pmp-library's
// (no colour count per face, either byte order).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "io/mesh/MeshIO.h"

namespace skelseg {

/// Reads an OFF file (ASCII, or Geomview's binary OFF) held in `size` bytes at `data`; `name` is
/// used in messages. @throw InputError(name, problem).
TriangleMesh readOff(const std::string& name, const char* data, std::size_t size);

}  // namespace skelseg

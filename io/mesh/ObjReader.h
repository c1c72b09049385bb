// skelseg: the OBJ reader (internal to io/mesh/; readMesh() in MeshIO.h
// dispatches to it by extension). Reads v and f statements
// (v, v/vt, v//vn, v/vt/vn and negative indices) and ignores every other one;
// a backslash at the end of a line continues the statement on the next.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "io/mesh/MeshIO.h"

namespace skelseg {

/// Reads a Wavefront OBJ file held in `size` bytes at `data`; `name` is used
/// in messages. @throw InputError(name, problem).
TriangleMesh readObj(const std::string& name, const char* data, std::size_t size);

}  // namespace skelseg

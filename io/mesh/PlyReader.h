// skelseg: the PLY reader (internal to io/mesh/; readMesh() in MeshIO.h
// dispatches to it by extension). ascii,
// binary_little_endian and binary_big_endian; vertex x, y, z and the face list
// vertex_indices (or vertex_index); every other element and property is skipped.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "io/mesh/MeshIO.h"

namespace skelseg {

/// Reads a PLY file held in `size` bytes at `data`; `name` is used in
/// messages. @throw InputError(name, problem).
TriangleMesh readPly(const std::string& name, const std::uint8_t* data, std::size_t size);

}  // namespace skelseg

// skelseg: the STL reader (internal to io/mesh/; readMesh() in MeshIO.h
// dispatches to it by extension). ASCII and binary; STL
// repeats every corner per facet, so corners at identical positions are merged.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "io/mesh/MeshIO.h"

namespace skelseg {

/// Reads an STL file (binary when its size is 84 + 50 n for the n in its
/// header, otherwise ASCII) held in `size` bytes at `data`; `name` is used in
/// messages. @throw InputError(name, problem).
TriangleMesh readStl(const std::string& name, const std::uint8_t* data, std::size_t size);

}  // namespace skelseg

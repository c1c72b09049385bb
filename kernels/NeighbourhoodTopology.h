// skelseg: the topology numbers of a voxel's 3x3x3 neighbourhood, for
// (26, 6) connectivity (objects 26-connected, background 6-connected).
//
// T26 counts the 26-connected pieces of the object voxels around a voxel
// (itself excluded); T6 counts the 6-connected pieces of the background
// voxels within its 18-neighbourhood that touch it by a face. A voxel is
// simple (setting or clearing it changes no object, cavity or tunnel) when
// both are 1; a background voxel with T26 = 1 and T6 >= 2 closes a passage
// of the background (kernels/NarrowTunnels.h, kernels/TunnelPlugs.h). These
// are the numbers of Bertrand and Malandain's characterisation of simple
// points; a 27-bit mask and a table of touching bits keep each count to a
// few word operations.
#pragma once

#include <cstdint>

#include "kernels/base/Volume.h"

namespace skelseg {

/// Bit (dz + 1) * 9 + (dy + 1) * 3 + (dx + 1) of a neighbourhood; the voxel
/// itself is bit kNeighbourhoodCentre.
constexpr int kNeighbourhoodCentre = 13;

/// The object voxels of the 3x3x3 neighbourhood of (x, y, z) as bits (the
/// voxel must not lie on the grid's outermost layer).
std::uint32_t neighbourhoodBits(const MaskVolume& mask, int x, int y, int z);

/// The centre's six face neighbours as bits.
std::uint32_t faceNeighbourBits();

/// T26: the 26-connected pieces of the object bits around the centre.
int objectPieces26(std::uint32_t bits);

/// T6: the 6-connected pieces of the background within the centre's
/// 18-neighbourhood that touch the centre by a face.
int backgroundPieces6(std::uint32_t bits);

}  // namespace skelseg

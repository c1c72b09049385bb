// skelseg: tunnels up to two voxels wide, plugged in a volume before its
// skeleton is computed (docs/algorithm.md §1, "Tunnels up to two voxels
// wide").
//
// kernels/NarrowTunnels.h closes the tunnels one voxel wide that surface
// noise makes; heavier noise (several per cent of the voxels near the
// surface flipped) also makes tunnels two voxels across, where no single
// voxel closes anything and so that test finds nothing. This is the
// homotopic closing of digital topology, restricted to what plugs a tunnel:
//
// 1. Y = the object plus every background voxel within one voxel of it
//    (26-neighbours, the grid's outermost layer excepted). Every passage of
//    the background at most two voxels wide is filled in Y.
// 2. The added voxels are taken away again while that changes no topology
//    (they are simple points for (26, 6) connectivity: their object
//    neighbours are one 26-connected piece, T26 = 1, and their background
//    neighbours within the 18-neighbourhood are one 6-connected piece
//    touching them by a face, T6 = 1), farthest from the object first, ties
//    by index. Grooves, bumps and wide holes empty completely; what stays is
//    where taking a voxel away would change Y's topology.
// 3. Of those, a voxel whose object neighbours fall into two or more pieces
//    (T26 != 1) bridges two places of the object that are apart (two limbs
//    within two voxels of each other): it is taken away too, and step 2
//    goes on. What is left are plugs: voxels with T26 = 1 whose removal
//    would open a passage of the background (T6 != 1), the "closes a
//    tunnel" test of NarrowTunnels.h, each in the configuration of its plug.
//
// So the object never gains a handle or a new piece from this, and loses
// every tunnel at most two voxels wide; a chamber whose opening is at most
// two voxels wide is sealed there (the caller fills it as a cavity), and a
// real handle two voxels wide is closed too: in a volume there is no mesh to
// tell it from noise.
#pragma once

#include <cstddef>
#include <vector>

#include "kernels/base/Interrupter.h"
#include "kernels/base/Volume.h"

namespace skelseg {

/// Plugs every tunnel of `mask`'s objects at most two voxels wide (see
/// above) and returns the linear indices of the voxels set, ascending.
/// Voxels on the outermost layer of the grid are never set. Serial: the
/// result depends on the order in which voxels are taken away, which is
/// fixed (distance to the object, then index). @throw InterruptedError when
/// asked to stop (`mask` is then left unchanged).
std::vector<std::size_t> plugTunnelsTwoVoxelsWide(MaskVolume& mask,
                                                  Interrupter& interrupter = nullInterrupter());

}  // namespace skelseg

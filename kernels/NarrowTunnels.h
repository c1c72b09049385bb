// skelseg: tunnels one voxel wide, closed in a volume before its skeleton is
// computed (docs/algorithm.md §1, "Tunnels one voxel wide").
//
// Surface noise in a thresholded volume (voxels added or missing within a
// few voxels of the surface) makes tunnels: a voxel that touches the
// surface at two places by an edge or a corner bridges the background
// under it. Each is a handle of the object, and a loop round a handle has no
// area it cuts off (docs/algorithm.md §5.4), so such loops stay in the
// simplified skeleton and hide the junctions: a figure of five parts with
// 3% of the voxels within three voxels of its body's surface flipped had
// genus 114 and gave 4 parts. A volume has no mesh to tell a real handle
// from such a tunnel (a mesh's voxel model is checked against the mesh's
// genus instead, docs/meshes.md); what is certain is that a tunnel one
// voxel wide is below what the voxels resolve, so those are closed.
//
// The test is the digital topology of (26, 6) connectivity (objects
// 26-connected, background 6-connected): a background voxel p whose object
// neighbours are one 26-connected piece (T26 = 1) and whose background
// neighbours within its 18-neighbourhood fall into two or more 6-connected
// pieces that touch p by a face (T6 >= 2) is the only passage of the
// background through it: setting p closes a tunnel (or seals a cavity,
// which the caller fills) and joins no two pieces of the object. A groove,
// a pit or a hole wider than one voxel has no such voxel. Voxels are taken
// in scan order, each judged on the mask as the voxels before it left it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "kernels/base/Interrupter.h"
#include "kernels/base/Volume.h"

namespace skelseg {

/// Sets, in scan order, every background voxel of `mask` that closes a
/// tunnel one voxel wide (see above) and returns their linear indices, in
/// that order. Voxels on the outermost layer of the grid are never set.
/// Serial (one pass; its result depends on the order). @throw
/// InterruptedError when asked to stop (`mask` is then left unchanged).
std::vector<std::size_t> closeNarrowTunnels(MaskVolume& mask,
                                            Interrupter& interrupter = nullInterrupter());

/// Whether setting background voxel (x, y, z) of `mask`, not on its
/// outermost layer, closes a tunnel one voxel wide (T26 = 1 and T6 >= 2).
bool closesNarrowTunnel(const MaskVolume& mask, int x, int y, int z);

}  // namespace skelseg

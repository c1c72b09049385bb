// A closed mesh that passes through itself, as an animated limb sunk into
// the body does: a tapering tube wound around a circle by more than one
// turn, so that its end runs inside its beginning. One piece, consistently
// oriented, genus 0; the voxel model fuses its two ends into a ring unless
// the self-overlap is separated (io/mesh/SelfOverlapSeparation.h).
#pragma once

#include <array>

#include "io/mesh/MeshIO.h"

namespace skelseg::test {

struct CurledTube {
    double bendRadius = 1.0;           // radius of the circle the axis follows
    double startRadius = 0.4;          // tube radius at the beginning of the axis
    double endRadius = 0.15;           // tube radius at its end (linear in between)
    double tipLength = 0.3;            // length of the rounded tips along the axis
    double extraAngle = 1.2;           // radians wound beyond one full turn
    int alongAxis = 160, around = 24;  // mesh rings and ring vertices

    /// Tube radius at the point of the axis that lies `angle` radians along
    /// it (0 to 2 pi + extraAngle), with the rounded tips of the mesh.
    double radiusAt(double angle) const;
    /// Tube radius at distance x along the straight axis.
    double profile(double x) const;
    /// The mesh: a tube with rounded tips along a straight axis, bent onto
    /// the circle (x, y, z) -> ((R + y) cos(x / R),
    /// (R + y) sin(x / R), z).
    TriangleMesh mesh() const;
    /// Whether `point` lies inside the tube at axis angle `angle` (grown by
    /// `slack`).
    bool insideAt(const std::array<double, 3>& point, double angle, double slack) const;
};

/// A UV sphere (one closed piece, outward triangles).
TriangleMesh sphereMesh(const std::array<double, 3>& centre, double radius, int rings = 24,
                        int around = 32);

}  // namespace skelseg::test

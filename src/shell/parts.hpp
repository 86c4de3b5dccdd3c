#pragma once
// One part for the slicer: the pattern can cut loose specks (a sliver of wall between three holes) and
// seal voids inside the wall (an inward-facing closed sheet); a slicer lists each as its own part. They
// are removed here; parts of comparable size (two input bodies) are all kept.

#include <cstdint>
#include <vector>

#include "geometry/mesh.hpp"

namespace poreshell {

struct PartsSummary {
  std::int64_t parts = 0;               // connected components kept (outward, positive volume)
  std::int64_t removed_fragments = 0;   // outward components below the threshold
  std::int64_t removed_voids = 0;       // inward components (sealed cavities) below the threshold
  double removed_volume = 0.0;          // sum of |volume| removed, in the mesh's units cubed
  double largest_removed_volume = 0.0;  // the largest |volume| removed
  // Each removed void's Euler characteristic and a point in it (its vertices' centroid: the voids
  // are small), for telling the voids the wall has without pores from those the pores made.
  struct Void {
    Vec3 inside = Vec3::Zero();
    std::int64_t euler_characteristic = 0;
  };
  std::vector<Void> voids;
  std::int64_t removed_wall_voids = 0;  // of them, the wall's without pores as well (wall_voids_euler)
  // Sealed cavities at or above the threshold filled (fill_cavities): pockets of the model's inside that
  // no pore opens (the inside of a hollow tail pinched off from the body's), which trap resin or powder.
  std::int64_t filled_cavities = 0;
  double filled_volume = 0.0, largest_filled_volume = 0.0;  // |volume|, the mesh's units cubed
};

// Removes every connected component whose |volume| is below `min_fraction` times the largest
// component's volume; returns what was kept and removed. With `fill_cavities`, every inward component
// (a sealed cavity) goes whatever its size: removing its sheet fills it with solid. Without, cavities at
// or above the threshold are kept (the inside of a shell without pores is the shell's own). Components
// are connected through shared vertices; the mesh must be closed and consistently oriented.
PartsSummary keep_main_parts(TriangleMesh& mesh, double min_fraction, bool fill_cavities = false);

}  // namespace poreshell

#pragma once
// The paper's route's result as a Surface: signed distances sampled on the grid's lattice, with the
// distance to their zero level off the lattice.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/grid.hpp"
#include "geometry/mesh.hpp"
#include "geometry/mesh_surface.hpp"
#include "geometry/point_tree.hpp"
#include "geometry/surface.hpp"

namespace poreshell {

// The discrete signed distance: samples on the lattice x = origin + h (i, j, k), which holds the paper's
// grid's points, so the band there reads psi and takes closest points from the paper's formula. Off the
// lattice (block centres, the fast solver's coarse grids) and beyond the samples: the unsigned distance
// to the zero level, as the mesh route gives, 1-Lipschitz. Without a zero level: trilinear between
// samples, and beyond them a lower bound of |distance| (distance to the points minus the zero level's
// largest gap to them), so the band builder's block culling stays safe.
class SampledLevelSet final : public Surface {
 public:
  SampledLevelSet(const Grid& lattice, std::vector<std::int64_t> keys, std::vector<double> values,
                  std::vector<Vec3> points, double gap, const TriangleMesh* zero_level = nullptr);

  double distance(const Vec3& p) const override;
  // Nothing (the band uses the paper's formula) at lattice points where the central-difference gradient
  // has unit length within 10%, i.e. where the samples are a distance function. Elsewhere (the kink of
  // the distance on the mid-surface of parts thinner than the band, where |grad psi| -> 0 sends the
  // formula's cp far away; points off the lattice) the exact closest point on the zero level.
  std::optional<Vec3> closest_point(const Vec3& p) const override;
  Box bounds() const override;
  std::string name() const override { return "segmented point cloud"; }

  const Grid& lattice() const { return lattice_; }
  std::size_t samples() const { return keys_.size(); }
  // The sample at lattice point c, if there is one.
  std::optional<double> sample(const Coord& c) const;

 private:
  Grid lattice_;
  std::vector<std::int64_t> keys_;  // ascending lattice keys
  std::vector<double> values_;
  std::vector<Vec3> points_;
  PointTree tree_;
  double gap_;
  std::unique_ptr<MeshSurface> zero_level_;
};

}  // namespace poreshell

#pragma once
// What every surface source answers: distance and closest point at a point. Analytic shapes,
// triangle meshes and point clouds all implement this; the band builder only sees this interface.

#include <memory>
#include <optional>
#include <string>

#include "core/types.hpp"

namespace poreshell {

struct SurfaceQuery {
  double distance = 0.0;
  std::optional<Vec3> closest_point;
};

class Surface {
 public:
  virtual ~Surface() = default;

  // Distance to the surface, signed (negative inside) where the surface has an inside.
  // Must be 1-Lipschitz: the band builder skips whole blocks of the grid on that bound.
  virtual double distance(const Vec3& p) const = 0;

  // Exact closest point on the surface, where the source can give one. Sources that cannot
  // (a sampled level set) return nothing, and the band uses the paper's gradient formula.
  virtual std::optional<Vec3> closest_point(const Vec3& p) const = 0;

  // Whether a closest point given is the exact one, so that |distance(p)| == |p - closest_point(p)|
  // up to rounding: one query then gives both. Not for a sampled level set, whose distance is its
  // samples', not that of its closest points.
  virtual bool closest_point_is_exact() const { return false; }

  // distance(p) and closest_point(p) together, bit for bit the same values; sources whose two answers
  // come from one search (a mesh's tree) override it to search once.
  virtual SurfaceQuery distance_and_closest_point(const Vec3& p) const {
    return {distance(p), closest_point(p)};
  }

  // distance_and_closest_point(p), given a point on the surface near p (the last query's closest point,
  // in a scan of neighbouring points): the nearest is no further than it, which can only shorten the
  // search. The same distance; at an exact tie between two closest points either may be returned.
  virtual SurfaceQuery distance_and_closest_point_near(const Vec3& p, const Vec3& on_surface) const {
    static_cast<void>(on_surface);
    return distance_and_closest_point(p);
  }

  // distance(p) where |distance(p)| <= bound, else any value beyond the bound on the same side: what
  // deciding "out of reach" needs. Sources whose search can stop at the bound (a mesh's tree) override it.
  virtual double distance_up_to(const Vec3& p, double bound) const {
    static_cast<void>(bound);
    return distance(p);
  }

  // A box that holds the whole surface.
  virtual Box bounds() const = 0;

  virtual std::string name() const = 0;
};

// Sphere of eq. (3.1): |x - c| - r.
class Sphere final : public Surface {
 public:
  Sphere(const Vec3& center, double radius);
  double distance(const Vec3& p) const override;
  std::optional<Vec3> closest_point(const Vec3& p) const override;
  bool closest_point_is_exact() const override { return true; }
  Box bounds() const override;
  std::string name() const override { return "sphere"; }

 private:
  Vec3 center_;
  double radius_;
};

// Torus of section 3.2: sqrt((sqrt((x-cx)^2 + (y-cy)^2) - R)^2 + (z-cz)^2) - r, axis along z.
class Torus final : public Surface {
 public:
  Torus(const Vec3& center, double major_radius, double minor_radius);
  double distance(const Vec3& p) const override;
  std::optional<Vec3> closest_point(const Vec3& p) const override;
  bool closest_point_is_exact() const override { return true; }
  Box bounds() const override;
  std::string name() const override { return "torus"; }

 private:
  Vec3 center_;
  double major_, minor_;
};

// The shapes of section 3.2 on the unit cube [0,1]^3: sphere r = 0.3, torus R = 0.3, r = 0.15.
inline constexpr double kPaperShapeRadius = 0.3;  // the sphere's radius, the torus's major radius
std::unique_ptr<Surface> make_paper_shape(const std::string& name);

}  // namespace poreshell

#include "solver/initial_condition.hpp"

#include <tbb/parallel_for.h>

#include "core/splitmix.hpp"

namespace poreshell {

double uniform_noise(std::uint64_t seed, std::int64_t key) {
  const std::uint64_t bits = splitmix64(splitmix64(seed) ^ static_cast<std::uint64_t>(key));
  return static_cast<double>(bits >> 11) * 0x1.0p-52 - 1.0;  // 53 random bits onto [-1, 1)
}

std::vector<double> random_initial_condition(const NarrowBand& band, double phi_bar, double amplitude,
                                             std::uint64_t seed) {
  std::vector<double> phi(band.size());
  const auto voxels = band.voxels();
  tbb::parallel_for(std::size_t{0}, phi.size(), [&](std::size_t v) {
    phi[v] = phi_bar + amplitude * uniform_noise(seed, band.grid().key(voxels[v]));
  });
  return phi;
}

std::vector<double> sampled_initial_condition(const NarrowBand& band,
                                              const std::function<double(const Vec3&)>& f) {
  std::vector<double> phi(band.size());
  const auto voxels = band.voxels();
  tbb::parallel_for(std::size_t{0}, phi.size(),
                    [&](std::size_t v) { phi[v] = f(band.grid().position(voxels[v])); });
  return phi;
}

}  // namespace poreshell

#pragma once
// Initial conditions on the band. Random values come from a hash of (seed, grid key), so they do
// not depend on the band's order or on the thread count.

#include <cstdint>
#include <functional>
#include <vector>

#include "band/band.hpp"

namespace poreshell {

// Uniform in [-1, 1], a pure function of (seed, key).
double uniform_noise(std::uint64_t seed, std::int64_t key);

// phi_bar + amplitude * rand, rand uniform in [-1, 1] (the paper's -0.3 + 0.5 rand(x, y, z)).
std::vector<double> random_initial_condition(const NarrowBand& band, double phi_bar, double amplitude,
                                             std::uint64_t seed);

// f(x) at every band voxel.
std::vector<double> sampled_initial_condition(const NarrowBand& band,
                                              const std::function<double(const Vec3&)>& f);

}  // namespace poreshell

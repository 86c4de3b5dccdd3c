#include "poreshell/pattern.hpp"

#include <algorithm>
#include <cmath>

namespace poreshell {

std::vector<std::int32_t> label_spots(const NarrowBand& band, std::span<const double> phi, double level) {
  const std::size_t n = band.size();
  std::vector<std::int32_t> label(n, -1);
  std::vector<std::size_t> stack;
  std::int32_t next = 0;
  for (std::size_t seed = 0; seed < n; ++seed) {
    if (label[seed] >= 0 || !(phi[seed] > level)) continue;
    label[seed] = next;
    stack.push_back(seed);
    while (!stack.empty()) {
      const std::size_t v = stack.back();
      stack.pop_back();
      for (int k = 0; k < NarrowBand::kNeighbors; ++k) {
        const auto nb = static_cast<std::size_t>(band.neighbor(v, k));
        if (nb < n && label[nb] < 0 && phi[nb] > level) {
          label[nb] = next;
          stack.push_back(nb);
        }
      }
    }
    ++next;
  }
  return label;
}

SpotStats spot_statistics(const NarrowBand& band, std::span<const double> phi, double level) {
  const std::vector<std::int32_t> label = label_spots(band, phi, level);
  SpotStats s;
  std::int64_t inside = 0;
  for (std::int32_t l : label) {
    if (l < 0) continue;
    if (static_cast<std::size_t>(l) >= s.sizes.size()) s.sizes.resize(static_cast<std::size_t>(l) + 1, 0);
    ++s.sizes[static_cast<std::size_t>(l)];
    ++inside;
  }
  s.count = static_cast<std::int64_t>(s.sizes.size());
  s.area_fraction = band.size() ? static_cast<double>(inside) / static_cast<double>(band.size()) : 0.0;
  if (s.count == 0) return s;
  double sum = 0.0, sum2 = 0.0;
  for (auto z : s.sizes) {
    sum += static_cast<double>(z);
    sum2 += static_cast<double>(z) * static_cast<double>(z);
  }
  s.mean_size = sum / static_cast<double>(s.count);
  const double var = std::max(0.0, sum2 / static_cast<double>(s.count) - s.mean_size * s.mean_size);
  s.size_cv = std::sqrt(var) / s.mean_size;
  return s;
}

}  // namespace poreshell

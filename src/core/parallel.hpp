#pragma once
// Reductions whose result does not depend on the thread count: a fixed split of the range and a
// fixed order of joining (oneTBB's deterministic reduce with a simple partitioner).

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/partitioner.h>

#include <algorithm>
#include <cstddef>

#include "core/run_monitor.hpp"

namespace poreshell {

inline constexpr std::size_t kReduceGrain = 4096;

template <class Term>
double deterministic_sum(std::size_t n, const Term& term) {
  return tbb::parallel_deterministic_reduce(
      tbb::blocked_range<std::size_t>(0, n, kReduceGrain), 0.0,
      [&](const tbb::blocked_range<std::size_t>& r, double acc) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) acc += term(i);
        return acc;
      },
      [](double a, double b) { return a + b; }, tbb::simple_partitioner());
}

template <class Term>
double parallel_max(std::size_t n, const Term& term) {
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, n, kReduceGrain), 0.0,
      [&](const tbb::blocked_range<std::size_t>& r, double acc) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) acc = std::max(acc, term(i));
        return acc;
      },
      [](double a, double b) { return std::max(a, b); });
}

// tbb::parallel_for over [0, n) for a loop that takes long: in about 256 to 512 pieces, each checking
// the cancel flag before it and reporting the share done after it. For bodies that write only their own
// item's results (the order of the pieces is free).
template <class Body>
void monitored_for(std::size_t n, const StageProgress& progress, const Body& body) {
  LoopProgress loop(progress, n);
  const std::size_t grain = std::max<std::size_t>(1, n / 256);
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, n, grain),
      [&](const tbb::blocked_range<std::size_t>& r) {
        progress.check();
        for (std::size_t i = r.begin(); i != r.end(); ++i) body(i);
        loop.done(r.size());
      },
      tbb::simple_partitioner());
}

}  // namespace poreshell

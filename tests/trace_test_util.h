// Helpers of the tests that compare tracers' hits (gpu_tracer_test.cpp, gpu_alpha_test.cpp).
#pragma once

#include <cstring>
#include <vector>

#include "core/ray.h"
#include "tracers/tracer.h"

namespace raycoh::test {

// The hits of rays (in `order` when given, through trace_indirect) from tracer t.
inline std::vector<Hit> trace_with(Tracer& t, const std::vector<Ray>& rays,
                                   const std::vector<uint32_t>* order = nullptr) {
  std::vector<Hit> hits(order ? order->size() : rays.size());
  if (order)
    t.trace_indirect(rays.data(), order->data(), order->size(), hits.data());
  else
    t.trace(rays.data(), rays.size(), hits.data());
  return hits;
}

// How many hits differ in any byte.
inline size_t differing_hits(const std::vector<Hit>& a, const std::vector<Hit>& b) {
  size_t differ = 0;
  for (size_t i = 0; i < a.size(); ++i) differ += std::memcmp(&a[i], &b[i], sizeof(Hit)) != 0;
  return differ;
}

}  // namespace raycoh::test

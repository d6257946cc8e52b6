// The timed reordering step of one frame (see reorder.h).
#include "encoders/reorder.h"

#include <chrono>
#include <numeric>

namespace raycoh {
namespace {

double ms_between(std::chrono::steady_clock::time_point a, std::chrono::steady_clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

}  // namespace

bool reorder(Encoder& encoder, const RayBatch& in, PermuteMode mode, RayBatch& out, std::vector<uint32_t>& order,
             ReorderTimings& timings) {
  timings = {};
  if (encoder.key_bits() == 0) {
    order.clear();
    return false;
  }
  const size_t n = in.size();
  ReorderWorkspace& ws = encoder.workspace();
  ws.keys.resize(n);
  order.resize(n);
  ws.sort.reserve(n);
  if (mode == PermuteMode::Physical) out.resize(n);

  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  encoder.encode(in, ws.keys.data());
  const auto t1 = Clock::now();
  std::iota(order.begin(), order.end(), 0u);
  radix_sort_pairs(ws.keys, order, encoder.key_bits(), ws.sort);
  const auto t2 = Clock::now();
  if (mode == PermuteMode::Physical) permute_batch(in, order, out);
  const auto t3 = Clock::now();

  timings.key_ms = ms_between(t0, t1);
  timings.sort_ms = ms_between(t1, t2);
  timings.permute_ms = mode == PermuteMode::Physical ? ms_between(t2, t3) : 0.0;
  return true;
}

}  // namespace raycoh

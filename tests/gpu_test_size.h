// How large the `gpu` tests run. RAYCOH_GPU_TEST_SIZE=sim (scripts/gpgpusim-test sets it) shrinks images, batches
// and value sweeps so that the whole GPU suite runs under GPGPU-Sim's functional mode (about 1 M
// thread-instructions/s on one core) in minutes; the assertions stay the same. Unset, empty or "full": the sizes
// for a real GPU. Any other value is an error (a typo must not silently run the full size for an hour).
#pragma once

#include <cstdlib>
#include <stdexcept>
#include <string>

namespace raycoh::test {

inline bool gpu_test_sim_size() {
  const char* env = std::getenv("RAYCOH_GPU_TEST_SIZE");
  const std::string v = env ? env : "";
  if (v.empty() || v == "full") return false;
  if (v == "sim") return true;
  throw std::invalid_argument("RAYCOH_GPU_TEST_SIZE='" + v + "': expected 'full' or 'sim'");
}

// full on a GPU, sim at the simulator size.
template <class T>
T gpu_test_size(T full, T sim) {
  return gpu_test_sim_size() ? sim : full;
}

}  // namespace raycoh::test

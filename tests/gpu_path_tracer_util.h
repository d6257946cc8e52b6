// What the device path tracer's gpu tests share (tests/gpu_path_tracer_test.cpp: first bounce, stage times and
// same-seed frames bit for bit; tests/gpu_path_tracer_images_test.cpp: whole images within their noise): the
// render settings at the test's size, and the device's copy of them (the bitwise count of differing elements is
// test::differing, tests/test_util.h). RAYCOH_GPU_TEST_SIZE=sim: 16x16 pixels, paths of 3 scattering events, Russian
// roulette from the second.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <vector>

#include "cuda/device_path_tracer.h"
#include "shading/path_tracer.h"
#include "tests/gpu_test_size.h"
#include "tests/test_util.h"

namespace raycoh::test {

// The settings at the simulator size (sim) or the full size; by default the size the test runs at.
inline RenderSettings path_settings(uint32_t seed, bool sim = gpu_test_sim_size()) {
  RenderSettings rs;
  rs.width = sim ? 16 : 64;
  rs.height = sim ? 16 : 48;
  rs.seed = seed;
  rs.max_depth = sim ? 3 : 5;
  rs.rr_depth = sim ? 2 : 3;
  return rs;
}

inline cuda::DevicePathSettings device_settings(const RenderSettings& rs) {
  return {rs.width, rs.height, rs.seed, rs.max_depth, rs.rr_depth};
}

}  // namespace raycoh::test

// `raycoh render --device cuda` (render_device.h).
#include "harness/image/render_device.h"

#include <fmt/format.h>

#include <cctype>
#include <vector>

#include "core/error.h"
#include "shading/emitters.h"
#if defined(RAYCOH_HAVE_CUDA)
#include "cuda/cuda_device.h"
#include "cuda/device_path_tracer.h"
#endif

namespace raycoh {

DeviceRenderTotals render_on_device(const LoadedScene& ls, const Generator& generator, const RenderSettings& rs,
                                    int frames, Accumulator& acc, const std::function<void(int)>& progress) {
#if defined(RAYCOH_HAVE_CUDA)
  if (cuda::device_count() == 0) throw Error("--device cuda: no CUDA device (this machine has no usable GPU)");
  DeviceRenderTotals totals;
  totals.device = cuda::device_name();
  std::string lower = totals.device;
  for (char& ch : lower) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  totals.clock = lower.find("gpgpu") != std::string::npos ? "simulated" : "measured";
  const EmitterDistribution lights(ls.scene);
  const cuda::DevicePathSettings ds{rs.width, rs.height, rs.seed, rs.max_depth, rs.rr_depth};
  cuda::DevicePathTracer device(ls.scene, ls.bvh, lights.view(ls.scene), generator, ds);
  std::vector<Vec3> radiance;
  for (int f = 0; f < frames; ++f) {
    const cuda::DeviceFrameStats s = device.render_frame(static_cast<uint32_t>(f), radiance);
    totals.gpu_ms += s.frame_ms;
    totals.rays += s.rays.primary + s.rays.secondary + s.rays.bounce + s.rays.shadow;
    for (size_t p = 0; p < radiance.size(); ++p) acc.add(p, radiance[p]);
    progress(f);
  }
  return totals;
#else
  (void)ls, (void)generator, (void)rs, (void)frames, (void)acc, (void)progress;
  throw Error("--device cuda: this build has no CUDA (configure with nvcc found, RAYCOH_CUDA=ON)");
#endif
}

}  // namespace raycoh

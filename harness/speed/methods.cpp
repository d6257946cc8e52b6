// The method list of an experiment (harness/speed/experiment.h): `auto` tracers expanded to what this machine has,
// the NoOpt baseline the ratios divide by, and the generator x encoder product in generator-major order.
#include <cstdio>

#include "core/error.h"
#include "harness/speed/experiment.h"
#if defined(RAYCOH_HAVE_CUDA)
#include "cuda/cuda_device.h"
#endif

namespace raycoh {

std::vector<PluginSpec> expand_auto(const std::vector<PluginSpec>& tracers) {
  std::vector<PluginSpec> out;
  for (const PluginSpec& t : tracers) {
    if (t.name != "auto") {
      out.push_back(t);
      continue;
    }
    if (!t.params.empty()) throw Error("tracer 'auto' takes no parameters");
#if defined(RAYCOH_HAVE_CUDA)
    if (cuda::device_count() > 0) {
      out.push_back({"cuda", ""});
      continue;
    }
#endif
    out.push_back({"cpu", ""});
    out.push_back({"simt", ""});
  }
  return out;
}

void ensure_baseline(std::vector<Method>& methods) {
  for (const Method& m : methods)
    if (m.label == "noopt") return;
  methods.insert(methods.begin(), Method{"noopt", {"noopt", ""}});
  std::fprintf(stderr, "adding generator noopt as the baseline of the ratios\n");
}

std::vector<Method> method_product(const std::vector<PluginSpec>& generators, const std::vector<PluginSpec>& encoders) {
  std::vector<Method> methods;
  for (const PluginSpec& g : generators)  // generator-major, so methods sharing a batch are adjacent
    for (const PluginSpec& e : encoders)
      methods.push_back({e.name == "none" ? g.text() : g.text() + "+" + e.text(), g, e});
  return methods;
}

}  // namespace raycoh

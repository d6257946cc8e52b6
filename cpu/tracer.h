// The tracer interface: one virtual call per batch, never per ray. A tracer is made for one scene (it may build
// acceleration structures of its own in the constructor, which is not part of the timed trace) and then traces
// any number of batches of closest-hit rays.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "core/params.h"
#include "core/ray.h"

namespace raycoh {

struct Scene;
struct Bvh;

class Tracer {
 public:
  virtual ~Tracer() = default;
  // Closest hit of rays[i] into hits[i], for all i < count. Not timed inside: the caller times this call.
  virtual void trace(const Ray* rays, size_t count, Hit* hits) = 0;
  // Canonical, defaulted parameter set ("mode=single").
  virtual std::string params() const = 0;
};

struct TracerInfo {
  std::string name;
  std::string summary;  // one line for `raycoh list`
  std::string params;   // "mode=single|packet16|stream_coherent|stream_incoherent (default single)"
};

// The explicit registry (adding a tracer = one file + one line in tracer_registry.cpp).
const std::vector<TracerInfo>& tracer_infos();
// Throws raycoh::Error for unknown names or bad parameters, naming the valid choices.
std::unique_ptr<Tracer> make_tracer(const PluginSpec& spec, const Scene& scene, const Bvh& bvh);

}  // namespace raycoh

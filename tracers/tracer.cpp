#include "tracers/tracer.h"

#include <vector>

namespace raycoh {

void Tracer::trace_indirect(const Ray* rays, const uint32_t* order, size_t count, Hit* hits) {
  std::vector<Ray> gathered(count);
  for (size_t i = 0; i < count; ++i) gathered[i] = rays[order[i]];
  trace(gathered.data(), count, hits);
}

}  // namespace raycoh

// FlushDenormalsScope: the floating-point mode every CPU tracing thread runs in (host only, x86-64 SSE).
#pragma once

namespace raycoh {

// Sets the flush-to-zero and denormals-are-zero modes of the calling thread for its lifetime and restores the
// previous modes afterwards. Embree requires FTZ/DAZ in tracing threads for speed; our own tracer uses it too
// so that both are timed under the same floating-point mode. Restoring matters because TBB worker threads are
// shared with other stages (generators, encoders) whose results must not depend on which thread ran them.
class FlushDenormalsScope {
 public:
  FlushDenormalsScope();
  ~FlushDenormalsScope();
  FlushDenormalsScope(const FlushDenormalsScope&) = delete;
  FlushDenormalsScope& operator=(const FlushDenormalsScope&) = delete;

 private:
  unsigned int saved_csr_;
};

}  // namespace raycoh

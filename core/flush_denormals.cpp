// FlushDenormalsScope; see flush_denormals.h.
#include "core/flush_denormals.h"

#include <pmmintrin.h>
#include <xmmintrin.h>

namespace raycoh {

FlushDenormalsScope::FlushDenormalsScope() : saved_csr_(_mm_getcsr()) {
  _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
  _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
}

FlushDenormalsScope::~FlushDenormalsScope() { _mm_setcsr(saved_csr_); }

}  // namespace raycoh

// Window: local reordering inside windows of W consecutive rays, the way hardware reordering works (NVIDIA's
// Shader Execution Reordering, Intel's thread sorting unit, the coherence engine of Vulkan-Sim) rather than by a
// global sort. Each ray gets a short bin, `bits` bits of a key: the direction octant (key=octant, 3 bits), or the
// top `bits` bits of another encoder's 64-bit code with that encoder's defaults (key=origin: the origin's cell in
// a 2^bits-cell Morton grid; reis, costa, aila, twopoint, mlhcc likewise). Rays are then ordered by bin inside
// their window, stably, and windows stay in the generator's order: a ray never leaves its window.
//
// The stage is an encoder so that it runs where every reordering runs: its 32-bit key is (window index << bits)
// | bin, so the stable radix sort of encoders/reorder.h computes exactly the per-window stable binning, and W = 1
// leaves every ray in place (the same order as `none`). The measured CPU times are those of this emulation
// (a global sort of the composite keys). On the `simt` GPU model the stage costs what a software windowed sort
// kernel would: one read and one write of the batch, DRAM-bound, and no separate key, sort or permutation pass
// (harness/speed/experiment.cpp, model_stages; an assumption of ours: no published cost of SER's reordering exists,
// and the hardware unit works on chip, so this is an upper bound of its cost).
//
// Parameters: window_params() below. The GPU key kernels (cuda/device_keys.cu) do not build window keys: its
// recipe is that of `none`, and GPU keys are not part of a `table` run.
#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/error.h"
#include "encoders/key_encoder.h"

namespace raycoh {
namespace {

class WindowEncoder final : public Encoder {
 public:
  WindowEncoder(const Bounds& box, std::unique_ptr<Encoder> inner, int window, int bits, std::string params)
      : Encoder("window", box), inner_(std::move(inner)), window_(window), bits_(bits), params_(std::move(params)) {}

  void encode(const RayBatch& batch, uint64_t* keys) const override {
    const size_t n = batch.size();
    if (n == 0) return;
    const uint64_t windows = (n - 1) / static_cast<uint64_t>(window_) + 1;
    if (windows > (uint64_t{1} << (32 - bits_)))
      throw Error(fmt::format("encoder 'window': {} windows of W={} rays need more than {} bits beside the {} bin bits",
                              windows, window_, 32 - bits_, bits_));
    if (inner_) inner_->encode(batch, keys);  // 64-bit codes
    const Ray* rays = batch.rays.data();
    const int shift = 64 - bits_;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i < r.end(); ++i) {
        uint64_t bin;
        if (inner_) {
          bin = keys[i] >> shift;
        } else {
          const Vec3 d = rays[i].dir;
          bin = (d.x < 0.f ? 1u : 0u) | (d.y < 0.f ? 2u : 0u) | (d.z < 0.f ? 4u : 0u);
        }
        keys[i] = ((i / static_cast<uint64_t>(window_)) << bits_) | bin;
      }
    });
  }
  int key_bits() const override { return 32; }
  std::string params() const override { return params_; }
  KeyRecipe recipe() const override {
    KeyRecipe r;
    r.box = box();
    return r;
  }
  int window() const override { return window_; }

 private:
  std::unique_ptr<Encoder> inner_;
  int window_, bits_;
  std::string params_;
};

}  // namespace

const ParamTable& window_params() {
  static const ParamTable table = {
      int_param("W", 1024, 1, 1 << 24, "rays per window (1: no reordering)"),
      choice_param("key", "origin", {"octant", "origin", "reis", "costa", "aila", "twopoint", "mlhcc"},
                   "what rays are binned by: the direction octant, or the top bits of that encoder's code"),
      int_param("bits", 8, 1, 16, "bin bits taken from the key's code (octant: always 3)"),
  };
  return table;
}

std::unique_ptr<Encoder> make_window_encoder(ParamSet& params, const EncoderContext& context) {
  const int window = params.get_int("W");
  const std::string key = params.get_choice("key");
  int bits = params.get_int("bits");
  const std::string canonical = finish_encoder_params(params, context.bounds);
  std::unique_ptr<Encoder> inner;
  if (key == "octant")
    bits = 3;
  else
    inner = make_encoder(PluginSpec{key, "bits=64"}, context);
  return std::make_unique<WindowEncoder>(context.bounds, std::move(inner), window, bits, canonical);
}

}  // namespace raycoh

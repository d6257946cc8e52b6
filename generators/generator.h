// The generator interface: G-buffer of first hits + frame seed -> secondary ray batch. One virtual call per
// frame, never per ray. Adding a generator = one file + one line in generators/registry.cpp.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/bsdf.h"
#include "core/params.h"
#include "core/plugin.h"
#include "core/ray_batch.h"
#include "generators/grouping.h"
#include "scenes/scene.h"

namespace raycoh {

// What decides a batch's layout, as a generator holds it: tile, group size K and batch order; empty where the
// generator has no such parameter. The typed source of a row's tile_w, tile_h, k and order columns
// (plugins/recorded_params.h).
struct BatchLayout {
  std::optional<int> tile_w, tile_h, k;
  std::string order;
};

class Generator {
 public:
  virtual ~Generator() = default;
  // Writes one ray per hit pixel of gbuffer into out (resized), in the generator's batch order.
  virtual void generate(const Scene& scene, const GBuffer& gbuffer, uint32_t seed, RayBatch& out,
                        GenerationStats& stats) = 0;
  // Canonical, defaulted parameter set ("order=tile,tile=8x8").
  virtual std::string params() const = 0;
  // The typed configuration a device version runs (generators/grouping.h); kind None where there is none.
  virtual DeviceRecipe device_recipe() const { return {}; }
  // Its batch layout, typed; nullopt where the generator does not give it (its recorded columns are then read
  // from params() through its parameter table).
  virtual std::optional<BatchLayout> layout() const { return std::nullopt; }
};

// Reads its values from a ParamSet over the record's table; throws raycoh::Error for bad ones.
using GeneratorFactory = std::unique_ptr<Generator> (*)(ParamSet& params);
using GeneratorInfo = PluginInfo<GeneratorFactory>;

const std::vector<GeneratorInfo>& generator_infos();
// Throws raycoh::Error for unknown names or bad parameters, naming the valid choices.
std::unique_ptr<Generator> make_generator(const PluginSpec& spec);
// The registered name a generator name stands for: `tile` is the old name of `contiguous` (kept so that existing
// command lines and CSV files still read); every other name is itself.
std::string generator_name(const std::string& name);
// The row `param` of a registered generator's parameter table, or null where it has none or the name is unknown.
const ParamSpec* generator_param_row(const std::string& name, const std::string& param);
// The group size row `k` of a registered generator's parameter table (ours, contiguous: generators that group a
// tile's pixels), or null for a generator that does not group or an unknown name.
const ParamSpec* group_size_row(const std::string& name);

// The `tile` of the generators that work per tile (ours, contiguous, direct) and of `sweep --tiles`, one rule: each
// side in [1, kMaxTileSide], at most kMaxTilePixels pixels (generators/common.cpp).
constexpr int kMaxTileSide = 1024;
constexpr int kMaxTilePixels = 65536;
// The parameter table's `tile` row with those sides; `what` says what the tile is to the generator.
ParamSpec tile_param(std::pair<int, int> def, const std::string& what);
// Throws raycoh::Error "<owner>: tile=WxH ..." naming the limits when a side or the area is beyond them.
void check_tile(const std::string& owner, std::pair<int, int> tile);

// Helpers shared by generators (generators/common.cpp).
BsdfParams bsdf_params(const Material& m);
// The BSDF parameters a G-buffer's points index (ShadingPoint::material): its own table, or for a G-buffer
// without one (built by hand) the scene's materials.
class MaterialTable {
 public:
  MaterialTable(const Scene& scene, const GBuffer& gbuffer);
  const BsdfParams& operator[](uint32_t material) const { return data_[material]; }
  const BsdfParams* data() const { return data_; }
  size_t size() const { return size_; }

 private:
  std::vector<BsdfParams> own_;
  const BsdfParams* data_ = nullptr;
  size_t size_ = 0;
};
// Hit pixels of gbuffer in the given pixel order.
std::vector<uint32_t> hit_pixels_in_order(const GBuffer& gbuffer, const std::vector<uint32_t>& order);
// Writes ray i of the batch from a shading point and the direction chosen for it. The origin is offset along
// the geometric normal on the side the direction leaves; a non-finite position yields a finite stand-in ray
// with weight 0, flagged kSampleNonFinite in the returned flags.
uint32_t emit_ray(RayBatch& out, size_t i, const ShadingPoint& sp, uint32_t pixel, const DirectionSample& s);
// Counts one emitted ray and its sample flags.
void tally_ray(uint32_t flags, GenerationStats& stats);
// Rays of the batch whose group is Hybrid and whose own material class is diffuse: the pixels the hybrid rule
// gives another lobe's direction (stability's hybrid_diffuse case, quality's hybrid_diffuse_share). 0 for a batch
// without groups.
size_t hybrid_diffuse_rays(const RayBatch& batch);
// Adds every counter of `from` into `into`.
void merge_stats(GenerationStats& into, const GenerationStats& from);

}  // namespace raycoh

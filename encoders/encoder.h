// Ray-reordering encoders: RayBatch -> keys -> stable radix sort -> permutation (docs/design.md section 3).
//
// An Encoder turns every ray of a batch into a k-bit sort key (k = key_bits(), 32 or 64) with one virtual call
// per batch; the per-ray codes are the host/device functions of encoders/keys.h. `none` makes no keys
// (key_bits() = 0): the batch is traced in the generator's order. Sorting is encoders/radix_sort.h, applying the
// order encoders/permute.h, and encoders/reorder.h times the three stages of one frame.
// Adding an encoder = one file with its doc block and factory + one entry in encoders/registry.cpp.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/params.h"
#include "core/plugin.h"
#include "core/ray_batch.h"
#include "core/vec.h"
#include "encoders/key_recipe.h"
#include "encoders/radix_sort.h"

namespace raycoh {

struct Bvh;

// What an encoder may read of the scene: the box positions are quantised in (the scene's bounds) and, for
// MLHCC, the BVH (it must outlive the encoder).
struct EncoderContext {
  Bounds bounds;
  const Bvh* bvh = nullptr;
};

// Buffers an encoder keeps between frames so that reorder() allocates nothing in its timed stages.
struct ReorderWorkspace {
  std::vector<uint64_t> keys;  // after reorder(): sorted, keys[i] belongs to ray order[i]
  RadixSortScratch sort;
};

class Encoder {
 public:
  virtual ~Encoder() = default;
  // keys[i] = the key of batch.rays[i] (the top key_bits() bits of its 64-bit code, right-aligned), for
  // every i < batch.size(); parallel over rays. Does nothing for `none`.
  virtual void encode(const RayBatch& batch, uint64_t* keys) const = 0;
  // Key width in bits: 32 or 64; 0 for `none` (no keys, no sort).
  virtual int key_bits() const = 0;
  // Canonical, defaulted parameter set, with the quantisation box last: "bits=32,box=-1/0/-1..1/2/1".
  virtual std::string params() const = 0;
  // The typed parameters (kind None for `none`).
  virtual KeyRecipe recipe() const = 0;
  // Facts derived from the scene that a report may show ("levels=4 bits=6/6/5/3 ..."); empty for most.
  virtual std::string details() const { return {}; }
  // Rays per window for the windowed reordering `window` (its keys keep every ray inside its window); 0 for a
  // global sort.
  virtual int window() const { return 0; }

  const std::string& name() const { return name_; }
  // The box positions are quantised in (the scene's bounds).
  const Bounds& box() const { return box_; }
  ReorderWorkspace& workspace() { return workspace_; }

 protected:
  Encoder(std::string name, const Bounds& box) : name_(std::move(name)), box_(box) {}

 private:
  std::string name_;
  Bounds box_;
  ReorderWorkspace workspace_;
};

// Reads its values from a ParamSet over the record's table; throws raycoh::Error for bad ones.
using EncoderFactory = std::unique_ptr<Encoder> (*)(ParamSet& params, const EncoderContext& context);
using EncoderInfo = PluginInfo<EncoderFactory>;

// The explicit registry.
const std::vector<EncoderInfo>& encoder_infos();
// Throws raycoh::Error for unknown names or bad parameters (naming the valid choices), and when an encoder
// needs the BVH (mlhcc) and context.bvh is null.
std::unique_ptr<Encoder> make_encoder(const PluginSpec& spec, const EncoderContext& context);

// "lo.x/lo.y/lo.z..hi.x/hi.y/hi.z" with shortest round-trip floats (no commas, so that it fits a parameter set).
std::string format_box(const Bounds& box);

}  // namespace raycoh

// The L1/TEX term of the stage model (simt/stage_model.h): the wavefronts each warp of a generation kernel puts
// through its SM's L1 pipeline, from each global load and store instruction's lane addresses, priced at one
// wavefront per cycle per SM. Modeled, never measured; docs/simt-model.md section 3 gives the rule's sources and
// what it leaves out (the miss path). Host only.
//
// A kernel's global memory instructions are an explicit inventory (L1Access rows, simt/stage_l1.cpp): per row the
// SASS instructions of one kind (scripts/count-stage-instructions --loads), their width, whose address each lane
// holds and the kernel line it describes. The wavefronts of one instruction follow from the preset's L1 rule
// (l1_request_wavefronts) applied to the 32 lanes' addresses.
#pragma once

#include <cstddef>
#include <cstdint>

#include "simt/gpu_model.h"

namespace raycoh {

struct StageWork;

// Whose address a lane of the warp holds.
enum class L1Lanes : uint8_t {
  Pixels,       // the G-buffer record of the lane's pixel: lane l of warp k is pixel number i = 32 k + l of its tile,
                // row-major in the tile (TileRect::pixel), at stride x image index + offset
  Consecutive,  // a batch column at consecutive slots: lane l at stride x (32 k + l) + offset
  Uniform,      // one address for the whole warp (a material's parameters, a tile's offset)
};

// `count` instructions of `width` bytes per lane. Pixels and Consecutive: the i-th of them reads offset +
// i x width modulo stride (a record's fields in turn).
struct L1Access {
  uint32_t count;
  uint32_t width;
  L1Lanes lanes;
  uint32_t stride;
  uint32_t offset;
};

// The global memory instructions of one kernel.
struct L1Inventory {
  const L1Access* rows = nullptr;
  size_t size = 0;
};

// Which G-buffer read the generation kernels make: since 63b5750 a 64-byte ShadingPoint in 16-byte loads
// (core/shading_point.h load_point); before it a 60-byte record read one 4-byte field at a time. The earlier
// kernels are kept so that the runs made with them (results/stages/h200-a26f7f6/) can be priced.
enum class GBufferRead : uint8_t { Wide64, Fields60 };
constexpr uint32_t gbuffer_record_bytes(GBufferRead r) { return r == GBufferRead::Fields60 ? 60 : 64; }

// One wavefront per cycle per SM: a wavefront is "the maximum unit of work that can pass through that pipeline stage
// per cycle" (the Nsight Compute team, NVIDIA developer forums, "What's the difference between wavefronts and
// sectors/req", thread 165293; Greg Smith, same forums, thread 273699, 2023: one load/store instruction a cycle
// enters an SM's LSU pipe, and the GV100+ tag stage resolves 4 sets x 4 sectors a cycle), and on an H100 the timed
// cycles per load equal its wavefronts for all 261 probed patterns (results/gpu/h100-6f75752/README.md). Measured on
// L1-resident data: a miss's extra work (fills from L2) is not counted, so the term is a lower bound.
constexpr double kL1WavefrontsPerCycle = 1.0;

// Wavefronts of one warp-wide request whose n active lanes access `width` bytes at addr[0..n), under the preset's
// L1 rule: the H100's measured rule (l1_words: hopper_l1_cycles), GPGPU-Sim's banks (l1_banks), or else
// max(distinct lines / l1_tags_per_clk, distinct bytes / 128-byte data path), at least 1.
double l1_request_wavefronts(const GpuModelConfig& gpu, const uint64_t* addr, uint32_t n, uint32_t width);

// Mean wavefronts per warp of `inventory` in a pass `w` (tile shape, image width), over the warps of the first 32
// tiles in row-major order (consecutive tiles, so that every alignment of a tile's records to the 128-byte lines
// occurs; tiles spread at a fixed step can alias to one alignment).
double l1_warp_wavefronts(const GpuModelConfig& gpu, const StageWork& w, const L1Inventory& inventory);

// `warps` warps of `wavefronts` each, spread over every SM's L1 at kL1WavefrontsPerCycle.
double stage_l1_ms(const GpuModelConfig& gpu, double warps, double wavefronts);

// The inventories of the generation kernels (simt/stage_l1.cpp cites the kernel line of every row).
L1Inventory tile_hits_l1(GBufferRead read);
L1Inventory noopt_l1(GBufferRead read);
L1Inventory group_l1(GBufferRead read);

}  // namespace raycoh

// The timing model of the `simt` tracer: replays the warps' step traces (simt/warp_trace.h) on a modelled GPU
// (simt/gpu_model.h) as a discrete-event simulation and reports the kernel's modeled time. Host only. The full
// specification, with what is and is not modelled, is docs/simt-model.md; in short:
//
//   - Warps are formed and placed as the `cuda` tracer's launch places them. Persistent kernel: every SM holds
//     `resident` warps (occupancy of the kernel: registers, block size, SM limits); a warp that finishes fetches
//     the next 32 rays of the batch (one global counter), so warp w of the batch runs on whichever SM frees a
//     slot first. Simple kernel: blocks of block_threads / 32 consecutive warps; an SM takes the next block when
//     all warps of one of its blocks have finished.
//   - A warp runs its steps one after the other: a ray fetch (its rays read through L1/L2/DRAM, then
//     traversal_begin), the node / leaf / triangle steps of its trace, and a hit store (DRAM write bandwidth
//     only, the warp does not wait). A step starts when its warp is ready and the SM's issue port takes its
//     instructions (the step's partition issue cycles, four partitions per SM, shared by the SM's warps, first
//     come first served); its memory instructions pass the SM's L1 pipeline (one wavefront per cycle: a global
//     load needs one per 4 distinct lines its lanes touch, a local access one), misses the GPU's L2 port
//     (`l2_bytes_per_clk`) and L2 misses the DRAM port (`dram_gb_s`), each a first-come-first-served server;
//     a sector arrives after its level's load-to-use latency. The step ends when its last sector has arrived
//     plus its issue cycles (the work that depends on the data).
//   - Other warps run while one waits, so latency is hidden as far as the resident warps allow (Little's law
//     emerges from the simulation), and every port limits throughput. The kernel time is the last warp's end:
//     the work-distribution tail is part of it.
//
// Events are processed in time order with ties broken by slot number, so the result depends on the traces and
// the configuration only: never on thread count or on how the traces were produced.
#pragma once

#include <cstddef>
#include <cstdint>
#include <queue>
#include <vector>

#include "simt/cache_model.h"
#include "simt/gpu_model.h"
#include "simt/warp_trace.h"
#include "tracers/tracer.h"

namespace raycoh {

// The port that bounded a kernel: "issue", "l1", "l2" or "dram" when that port was busy at least 80% of the
// kernel's time (the busiest such port), otherwise "latency" (too few warps to cover the waits, or the tail).
const char* modeled_limiter(const ModeledKernel& k);

class TimedReplay {
 public:
  // `ray_base_sector`: sector number of rays[0] (the ray array sits after the BVH in the modelled memory).
  TimedReplay(const GpuModelConfig& config, size_t warp_count, uint64_t ray_base_sector);
  // Replays events as long as every warp they need is below `ready` (traces[w] complete for w < ready); returns
  // before the first event that needs a later warp, so that the caller can trace more warps meanwhile. The result
  // does not depend on where it paused. The trace of a warp is freed when the warp finishes.
  void run(std::vector<WarpTrace>& traces, size_t ready);
  bool done() const { return done_; }
  const MemoryCounters& counters() const { return memory_.counters(); }  // BVH sectors only
  ModeledKernel result() const;
  // The SM each warp ran on (for tests of the placement).
  const std::vector<uint32_t>& warp_sms() const { return warp_sm_; }

 private:
  struct Slot {
    size_t warp = SIZE_MAX;  // SIZE_MAX: no warp
    uint32_t step = 0;       // next step of the trace; the fetch comes first
    bool fetched = false;
    bool wants_work = false;  // an event of this slot asks for the next warp (or block)
  };
  struct Event {
    double time;
    uint32_t slot;
    bool operator>(const Event& o) const { return time > o.time || (time == o.time && slot > o.slot); }
  };
  struct SmPorts {
    double issue_free = 0, l1_free = 0, issue_busy = 0, l1_busy = 0;
  };

  // Gives the slot its next warp (simple kernel: the block slot its next block) at time t; false when that warp
  // is not traced yet (>= ready).
  bool assign(uint32_t slot, double t, size_t ready);
  void finish(uint32_t slot, double t, WarpTrace& trace);
  size_t block_slot(uint32_t slot) const;
  // Runs one step of the slot's warp starting at t; returns when the warp is ready again.
  double step(uint32_t slot, double t, std::vector<WarpTrace>& traces);
  double issue(uint32_t sm, double t, double issue_cycles);
  double l1_wavefronts(const StepCost& cost, const WarpTrace& trace, uint32_t r) const;
  double ray_wavefronts(uint32_t warp, uint32_t lanes) const;
  double hopper_ray_wavefronts(uint32_t warp, uint32_t lanes) const;
  double after_data(const StepCost& cost) const;
  static constexpr uint32_t kMaxWarpLanes = 64;
  double fetch_sectors(uint32_t sm, double t, double wavefronts, const uint32_t* sectors, uint32_t count, bool bvh);

  GpuModelConfig config_;
  MemoryHierarchy memory_;
  uint32_t sms_, resident_, block_warps_;
  bool persistent_;
  size_t warp_count_;
  uint64_t ray_base_sector_;
  uint32_t ray_sectors_per_lane_, sectors_per_line_;
  double l2_cycles_per_sector_, dram_cycles_per_sector_, dram_cycles_per_byte_;

  std::vector<Slot> slots_;  // j * sms + sm: ties in time go to slot j of every SM in turn, as the launch deals
  std::vector<SmPorts> sm_;
  std::vector<uint32_t> warp_sm_;
  std::priority_queue<Event, std::vector<Event>, std::greater<Event>> events_;
  size_t next_warp_ = 0;              // persistent: the global ray counter, in warps
  size_t next_block_ = 0;             // simple: the block scheduler's next block
  std::vector<uint32_t> block_left_;  // simple: per block slot (sm * blocks + k), warps still running
  double l2_free_ = 0, dram_free_ = 0, l2_busy_ = 0, dram_busy_ = 0;
  double end_ = 0, first_idle_ = -1;
  uint64_t ray_sectors_ = 0, ray_dram_sectors_ = 0;
  double issue_cycles_ = 0;
  double l1_local_wavefronts_ = 0;
  bool started_ = false, done_ = false;
};

}  // namespace raycoh

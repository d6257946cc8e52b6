// The discrete-event timing model; the rules are in simt/timed_replay.h and docs/simt-model.md.
#include "simt/timed_replay.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <utility>

#include "core/error.h"

namespace raycoh {

TimedReplay::TimedReplay(const GpuModelConfig& config, size_t warp_count, uint64_t ray_base_sector)
    : config_(config),
      memory_(config.cache),
      sms_(config.cache.sms),
      resident_(resident_warps(config)),
      block_warps_(config.kernel.block_threads / 32),
      persistent_(config.kernel.kind == TraceKernel::Persistent),
      warp_count_(warp_count),
      ray_base_sector_(ray_base_sector) {
  validate(config_);
  const GpuSpec& g = config_.gpu;
  const uint32_t sector = config_.cache.sector_bytes;
  RAYCOH_CHECK(config_.kernel.ray_bytes % sector == 0 || sector % config_.kernel.ray_bytes == 0,
               fmt::format("ray of {} B and sectors of {} B", config_.kernel.ray_bytes, sector));
  ray_sectors_per_lane_ = std::max(1u, config_.kernel.ray_bytes / sector);
  sectors_per_line_ = config_.cache.line_bytes / sector;
  l2_cycles_per_sector_ = sector / g.l2_bytes_per_clk;
  dram_cycles_per_byte_ = 1.0 / g.dram_bytes_per_clk();
  dram_cycles_per_sector_ = sector * dram_cycles_per_byte_;
  slots_.assign(size_t{sms_} * resident_, Slot{});
  sm_.assign(sms_, SmPorts{});
  warp_sm_.assign(warp_count_, 0);
  const uint32_t block_slots = resident_ / block_warps_;
  block_left_.assign(size_t{sms_} * block_slots, 0);
  done_ = warp_count_ == 0;
}

// The step's instructions take `issue_cycles` of one partition: the SM's issue port (all partitions together)
// is occupied issue_cycles / schedulers_per_sm, first come first served.
double TimedReplay::issue(uint32_t sm, double t, double issue_cycles) {
  SmPorts& p = sm_[sm];
  const double start = std::max(t, p.issue_free);
  const double occupied = issue_cycles / config_.gpu.schedulers_per_sm;
  p.issue_free = start + occupied;
  p.issue_busy += occupied;
  issue_cycles_ += issue_cycles;
  return start;
}

// Wavefronts of the step's memory instructions in the SM's L1 pipeline, one per cycle: each global load needs
// one per l1_tags_per_clk distinct lines the active lanes touch (with l1_banks or l1_words: the cycles of that
// rule for the record word it reads, WarpTrace::word_cycles), each local access one.
double TimedReplay::l1_wavefronts(const StepCost& cost, const WarpTrace& trace, uint32_t r) const {
  if (config_.gpu.l1_banks || config_.gpu.l1_words) {
    RAYCOH_CHECK(trace.l1_banks == config_.gpu.l1_banks && trace.l1_words == config_.gpu.l1_words &&
                     r < trace.word_cycles.size(),
                 "the warp trace was recorded with the model's L1 rule");
    double cycles = 0;
    for (uint32_t w = 0; w < kMaxRecordWords; ++w)
      cycles += static_cast<double>(cost.word_loads[w]) * trace.word_cycles[r][w];
    return cycles + cost.local_accesses;
  }
  const uint32_t begin = r == 0 ? 0 : trace.request_end[r - 1];
  uint32_t lines = 0;
  uint64_t last = UINT64_MAX;
  for (uint32_t i = begin; i < trace.request_end[r]; ++i) {  // sorted: distinct lines are the changes of line
    const uint64_t line = trace.sectors[i] / sectors_per_line_;
    lines += line != last;
    last = line;
  }
  const double per_load = std::max(1.0, std::ceil(lines / config_.gpu.l1_tags_per_clk));
  return cost.global_loads * per_load + cost.local_accesses;
}

// Wavefronts of the ray fetch: 16-byte loads of consecutive rays; each moves 16 x lanes bytes through the L1's
// 128-byte data path (with l1_banks or l1_words: that rule for the addresses of each load).
double TimedReplay::ray_wavefronts(uint32_t warp, uint32_t lanes) const {
  const KernelSpec& k = config_.kernel;
  if (config_.gpu.l1_words) return hopper_ray_wavefronts(warp, lanes);
  if (!config_.gpu.l1_banks) return k.ray_begin.global_loads * std::max(1.0, 16.0 * lanes / 128.0);
  const uint64_t sector = config_.cache.sector_bytes;
  const uint64_t base = ray_base_sector_ * sector + uint64_t{warp} * k.warp_size * k.ray_bytes;
  double cycles = 0;
  uint64_t sectors[kMaxWarpLanes];
  for (uint32_t load = 0; load < k.ray_begin.global_loads; ++load) {
    uint32_t n = 0;
    for (uint32_t l = 0; l < lanes && l < kMaxWarpLanes; ++l) {
      const uint64_t s = (base + uint64_t{l} * k.ray_bytes + 16u * (load % std::max(1u, k.ray_bytes / 16))) / sector;
      if (n == 0 || sectors[n - 1] != s) sectors[n++] = s;  // ascending: lanes' rays are consecutive
    }
    cycles += l1_bank_cycles(sectors, n, config_.gpu.l1_banks);
  }
  return cycles;
}

// The ray fetch under the H100's rule: each 16-byte load of the lanes' consecutive rays (hopper_l1_cycles).
double TimedReplay::hopper_ray_wavefronts(uint32_t warp, uint32_t lanes) const {
  const KernelSpec& k = config_.kernel;
  const uint64_t base = ray_base_sector_ * config_.cache.sector_bytes + uint64_t{warp} * k.warp_size * k.ray_bytes;
  uint64_t addr[kMaxWarpLanes];
  const uint32_t n = std::min<uint32_t>(lanes, kMaxWarpLanes);
  double cycles = 0;
  for (uint32_t load = 0; load < k.ray_begin.global_loads; ++load) {
    for (uint32_t l = 0; l < n; ++l)
      addr[l] = base + uint64_t{l} * k.ray_bytes + 16u * (load % std::max(1u, k.ray_bytes / 16));
    cycles += hopper_l1_cycles(addr, n, 16);
  }
  return cycles;
}

// A warp's cycles from its step's data to its next step: its instructions back to back, or with inorder_cycles
// (in-order issue, each operand awaited) that time less the one L1 hit it assumed, whichever is longer.
double TimedReplay::after_data(const StepCost& cost) const {
  return std::max(cost.issue_cycles, cost.inorder_cycles - config_.gpu.l1_latency);
}

// The request passes the SM's L1 pipeline (`wavefronts` cycles); then each sector takes the latency of the level
// that serves it, misses queueing at the GPU-wide L2 and DRAM ports. Returns when the last sector has arrived.
double TimedReplay::fetch_sectors(uint32_t sm, double t, double wavefronts, const uint32_t* sectors, uint32_t count,
                                  bool bvh) {
  if (wavefronts == 0 && count == 0) return t;
  const GpuSpec& g = config_.gpu;
  SmPorts& p = sm_[sm];
  const double l1_start = std::max(t, p.l1_free);
  p.l1_free = l1_start + wavefronts;
  p.l1_busy += wavefronts;
  const double past_l1 = p.l1_free;
  double arrived = past_l1 + g.l1_latency;
  for (uint32_t i = 0; i < count; ++i) {
    const MemoryLevel level = memory_.access(sm, sectors[i], bvh);
    if (level == MemoryLevel::L1) continue;
    const double at_l2 = std::max(past_l1, l2_free_);
    l2_free_ = at_l2 + l2_cycles_per_sector_;
    l2_busy_ += l2_cycles_per_sector_;
    if (level == MemoryLevel::L2) {
      arrived = std::max(arrived, at_l2 + g.l2_latency);
      continue;
    }
    const double at_dram = std::max(at_l2, dram_free_);
    dram_free_ = at_dram + dram_cycles_per_sector_;
    dram_busy_ += dram_cycles_per_sector_;
    arrived = std::max(arrived, at_dram + g.dram_latency);
    if (!bvh) ++ray_dram_sectors_;
  }
  return arrived;
}

double TimedReplay::step(uint32_t slot_index, double t, std::vector<WarpTrace>& traces) {
  Slot& slot = slots_[slot_index];
  const uint32_t sm = slot_index % sms_;
  const KernelSpec& k = config_.kernel;
  WarpTrace& trace = traces[slot.warp];
  if (!slot.fetched) {
    // The warp's rays: one sector per 32 bytes of each lane's ray, consecutive in the batch.
    slot.fetched = true;
    uint32_t ray_sectors[64 * 4];
    const uint32_t n = std::min<uint32_t>(trace.lanes * ray_sectors_per_lane_, 64 * 4);
    const uint64_t first = ray_base_sector_ + uint64_t{slot.warp} * k.warp_size * ray_sectors_per_lane_;
    for (uint32_t i = 0; i < n; ++i) ray_sectors[i] = static_cast<uint32_t>(first + i);
    ray_sectors_ += n;
    const double wavefronts = ray_wavefronts(slot.warp, trace.lanes);
    const double start = issue(sm, t, k.ray_begin.issue_cycles);
    return fetch_sectors(sm, start, wavefronts, ray_sectors, n, false) + after_data(k.ray_begin);
  }
  const uint32_t r = slot.step++;
  const SimtStepKind kind = trace.kinds[r];
  const StepCost& cost = kind == SimtStepKind::Node ? k.node : kind == SimtStepKind::Triangle ? k.triangle : k.leaf;
  const uint32_t begin = r == 0 ? 0 : trace.request_end[r - 1];
  const uint32_t* sectors = trace.sectors.data() + begin;
  const uint32_t count = trace.request_end[r] - begin;
  const double start = issue(sm, t, cost.issue_cycles);
  l1_local_wavefronts_ += cost.local_accesses;
  const double data = fetch_sectors(sm, start, l1_wavefronts(cost, trace, r), sectors, count, true);
  return data + after_data(cost);
}

size_t TimedReplay::block_slot(uint32_t slot_index) const {
  return size_t{slot_index % sms_} * (resident_ / block_warps_) + (slot_index / sms_) / block_warps_;
}

bool TimedReplay::assign(uint32_t slot_index, double t, size_t ready) {
  slots_[slot_index].wants_work = false;
  if (persistent_) {
    if (next_warp_ >= warp_count_) {
      if (first_idle_ < 0) first_idle_ = t;
      return true;
    }
    if (next_warp_ >= ready) {
      slots_[slot_index].wants_work = true;
      return false;
    }
    warp_sm_[next_warp_] = slot_index % sms_;
    slots_[slot_index] = Slot{next_warp_++, 0, false, false};
    events_.push({t, slot_index});
    return true;
  }
  const size_t blocks = (warp_count_ + block_warps_ - 1) / block_warps_;
  if (next_block_ >= blocks) {
    if (first_idle_ < 0) first_idle_ = t;
    return true;
  }
  const size_t first = next_block_ * block_warps_;
  const size_t last = std::min(warp_count_, first + block_warps_);
  if (last > ready) {
    slots_[slot_index].wants_work = true;
    return false;
  }
  ++next_block_;
  block_left_[block_slot(slot_index)] = static_cast<uint32_t>(last - first);
  for (size_t w = first; w < last; ++w) {
    const uint32_t s = slot_index + static_cast<uint32_t>(w - first) * sms_;
    warp_sm_[w] = s % sms_;
    slots_[s] = Slot{w, 0, false, false};
    events_.push({t, s});
  }
  return true;
}

void TimedReplay::run(std::vector<WarpTrace>& traces, size_t ready) {
  RAYCOH_CHECK(traces.size() == warp_count_, fmt::format("{} traces for {} warps", traces.size(), warp_count_));
  if (done_) return;
  if (!started_) {
    // The launch: slot j of every SM in turn, so that consecutive warps (or blocks) start on different SMs, as
    // the block scheduler deals the first wave. Simple kernel: a block's first slot asks for the whole block.
    started_ = true;
    for (uint32_t j = 0; j < resident_; ++j) {
      for (uint32_t s = 0; s < sms_; ++s) {
        if (!persistent_ && j % block_warps_ != 0) continue;
        slots_[j * sms_ + s].wants_work = true;
        events_.push({0.0, j * sms_ + s});
      }
    }
  }
  while (!events_.empty()) {
    const Event e = events_.top();
    Slot& slot = slots_[e.slot];
    if (slot.warp == SIZE_MAX) {
      // The event stays queued when the next warp is not traced yet, so that run() resumes exactly here.
      if (slot.wants_work && !assign(e.slot, e.time, ready)) return;
      events_.pop();
      continue;
    }
    events_.pop();
    WarpTrace& trace = traces[slot.warp];
    if (!slot.fetched || slot.step < trace.requests()) {
      events_.push({step(e.slot, e.time, traces), e.slot});
      continue;
    }
    finish(e.slot, e.time, trace);
  }
  done_ = true;
}

// The warp's last step has ended: store its hits (DRAM write bandwidth only; the warp does not wait) and free the
// slot. A persistent slot fetches again; a simple kernel's block slot takes a new block when its last warp ends.
void TimedReplay::finish(uint32_t slot_index, double t, WarpTrace& trace) {
  const double cycles = static_cast<double>(config_.kernel.hit_bytes) * trace.lanes * dram_cycles_per_byte_;
  dram_free_ = std::max(t, dram_free_) + cycles;
  dram_busy_ += cycles;
  end_ = std::max(end_, t);
  trace = WarpTrace{};
  slots_[slot_index] = Slot{};
  uint32_t next = slot_index;
  if (!persistent_) {
    const size_t b = block_slot(slot_index);
    if (--block_left_[b] > 0) return;
    next = slot_index - ((slot_index / sms_) % block_warps_) * sms_;  // the block's first slot
  }
  slots_[next].wants_work = true;
  events_.push({t, next});
}

const char* modeled_limiter(const ModeledKernel& k) {
  const std::pair<double, const char*> ports[] = {
      {k.issue_busy, "issue"}, {k.l1_busy, "l1"}, {k.l2_busy, "l2"}, {k.dram_busy, "dram"}};
  const auto& busiest = *std::max_element(std::begin(ports), std::end(ports));
  return busiest.first >= 0.8 * k.cycles && k.cycles > 0 ? busiest.second : "latency";
}

ModeledKernel TimedReplay::result() const {
  ModeledKernel m;
  m.cycles = config_.gpu.launch_cycles + end_;  // the launch latency, then the warps
  m.ms = m.cycles / (config_.gpu.clock_mhz * 1e3);
  m.resident_warps = resident_;
  for (const SmPorts& p : sm_) {
    m.issue_busy = std::max(m.issue_busy, p.issue_busy);
    m.l1_busy = std::max(m.l1_busy, p.l1_busy);
    m.l1_wavefronts += p.l1_busy;
  }
  m.l1_local_wavefronts = l1_local_wavefronts_;
  m.l2_busy = l2_busy_;
  m.dram_busy = dram_busy_;
  m.tail_cycles = first_idle_ >= 0 ? end_ - first_idle_ : 0.0;
  m.ray_sectors = ray_sectors_;
  m.ray_dram_sectors = ray_dram_sectors_;
  m.issue_cycles = issue_cycles_;
  return m;
}

}  // namespace raycoh

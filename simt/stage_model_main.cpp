// raycoh_stage_model: the stage model (simt/stage_model.h) of passes described on stdin, one CSV line each:
//   label,preset,width,height,rays,generator,tile_w,tile_h,encoder,key_bits,permute_bytes[,gbuffer]
// generator: noopt or group (ours / contiguous); encoder: none, origin, reis, costa, aila, twopoint or mlhcc;
// permute_bytes: the gather's bytes (simt/pipeline_model.h permute_bytes of the pass's order; empty: no gather);
// gbuffer: wide64 (the default: the kernels since 63b5750) or fields60 (before it, simt/stage_l1.h GBufferRead).
// Five more fields give the group kernel's path (simt/stage_paths.h), which prices it by its trip-counted count:
//   ...,gbuffer,k,hybrid,frame,nondiffuse_groups,hybrid_groups   (hybrid: paper, donor, glossy or independent;
// frame: duff or rotate; the group counts: the pass's groups_glossy + groups_hybrid + groups_independent, and
// groups_hybrid). Without them (11 or 12 fields) the group kernel is priced by its static count. Two more
// (19 fields): MLHCC's cut-walk iterations per warp, origin and end point (bench/mlhcc_walks.cpp; empty: unknown),
// which price its key kernel by its trip-counted count. Two more (21 fields): the scene's glossy-like and
// transmissive group counts (simt/stage_paths.h NooptPath), which price the noopt kernel by its path. One more
// (22 fields): latency, 1 to add the latency term to the generator and key kernels (simt/stage_latency.h), else 0.
// Prints label,gen_ms,key_ms,sort_ms,permute_ms and the generator kernel's terms (gen_dram_ms, gen_issue_ms,
// gen_l1_ms, gen_l1_wavefronts per warp; tile_hits_l1_wavefronts) and the latency terms (gen_latency_ms,
// key_latency_ms; 0 without it), every figure MODELED. No times are read: what a pass
// is, not what it took. scripts/stage_model_check.py drives it (results/model/h200-stages/).
// --per-warp: also what the generator and key kernels' terms are made of, to set beside Nsight Compute's counters
// (scripts/stage_counters.py): warps, partition cycles per warp, the bytes it moves, resident warps per SM and a
// block's chain (SM cycles; both 0 without the latency term), for the generator, key and gather kernels (gen_*,
// key_*, gather_*; 0 where the pass has no such kernel).
#include <cstdio>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "simt/stage_model.h"

namespace {

constexpr const char* kKinds[] = {"none", "origin", "reis", "costa", "aila", "twopoint", "mlhcc"};

raycoh::KeyKind kind_of(const std::string& name) {
  for (int k = 0; k < 7; ++k)
    if (name == kKinds[k]) return static_cast<raycoh::KeyKind>(k);
  throw raycoh::Error("raycoh_stage_model: unknown encoder '" + name + "'");
}

std::vector<std::string> fields(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream in(line);
  for (std::string f; std::getline(in, f, ',');) out.push_back(f);
  if (!line.empty() && line.back() == ',') out.emplace_back();
  return out;
}

// Fields 12-16: k, hybrid, frame, nondiffuse_groups, hybrid_groups.
raycoh::GroupPath group_path_of(const std::vector<std::string>& f) {
  raycoh::GroupPath p;
  p.k = std::stoi(f[12]);
  if (f[13] != "paper" && f[13] != "donor" && f[13] != "glossy" && f[13] != "independent")
    throw raycoh::Error("raycoh_stage_model: hybrid is paper, donor, glossy or independent, not '" + f[13] + "'");
  if (f[14] != "duff" && f[14] != "rotate")
    throw raycoh::Error("raycoh_stage_model: frame is duff or rotate, not '" + f[14] + "'");
  p.hybrid_glossy = f[13] == "glossy";
  p.hybrid_own = f[13] == "independent";
  p.rotate = f[14] == "rotate";
  p.nondiffuse_groups = f[15].empty() ? 0.0 : std::stod(f[15]);
  p.hybrid_groups = f[16].empty() ? 0.0 : std::stod(f[16]);
  return p;
}

// The --per-warp columns of one kernel's terms.
std::string per_warp(const raycoh::StageKernelTerms& t) {
  char out[160];
  std::snprintf(out, sizeof out, ",%.0f,%.2f,%.0f,%.0f,%.1f", t.warps, t.cycles, t.bytes, t.resident_warps,
                t.chain_cycles);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace raycoh;
  const bool warp_columns = argc == 2 && std::string(argv[1]) == "--per-warp";
  if (argc > 2 || (argc == 2 && !warp_columns)) {
    std::cerr << "raycoh_stage_model: the one option is --per-warp; passes are read from stdin\n";
    return 2;
  }
  std::cout << "label,gen_ms,key_ms,sort_ms,permute_ms,gen_dram_ms,gen_issue_ms,gen_l1_ms,gen_l1_wavefronts,"
               "tile_hits_l1_wavefronts,gen_latency_ms,key_latency_ms";
  if (warp_columns)
    for (const char* k : {"gen", "key", "gather"})
      std::cout << "," << k << "_warps," << k << "_cycles_per_warp," << k << "_bytes," << k << "_resident_warps," << k
                << "_chain_cycles";
  std::cout << "\n";
  try {
    for (std::string line; std::getline(std::cin, line);) {
      if (line.empty()) continue;
      const std::vector<std::string> f = fields(line);
      if (f.size() != 11 && f.size() != 12 && f.size() != 17 && f.size() != 19 && f.size() != 21 && f.size() != 22)
        throw Error("raycoh_stage_model: 11, 12, 17, 19, 21 or 22 fields expected: " + line);
      const GpuModelConfig gpu = gpu_preset(f[1]);
      StageWork w;
      w.width = std::stoi(f[2]);
      w.height = std::stoi(f[3]);
      w.rays = std::stoull(f[4]);
      w.grouping = f[5] == "group";
      w.tile_w = std::stoi(f[6]);
      w.tile_h = std::stoi(f[7]);
      w.key = kind_of(f[8]);
      w.key_bits = w.key == KeyKind::None ? 0 : std::stoi(f[9]);
      if (f.size() >= 12 && f[11] != "wide64" && f[11] != "fields60")
        throw Error("raycoh_stage_model: gbuffer is wide64 or fields60, not '" + f[11] + "'");
      if (f.size() >= 12 && f[11] == "fields60") w.gbuffer = GBufferRead::Fields60;
      if (f.size() >= 17 && w.grouping) w.group_path = group_path_of(f);
      if (f.size() >= 19 && !f[17].empty()) w.mlhcc_walks.origin = std::stod(f[17]);
      if (f.size() >= 19 && !f[18].empty()) w.mlhcc_walks.end = std::stod(f[18]);
      if (f.size() >= 21 && !w.grouping && !f[19].empty())
        w.noopt_path = NooptPath{true, std::stod(f[19]), std::stod(f[20])};
      if (f.size() == 22 && f[21] != "0" && f[21] != "1")
        throw Error("raycoh_stage_model: latency is 0 or 1, not '" + f[21] + "'");
      w.latency = f.size() == 22 && f[21] == "1";
      ModeledStages m;
      m.gen_ms = stage_generation_ms(gpu, w);
      m.key_ms = stage_key_ms(gpu, w);
      m.sort_ms = stage_sort_ms(gpu, w.rays, w.key_bits);
      if (!f[10].empty() && w.key_bits > 0) m.permute_ms = stage_permute_ms(gpu, std::stod(f[10]), w.rays);
      const StageKernelTerms g = stage_generator_terms(gpu, w);
      char out[512];
      const StageKernelTerms k = stage_key_terms(gpu, w);
      std::snprintf(out, sizeof out, "%s,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.2f,%.2f,%.6f,%.6f", f[0].c_str(),
                    m.gen_ms, m.key_ms, m.sort_ms, m.permute_ms, g.dram_ms, g.issue_ms, g.l1_ms, g.l1_wavefronts,
                    stage_tile_hits_terms(gpu, w).l1_wavefronts, g.latency_ms, k.latency_ms);
      const StageKernelTerms gather =
          m.permute_ms > 0 ? stage_permute_terms(gpu, std::stod(f[10]), w.rays) : StageKernelTerms{};
      std::cout << out << (warp_columns ? per_warp(g) + per_warp(k) + per_warp(gather) : std::string()) << "\n";
    }
  } catch (const std::exception& e) {
    std::cerr << e.what() << "\n";
    return 2;
  }
  return 0;
}

// The explicit encoder registry: adding an encoder is one file (its doc block, parameter table and factory) plus
// one record here.
#include <fmt/format.h>

#include "core/error.h"
#include "encoders/encoder.h"
#include "encoders/key_encoder.h"

namespace raycoh {

const std::vector<EncoderInfo>& encoder_infos() {
  // Every key encoder also records box=lo..hi after its parameters: the scene bounds positions are quantised in.
  static const std::vector<EncoderInfo> infos = {
      {"none", "no reordering: rays are traced in the order the generator wrote them", none_params, make_none_encoder},
      {"origin", "3-D Morton code of the origin, 21 bits per axis (Meister et al. 2020)", origin_params,
       make_origin_encoder},
      {"reis", "origin Morton (top 22 bits), then direction phi/theta interleaved, 21 bits each (Reis et al. 2017)",
       reis_params, make_reis_encoder},
      {"costa", "direction phi/theta 4+4 bits, then origin Morton 15 bits per axis (Costa et al. 2015)", costa_params,
       make_costa_encoder},
      {"aila",
       "AilaCompact: 3 origin levels, then alternating origin / (d+1)/2 direction 3-bit groups, 13 bits per axis "
       "(Aila & Karras 2010)",
       aila_params, make_aila_encoder},
      {"twopoint",
       "6-D Morton code of origin and end point o + L d, L = min(L x longest extent, tmax, box exit), 13 bits per "
       "axis (Meister et al. 2020)",
       twopoint_params, make_twopoint_encoder},
      {"mlhcc",
       "RECONSTRUCTION of the hierarchy cut code of Xiang et al. 2023 (\"Faster Ray Tracing through Hierarchy Cut "
       "Code\"; no public code) from its description: ranks of origin and end point in nested BVH cuts, per-level "
       "widths; the exact rule chosen is documented in encoders/mlhcc.cpp",
       mlhcc_params, make_mlhcc_encoder},
      {"window",
       "windowed reordering: rays binned by a short key (octant, or the top bits of another encoder's code) inside "
       "windows of W rays, as hardware reordering does",
       window_params, make_window_encoder},
  };
  return infos;
}

std::unique_ptr<Encoder> make_encoder(const PluginSpec& spec, const EncoderContext& context) {
  const EncoderInfo& info = find_plugin(encoder_infos(), "encoder", spec.name);
  ParamSet params(fmt::format("encoder '{}'", spec.name), spec.params, info.table());
  return info.make(params, context);
}

ParamSpec key_bits_param() {
  return choice_param("bits", "32", {"32", "64"}, "key width: the top bits of the 64-bit code");
}

ParamSpec end_point_param() {
  return float_param("L", 0.25f, 0.f, 16.f, "end-point distance as a fraction of the longest scene extent");
}

int read_key_bits(ParamSet& params) { return params.get_choice("bits") == "64" ? 64 : 32; }

std::string finish_encoder_params(ParamSet& params, const Bounds& box) {
  params.finish();
  return params.canonical() + ",box=" + format_box(box);
}

std::string format_box(const Bounds& box) {
  return fmt::format("{}/{}/{}..{}/{}/{}", box.lo.x, box.lo.y, box.lo.z, box.hi.x, box.hi.y, box.hi.z);
}

}  // namespace raycoh

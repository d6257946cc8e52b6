// The explicit encoder registry: adding an encoder is one file plus one entry in the table here.
#include <fmt/format.h>

#include "core/error.h"
#include "encoders/encoder.h"
#include "encoders/key_encoder.h"

namespace raycoh {
namespace {

using Factory = std::unique_ptr<Encoder> (*)(ParamSet&, const EncoderContext&);

struct Entry {
  EncoderInfo info;
  Factory make;
};

const std::vector<Entry>& entries() {
  static const std::string box = "; positions are quantised in the scene bounds, recorded as box=lo..hi";
  static const std::vector<Entry> table = {
      {{"none", "no reordering: rays are traced in the order the generator wrote them", "(no parameters)"},
       make_none_encoder},
      {{"origin", "3-D Morton code of the origin, 21 bits per axis (Meister et al. 2020)", "bits=32|64 (32)" + box},
       make_origin_encoder},
      {{"reis", "origin Morton (top 22 bits), then direction phi/theta interleaved, 21 bits each (Reis et al. 2017)",
        "bits=32|64 (32)" + box},
       make_reis_encoder},
      {{"costa", "direction phi/theta 4+4 bits, then origin Morton 15 bits per axis (Costa et al. 2015)",
        "bits=32|64 (32)" + box},
       make_costa_encoder},
      {{"aila",
        "AilaCompact: 3 origin levels, then alternating origin / (d+1)/2 direction 3-bit groups, 13 bits per axis "
        "(Aila & Karras 2010)",
        "bits=32|64 (32)" + box},
       make_aila_encoder},
      {{"twopoint",
        "6-D Morton code of origin and end point o + L d, L = min(L x longest extent, tmax, box exit), 13 bits per "
        "axis (Meister et al. 2020)",
        "bits=32|64 (32), L=float (0.25, [0, 16])" + box},
       make_twopoint_encoder},
      {{"mlhcc",
        "hierarchy cut code: ranks of origin and end point in nested BVH cuts, per-level widths (Xiang et al. 2023)",
        "bits=32|64 (32), lambda=float (0.125, [0.001, 0.999]), L=float (0.25, [0, 16]), points=both|origin "
        "(both), ranks=compressed|global (compressed)" +
            box},
       make_mlhcc_encoder},
  };
  return table;
}

}  // namespace

const std::vector<EncoderInfo>& encoder_infos() {
  static const std::vector<EncoderInfo> infos = [] {
    std::vector<EncoderInfo> out;
    for (const Entry& e : entries()) out.push_back(e.info);
    return out;
  }();
  return infos;
}

std::unique_ptr<Encoder> make_encoder(const PluginSpec& spec, const EncoderContext& context) {
  ParamSet params(fmt::format("encoder '{}'", spec.name), spec.params);
  for (const Entry& e : entries())
    if (spec.name == e.info.name) return e.make(params, context);
  std::vector<std::string> names;
  for (const Entry& e : entries()) names.push_back(e.info.name);
  throw Error(fmt::format("unknown encoder '{}'; valid encoders: {}", spec.name, join(names)));
}

int read_key_bits(ParamSet& params) { return params.get_choice("bits", "32", {"32", "64"}) == "64" ? 64 : 32; }

std::string finish_encoder_params(ParamSet& params, const Bounds& box) {
  params.finish();
  return params.canonical() + ",box=" + format_box(box);
}

std::string format_box(const Bounds& box) {
  return fmt::format("{}/{}/{}..{}/{}/{}", box.lo.x, box.lo.y, box.lo.z, box.hi.x, box.hi.y, box.hi.z);
}

}  // namespace raycoh

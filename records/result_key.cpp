#include "records/result_key.h"

namespace raycoh {

std::string ResultKey::label(bool every_parameter) const {
  const std::string detail = every_parameter   ? params
                             : !preset.empty() ? "preset=" + preset
                             : !mode.empty()   ? "mode=" + mode
                                               : "";
  return detail.empty() ? tracer : tracer + "[" + detail + "]";
}

std::map<ResultKey, std::string> heading_labels(const std::vector<ResultKey>& keys) {
  std::map<ResultKey, std::string> names;
  std::map<std::string, int> uses;
  for (const ResultKey& k : keys)
    if (names.emplace(k, k.label()).second) ++uses[k.label()];
  for (auto& [k, name] : names)
    if (uses[name] > 1) name = k.label(true);
  return names;
}

}  // namespace raycoh

#include "records/stability_row.h"

namespace raycoh {

const Schema<StabilityRow>& stability_schema() {
  using namespace csv_format;
  using R = StabilityRow;
  static const Schema<R> schema = [] {
    Schema<R> s = {
        column("scene", &R::scene, Text{}),
        column("scene_spec", &R::spec, Text{}),
        column("scene_triangles", &R::triangles, Integer<size_t>{}),
        column("batch", &R::batch, Text{}),
        column("case", &R::name, Text{}),
        column("count", &R::count, Integer<size_t>{}),
        column("of", &R::of, Integer<size_t>{}),
        column("rate", &R::rate, General{}),
        column("threshold", &R::threshold, GeneralOrEmpty{}),
        column("status", &R::status, Text{}),
        column("width", &R::width, Integer<int>{}),
        column("height", &R::height, Integer<int>{}),
        column("frame", &R::frame, Integer<int>{}),
        column("seed", &R::seed, Integer<uint32_t>{}),
        column("max_rays", &R::max_rays, Integer<size_t>{}),
    };
    append_columns(s, provenance_schema(), &R::provenance);
    return s;
  }();
  return schema;
}

}  // namespace raycoh

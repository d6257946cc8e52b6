#include "records/validate_row.h"

namespace raycoh {

const Schema<ValidateRow>& validate_schema() {
  using namespace csv_format;
  using R = ValidateRow;
  static const Schema<R> schema = [] {
    Schema<R> s = {
        column("table", &R::table, Text{}, Key::Yes),
        column("row", &R::row, Text{}, Key::Yes),
        column("paper_scene", &R::paper_scene, Text{}, Key::Yes),
        column("paper_row", &R::paper_row, Text{}),
        column("tile", &R::tile, Text{}),
        column("k", &R::k, Integer<int>{}),
        column("paper_mray_s", &R::paper_mray_s, GeneralOrEmpty{}),
        column("paper_ratio", &R::paper_ratio, GeneralOrEmpty{}),
        column("kind", &R::kind, Text{}),
        column("modeled_mray_s", &R::modeled_mray_s, GeneralOrEmpty{}),
        column("modeled_ratio", &R::modeled_ratio, GeneralOrEmpty{}),
        column("measured_mray_s", &R::measured_mray_s, GeneralOrEmpty{}),
        column("measured_ratio", &R::measured_ratio, GeneralOrEmpty{}),
        column("ratio_lo", &R::ratio_lo, GeneralOrEmpty{}),
        column("ratio_hi", &R::ratio_hi, GeneralOrEmpty{}),
        column("paper_in_interval", &R::paper_in_interval, Text{}),
        column("ratio_error", &R::ratio_error, GeneralOrEmpty{}),
        column("modeled_limiter", &R::limiter, Text{}),
        column("scene", &R::scene, Text{}),
        column("preset", &R::preset, Text{}),
        column("tracer_params", &R::tracer_params, Text{}),
        column("order", &R::order, Text{}),
        column("width", &R::width, Integer<int>{}),
        column("height", &R::height, Integer<int>{}),
    };
    append_columns(s, provenance_schema(), &R::provenance);
    return s;
  }();
  return schema;
}

}  // namespace raycoh

#include "records/tune_row.h"

namespace raycoh {

namespace {

// 0 / 1.
struct Flag {
  static std::string write(bool v) { return v ? "1" : "0"; }
  static bool read(const std::string& s) {
    if (s != "0" && s != "1") csv_format::bad(s, "0 or 1");
    return s == "1";
  }
};

}  // namespace

const Schema<TuneRow>& tune_schema() {
  using namespace csv_format;
  using R = TuneRow;
  using G = GeneralOrEmpty;
  static const Schema<R> schema = [] {
    Schema<R> s = {
        column("scene", &R::scene, Text{}),
        column("scene_spec", &R::scene_spec, Text{}),
        column("setting", &R::setting, Text{}),
        column("generator", &R::generator, Text{}),
        column("tile_w", &R::tile_w, Integer<int>{}),
        column("tile_h", &R::tile_h, Integer<int>{}),
        column("k", &R::k, Integer<int>{}),
        column("order", &R::order, Text{}),
        column("hybrid", &R::hybrid, Text{}),
        column("frame", &R::frame, Text{}),
        column("tracer_spec", &R::tracer_spec, Text{}),
        column("speed_csv", &R::speed_csv, Text{}),
        column("speed_kind", &R::speed_kind, Text{}),
        column("rank", &R::rank, Text{}),
        column("mray_s", &R::mray_s, G{}),
        column("speedup", &R::speedup, G{}),
        column("trace_mray_s", &R::trace_mray_s, G{}),
        column("e2e_mray_s", &R::e2e_mray_s, G{}),
        column("noopt_mray_s", &R::noopt_mray_s, G{}),
        column("speedup_lo", &R::speedup_lo, G{}),
        column("speedup_hi", &R::speedup_hi, G{}),
        column("vs_paper", &R::vs_paper, G{}),
        column("vs_paper_lo", &R::vs_paper_lo, G{}),
        column("vs_paper_hi", &R::vs_paper_hi, G{}),
        column("vs_paper_verdict", &R::vs_paper_verdict, Text{}),
        column("speed_repeats", &R::speed_repeats, Integer<int>{}),
        column("waves", &R::waves, G{}),
        column("render_tracer", &R::render_tracer, Text{}),
        column("render_device", &R::render_device, Text{}),
        column("width", &R::width, Integer<int>{}),
        column("height", &R::height, Integer<int>{}),
        column("frames", &R::frames, Integer<int>{}),
        column("ref_frames", &R::ref_frames, Integer<int>{}),
        column("seeds", &R::seeds, Integer<int>{}),
        column("seed", &R::seed, Integer<uint32_t>{}),
        column("error_measured", &R::error_measured, Flag{}),
        column("ds8_ratio", &R::ds8, G{}),
        column("ds8_lo", &R::ds8_lo, G{}),
        column("ds8_hi", &R::ds8_hi, G{}),
        column("rel_ratio", &R::rel, G{}),
        column("rel_lo", &R::rel_lo, G{}),
        column("rel_hi", &R::rel_hi, G{}),
        column("flip_ratio", &R::flip, G{}),
        column("flip_lo", &R::flip_lo, G{}),
        column("flip_hi", &R::flip_hi, G{}),
        column("bias_verdict", &R::bias_verdict, Text{}),
        column("budget", &R::budget, Text{}),
        column("meets_budget", &R::meets_budget, Flag{}),
        column("front", &R::front, Flag{}),
        column("recommended", &R::recommended, Flag{}),
        column("closest_miss", &R::closest_miss, Flag{}),
        column("paper_default", &R::paper_default, Flag{}),
        column("fastest_passing", &R::fastest_passing, Flag{}),
        column("reason", &R::reason, Text{}),
        column("search", &R::search, Text{}),
    };
    append_columns(s, provenance_schema(), &R::provenance);
    return s;
  }();
  return schema;
}

const Schema<TuneConfirmRow>& tune_confirm_schema() {
  using namespace csv_format;
  using R = TuneConfirmRow;
  using G = GeneralOrEmpty;
  static const Schema<R> schema = [] {
    Schema<R> s = {
        column("scene", &R::scene, Text{}),
        column("scene_spec", &R::scene_spec, Text{}),
        column("kind", &R::kind, Text{}),
        column("seeds", &R::seeds, Text{}),
        column("setting", &R::setting, Text{}),
        column("baseline", &R::baseline, Text{}),
        column("claim", &R::claim, Text{}),
        column("search_ratio", &R::search_ratio, G{}),
        column("ratio", &R::ratio, G{}),
        column("ratio_lo", &R::lo, G{}),
        column("ratio_hi", &R::hi, G{}),
        column("verdict", &R::verdict, Text{}),
        column("held", &R::held, Text{}),
        column("setting_speedup", &R::setting_speedup, G{}),
        column("setting_speedup_lo", &R::setting_speedup_lo, G{}),
        column("setting_speedup_hi", &R::setting_speedup_hi, G{}),
        column("setting_mray_s", &R::setting_mray_s, G{}),
        column("baseline_mray_s", &R::baseline_mray_s, G{}),
        column("noopt_mray_s", &R::noopt_mray_s, G{}),
        column("tracer_spec", &R::tracer_spec, Text{}),
        column("speed_kind", &R::speed_kind, Text{}),
        column("rank", &R::rank, Text{}),
        column("speed_csv", &R::speed_csv, Text{}),
        column("width", &R::width, Integer<int>{}),
        column("height", &R::height, Integer<int>{}),
        column("speed_frames", &R::speed_frames, Integer<int>{}),
        column("repeats", &R::repeats, Integer<int>{}),
        column("waves", &R::waves, G{}),
    };
    append_columns(s, provenance_schema(), &R::provenance);
    return s;
  }();
  return schema;
}

}  // namespace raycoh

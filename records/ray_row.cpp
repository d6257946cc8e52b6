#include "records/ray_row.h"

#include <fmt/format.h>

#include <tuple>

namespace raycoh {

namespace {

// Floats with every digit needed to read them back exactly.
struct Float9 {
  static std::string write(float v) { return fmt::format("{:.9g}", v); }
  static float read(const std::string& s) { return static_cast<float>(csv_format::read_double(s)); }
};

// Every column; rays_schema() leaves out those the batch has no values for.
const Schema<RayRow>& all_ray_columns() {
  using namespace csv_format;
  using R = RayRow;
  static const Schema<R> schema = {
      column("index", &R::index, Integer<size_t>{}),
      column("pixel_x", &R::pixel_x, Integer<uint32_t>{}),
      column("pixel_y", &R::pixel_y, Integer<uint32_t>{}),
      column("frame", &R::frame, Integer<int>{}),
      column("org_x", &R::org_x, Float9{}),
      column("org_y", &R::org_y, Float9{}),
      column("org_z", &R::org_z, Float9{}),
      column("dir_x", &R::dir_x, Float9{}),
      column("dir_y", &R::dir_y, Float9{}),
      column("dir_z", &R::dir_z, Float9{}),
      column("tmin", &R::tmin, Float9{}),
      column("tmax", &R::tmax, Float9{}),
      column("normal_x", &R::normal_x, Float9{}),
      column("normal_y", &R::normal_y, Float9{}),
      column("normal_z", &R::normal_z, Float9{}),
      column("material_class", &R::material_class, Text{}),
      column("pdf", &R::pdf, Float9{}),
      column("weight_r", &R::weight_r, Float9{}),
      column("weight_g", &R::weight_g, Float9{}),
      column("weight_b", &R::weight_b, Float9{}),
      column("tile", &R::tile, Integer<uint32_t>{}),
      column("group", &R::group, Integer<uint32_t>{}),
      column("group_type", &R::group_type, Text{}),
      column("key", &R::key, Text{}),
  };
  return schema;
}

}  // namespace

Schema<RayRow> rays_schema(bool groups, bool keys) {
  Schema<RayRow> s;
  for (const Column<RayRow>& c : all_ray_columns()) {
    const bool group_column = c.name == "tile" || c.name == "group" || c.name == "group_type";
    if ((group_column && !groups) || (c.name == "key" && !keys)) continue;
    s.push_back(c);
  }
  return s;
}

RayRow ray_row(const RayBatch& batch, size_t i, int width, int frame) {
  const Ray& r = batch.rays[i];
  const Vec3 n = batch.normal[i], w = batch.weight[i];
  RayRow row;
  row.index = i;
  row.pixel_x = batch.pixel[i] % width;
  row.pixel_y = batch.pixel[i] / width;
  row.frame = frame;
  std::tie(row.org_x, row.org_y, row.org_z) = std::tuple(r.org.x, r.org.y, r.org.z);
  std::tie(row.dir_x, row.dir_y, row.dir_z) = std::tuple(r.dir.x, r.dir.y, r.dir.z);
  std::tie(row.tmin, row.tmax) = std::tuple(r.tmin, r.tmax);
  std::tie(row.normal_x, row.normal_y, row.normal_z) = std::tuple(n.x, n.y, n.z);
  row.material_class = to_string(batch.material[i]);
  row.pdf = batch.pdf[i];
  std::tie(row.weight_r, row.weight_g, row.weight_b) = std::tuple(w.x, w.y, w.z);
  if (batch.has_groups()) {
    row.tile = batch.tile[i];
    row.group = batch.group[i];
    row.group_type = to_string(batch.group_type[i]);
  }
  return row;
}

}  // namespace raycoh

// The measurement of `raycoh stability` (harness/stability.h): one scene's primary batch and each generator's
// secondary batch, traced in float by the `cpu` tracer and checked against the double-precision reference and
// their shading points (the cases and their rules: docs/stability.md). The command, its CSV and report are in
// harness/stability.cpp.
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <map>

#include "bvh/bvh_build.h"
#include "core/error.h"
#include "encoders/encoder.h"
#include "generators/generator.h"
#include "generators/pixel_order.h"
#include "harness/stability.h"
#include "pipeline/first_hits.h"
#include "plugins/tracer_registry.h"
#include "tracers/double_reference.h"
#include "tracers/tracer.h"

namespace raycoh {

namespace {

constexpr double kGrazingCos = 0.05;         // directions within about 3 degrees of the surface
constexpr double kNearOffsets = 4.0;         // a hit this many offset lengths from the origin is "within the offset"
constexpr double kReuseNormalDeg = 1.0;      // reuse pairs whose normals differ by less than this ...
constexpr double kReuseDirectionDeg = 30.0;  // ... but whose directions differ by more than this
constexpr double kDisplacedDiagonal = 1e-3;  // an origin further than this x the scene's diagonal off its point

bool bad_float(float x) { return !std::isfinite(x) || (x != 0.f && std::fabs(x) < FLT_MIN); }
bool bad_ray(const Ray& r) {
  return bad_float(r.org.x) || bad_float(r.org.y) || bad_float(r.org.z) || bad_float(r.dir.x) || bad_float(r.dir.y) ||
         bad_float(r.dir.z) || std::isnan(r.tmin) || std::isnan(r.tmax);
}

double length_d(Vec3 v) { return std::sqrt(double(v.x) * v.x + double(v.y) * v.y + double(v.z) * v.z); }
double dot_d(Vec3 a, Vec3 b) { return double(a.x) * b.x + double(a.y) * b.y + double(a.z) * b.z; }
double angle_deg(Vec3 a, Vec3 b) {
  const double c = dot_d(a, b) / (length_d(a) * length_d(b));
  return std::acos(std::clamp(c, -1.0, 1.0)) * 180.0 / 3.14159265358979323846;
}

// Indices of the rays checked against the reference: all, or max_rays evenly spaced.
std::vector<uint8_t> sample_mask(size_t n, size_t max_rays) {
  std::vector<uint8_t> mask(n, max_rays == 0 || max_rays >= n ? 1 : 0);
  if (max_rays > 0 && max_rays < n)
    for (size_t k = 0; k < max_rays; ++k) mask[k * n / max_rays] = 1;
  return mask;
}

enum class Verdict : uint8_t { Agree, Wrong, Missed, Graze };

// Whether the ray passes within the float triangle test's rounding of an edge of triangle `prim`: the smallest
// barycentric (negative outside) in double, against the error bound of the float edge functions, 32 eps M^2 |d|
// over the double determinant (M: the largest vertex distance from the origin; the sheared float products of
// coordinates of size M each carry about 24 eps M^2).
bool grazes_edge(const Scene& scene, uint32_t prim, const Ray& ray) {
  const uint32_t* idx = &scene.indices[3 * size_t(prim)];
  const Vec3 v[3] = {scene.positions[idx[0]], scene.positions[idx[1]], scene.positions[idx[2]]};
  const auto det = [&](Vec3 p, Vec3 q) {
    const double a[3] = {double(p.x) - ray.org.x, double(p.y) - ray.org.y, double(p.z) - ray.org.z};
    const double b[3] = {double(q.x) - ray.org.x, double(q.y) - ray.org.y, double(q.z) - ray.org.z};
    return (a[1] * b[2] - a[2] * b[1]) * ray.dir.x + (a[2] * b[0] - a[0] * b[2]) * ray.dir.y +
           (a[0] * b[1] - a[1] * b[0]) * ray.dir.z;
  };
  const double u = det(v[1], v[2]), w1 = det(v[2], v[0]), w2 = det(v[0], v[1]), s = u + w1 + w2;
  if (s == 0.0) return false;
  const double smallest = std::min(u / s, std::min(w1 / s, w2 / s));
  double m = 0.0;
  for (const Vec3& p : v) m = std::max(m, length_d(p - ray.org));
  const double bound = 32.0 * 0x1p-24 * m * m * length_d(ray.dir) / std::fabs(s);
  return std::fabs(smallest) <= bound;
}

// The float hit against the reference's: a different triangle is a tie (fine) when the reference hits the
// float's triangle at the same t, or the float's t is the reference's within 1e-6 (about 8 float ulps: two
// triangles meeting there). A disagreement caused by the ray grazing an edge within the float test's rounding
// (the reference's nearer triangle, or the float's one the reference misses) is a graze, not a wrong hit.
Verdict compare(const Scene& scene, const Ray& ray, const Hit& h, const RefHit& ref) {
  if (h.valid() && ref.valid() && h.prim == ref.prim) return Verdict::Agree;
  if (!h.valid() && !ref.valid()) return Verdict::Agree;
  if (h.valid() && ref.valid()) {
    const uint32_t* idx = &scene.indices[3 * size_t(h.prim)];
    const double t_other =
        reference_triangle_t(scene.positions[idx[0]], scene.positions[idx[1]], scene.positions[idx[2]], ray);
    if (std::fabs(t_other - ref.t) <= 1e-6 * ref.t) return Verdict::Agree;
    if (std::fabs(double(h.t) - ref.t) <= 1e-6 * ref.t) return Verdict::Agree;
  }
  const bool float_further = ref.valid() && (!h.valid() || double(h.t) > ref.t);
  if (grazes_edge(scene, float_further ? ref.prim : h.prim, ray)) return Verdict::Graze;
  return h.valid() ? Verdict::Wrong : Verdict::Missed;
}

// Counts of one batch, summed over rays (each flag array is per ray, then counted).
struct Flags {
  std::vector<uint8_t> non_finite, checked, wrong, missed, graze;
};

void check_hits(const Scene& scene, const Bvh& bvh, const std::vector<Ray>& rays, const std::vector<Hit>& hits,
                size_t max_rays, Flags& f, std::vector<RefHit>& refs) {
  const size_t n = rays.size();
  f.checked = sample_mask(n, max_rays);
  f.non_finite.assign(n, 0);
  f.wrong.assign(n, 0);
  f.missed.assign(n, 0);
  f.graze.assign(n, 0);
  refs.assign(n, RefHit{});
  const AlphaMaskView view = scene.alpha.view();
  const AlphaMaskView* alpha = scene.alpha.empty() ? nullptr : &view;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 256), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i < r.end(); ++i) {
      f.non_finite[i] = bad_ray(rays[i]);
      if (!f.checked[i] || f.non_finite[i]) continue;
      refs[i] = reference_closest_hit(bvh, rays[i], alpha);
      const Verdict v = compare(scene, rays[i], hits[i], refs[i]);
      f.wrong[i] = v == Verdict::Wrong;
      f.missed[i] = v == Verdict::Missed;
      f.graze[i] = v == Verdict::Graze;
    }
  });
}

size_t count(const std::vector<uint8_t>& v) { return static_cast<size_t>(std::count(v.begin(), v.end(), 1)); }
size_t count_and(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
  size_t c = 0;
  for (size_t i = 0; i < a.size(); ++i) c += a[i] && b[i];
  return c;
}

// Rays whose key equals another ray's key.
size_t colliding_keys(const Encoder& encoder, const RayBatch& batch) {
  std::vector<uint64_t> keys(batch.size());
  encoder.encode(batch, keys.data());
  std::sort(keys.begin(), keys.end());
  size_t colliding = 0;
  for (size_t i = 0; i < keys.size();) {
    size_t j = i + 1;
    while (j < keys.size() && keys[j] == keys[i]) ++j;
    if (j - i > 1) colliding += j - i;
    i = j;
  }
  return colliding;
}

// The batch's own box: its finite ray origins.
Bounds origin_box(const RayBatch& batch) {
  Bounds b;
  for (const Ray& r : batch.rays)
    if (is_finite(r.org)) b.grow(r.org);
  return b;
}

// Pairs of diffuse members of one reuse group (they share a direction in tangent or world space) whose normals
// differ by less than 1 degree: `of`; those whose directions differ by more than 30 degrees: `count`.
void reuse_pairs(const RayBatch& batch, size_t& pairs, size_t& bad) {
  pairs = bad = 0;
  if (!batch.has_groups()) return;
  std::map<uint32_t, std::vector<size_t>> groups;
  for (size_t i = 0; i < batch.size(); ++i) {
    const GroupType t = batch.group_type[i];
    const bool shares = t == GroupType::Diffuse || t == GroupType::Hybrid || t == GroupType::WorldShared;
    if (shares && batch.material[i] == MaterialClass::Diffuse) groups[batch.group[i]].push_back(i);
  }
  for (const auto& [g, members] : groups) {
    const size_t m = std::min<size_t>(members.size(), 256);
    for (size_t a = 0; a < m; ++a)
      for (size_t b = a + 1; b < m; ++b) {
        const size_t i = members[a], j = members[b];
        if (angle_deg(batch.normal[i], batch.normal[j]) >= kReuseNormalDeg) continue;
        ++pairs;
        bad += angle_deg(batch.rays[i].dir, batch.rays[j].dir) > kReuseDirectionDeg;
      }
  }
}

class SceneCheck {
 public:
  SceneCheck(const std::string& spec, const StabilityOptions& o) : o_(o) {
    report_.spec = spec;
    scene_ = load_scene(spec);
    report_.scene = scene_.name;
    report_.triangles = scene_.triangle_count();
    bvh_ = build_bvh(scene_);
    tracer_ = make_tracer({"cpu", ""}, scene_, bvh_);
  }

  StabilityReport run() {
    const auto order = make_pixel_order(o_.width, o_.height, RayOrder::Tile, 8, 8);
    const FirstHits first =
        first_hits(scene_, *tracer_, o_.width, o_.height, order, o_.seed, static_cast<uint32_t>(o_.frame), true);
    Flags f;
    std::vector<RefHit> refs;
    check_hits(scene_, bvh_, first.primary.rays, first.hits, o_.max_rays, f, refs);
    add("primary", "non_finite", count(f.non_finite), f.non_finite.size(), 0.0);
    add("primary", "wrong_closest_hit", count(f.wrong), count(f.checked), kWrongHitThreshold);
    add("primary", "missed_hit", count(f.missed), count(f.checked), kWrongHitThreshold);
    add("primary", "edge_graze", count(f.graze), count(f.checked), -1.0);
    for (const PluginSpec& g : o_.generators) secondary(g, first.gbuffer);
    return std::move(report_);
  }

 private:
  void add(const std::string& batch, const std::string& name, size_t n, size_t of, double threshold) {
    for (const auto& [key, value] : o_.thresholds)
      if (key == name || key == name.substr(0, name.find(':'))) threshold = value;
    report_.cases.push_back({batch, name, n, of, threshold});
  }

  void secondary(const PluginSpec& spec, const GBuffer& gbuffer) {
    const std::string label = spec.text();
    auto generator = make_generator(spec);
    RayBatch batch;
    GenerationStats stats;
    generator->generate(scene_, gbuffer, o_.seed, batch, stats);
    std::vector<Hit> hits(batch.size());
    tracer_->trace(batch.rays.data(), batch.size(), hits.data());
    Flags f;
    std::vector<RefHit> refs;
    check_hits(scene_, bvh_, batch.rays, hits, o_.max_rays, f, refs);

    const size_t n = batch.size();
    std::vector<uint8_t> valid(n, 0), self(n, 0), grazing(n, 0), behind(n, 0), disagree(n, 0), displaced(n, 0);
    const double diagonal = length_d(scene_.bounds.extent());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 256), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i < r.end(); ++i) {
        const ShadingPoint& sp = gbuffer.points[batch.pixel[i]];
        const Ray& ray = batch.rays[i];
        if (f.non_finite[i] || !is_finite(sp.position) || !is_finite(sp.ng)) continue;
        valid[i] = 1;
        const uint32_t* idx = &scene_.indices[3 * size_t(sp.prim)];
        const Vec3 v0 = scene_.positions[idx[0]], v1 = scene_.positions[idx[1]], v2 = scene_.positions[idx[2]];
        // The origin triangle's plane in double: the origin must lie strictly on the side the ray leaves to.
        const double e1[3] = {double(v1.x) - v0.x, double(v1.y) - v0.y, double(v1.z) - v0.z};
        const double e2[3] = {double(v2.x) - v0.x, double(v2.y) - v0.y, double(v2.z) - v0.z};
        const double ng[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                              e1[0] * e2[1] - e1[1] * e2[0]};
        const double side = ng[0] * ray.dir.x + ng[1] * ray.dir.y + ng[2] * ray.dir.z;
        const double height = ng[0] * (double(ray.org.x) - v0.x) + ng[1] * (double(ray.org.y) - v0.y) +
                              ng[2] * (double(ray.org.z) - v0.z);
        behind[i] = side != 0.0 && height * side <= 0.0;
        const double cos_g = dot_d(ray.dir, sp.ng) / length_d(ray.dir);
        grazing[i] = std::fabs(cos_g) < kGrazingCos;
        disagree[i] = (dot_d(ray.dir, sp.ng) > 0.0) != (dot_d(ray.dir, batch.normal[i]) > 0.0);
        const double offset = length_d(ray.org - sp.position);
        displaced[i] = offset > kDisplacedDiagonal * diagonal;
        const Hit& h = hits[i];
        if (!h.valid()) continue;
        const bool near = double(h.t) * length_d(ray.dir) <= kNearOffsets * offset;
        self[i] = h.prim == sp.prim || (near && f.checked[i] && f.wrong[i]);
      }
    });
    add(label, "non_finite", count(f.non_finite), n, 0.0);
    add(label, "origin_behind_surface", count(behind), count(valid), -1.0);
    add(label, "origin_displaced", count(displaced), count(valid), kDisplacedThreshold);
    add(label, "self_intersection", count(self), count(valid), kSelfIntersectionThreshold);
    add(label, "self_intersection_grazing", count_and(self, grazing), count_and(valid, grazing),
        kSelfIntersectionThreshold);
    add(label, "wrong_closest_hit", count(f.wrong), count(f.checked), kWrongHitThreshold);
    add(label, "missed_hit", count(f.missed), count(f.checked), kWrongHitThreshold);
    add(label, "edge_graze", count(f.graze), count(f.checked), -1.0);
    add(label, "below_geometric_surface", stats.below_geometric, n, -1.0);
    add(label, "shading_geometric_disagreement", count(disagree), count(valid), -1.0);
    size_t pairs = 0, bad = 0;
    reuse_pairs(batch, pairs, bad);
    if (batch.has_groups()) add(label, "reuse_discontinuity", bad, pairs, -1.0);
    if (batch.has_groups()) add(label, "hybrid_diffuse", hybrid_diffuse_rays(batch), n, -1.0);
    // Key degeneracy: rays whose keys collide with the scene's box beyond those that collide with the batch's own.
    for (const PluginSpec& e : o_.encoders) {
      const auto with_scene = make_encoder(e, EncoderContext{scene_.bounds, &bvh_});
      if (with_scene->key_bits() == 0) continue;
      const auto with_own = make_encoder(e, EncoderContext{origin_box(batch), &bvh_});
      const size_t a = colliding_keys(*with_scene, batch), b = colliding_keys(*with_own, batch);
      add(label, "key_degeneracy:" + e.text(), a > b ? a - b : 0, n, -1.0);
    }
  }

  const StabilityOptions& o_;
  StabilityReport report_;
  Scene scene_;
  Bvh bvh_;
  std::unique_ptr<Tracer> tracer_;
};
}  // namespace

StabilityReport measure_stability(const std::string& scene_spec, const StabilityOptions& options) {
  return SceneCheck(scene_spec, options).run();
}

}  // namespace raycoh

// Wavefront path tracer on the benchmark's pipeline (DESIGN.md sections 1 and 5).
//
// Per frame (one path per pixel, frame index = the rng's frame argument):
//   1. Camera rays through jittered pixel positions (generators/primary.h, 8x8 tile order), traced; the G-buffer
//      of their hits. A camera ray sees an emitter's radiance on its front face, or the environment (sky + sun
//      disc) when it misses.
//   2. At every path vertex with a non-delta BSDF (diffuse, emissive, glossy, specular: core/bsdf.h):
//      next-event estimation, one shadow ray per light kind, all of a bounce's shadow rays in one batch traced
//      closest-hit with tmax just short of the light (the tracer interface has no any-hit query). A shadow ray
//      that hits a thin-walled transmissive surface (a window pane) goes on behind it, attenuated by the
//      pane's straight-through transmittance (1 - F) x base colour, in another batch: thin-walled refraction
//      does not bend light, so this is the same path BSDF sampling finds through the pane, and without it a
//      scene lit through glass (Sibenik) would get no sunlight. At most max_depth - 1 - b panes are crossed
//      from the vertex of bounce b, so that both strategies cover the same path lengths. Lights:
//        emitters  one emissive triangle chosen with probability proportional to its power, area x luminance of
//                  its emission, then a uniform point on it (Shirley's square-root map). Emission is one-sided:
//                  the front side of the triangle's winding, as in pbrt and Mitsuba.
//        sun       a direction uniform in the sun's cone (Environment::sun_cos_half_angle).
//      The sky is not sampled by NEE: it is smooth and dim, and BSDF sampling (cosine-weighted for diffuse
//      surfaces) is already close to ideal for it, so a second strategy would only add shadow rays.
//   3. The direction leaving the FIRST hit comes from the chosen generator (NoOpt, ours, ...), with the pdf and
//      weight (f cos / pdf) the generator reports; later directions are sampled independently with
//      core/bsdf.h sample_direction. Transmissive surfaces are a smooth dielectric (delta lobes, no NEE).
//   4. A BSDF-sampled ray that hits an emitter's front face, or misses into the sun's cone, adds that light
//      weighted by multiple importance sampling with the power heuristic (beta = 2) against the NEE pdf of the
//      same light (Veach, "Robust Monte Carlo Methods for Light Transport Simulation", PhD thesis 1997, ch. 9);
//      after a delta lobe the weight is 1. Straight passes through thin panes keep the MIS state (pdf and
//      distance) of the scattering event before them, as NEE sees through them. A ray that misses always adds
//      the sky (weight 1: the sky's only strategy). Both strategies cover exactly the same path lengths (up to
//      max_depth scattering events), so the estimator is unbiased for NoOpt. With a reusing generator (ours), the first
//      bounce's MIS weight uses the pdf the generator reports for each pixel — each pixel's own marginal pdf for
//      diffuse groups, so unbiased there; the hybrid groups' shared direction is not drawn from that pdf (the paper's
//      bias, which the quality runs measure).
//   5. Russian roulette from rr_depth on: a path survives with probability min(1, max component of its
//      throughput) and is divided by it (unbiased).
//   6. Each pixel's frame sample is added to the Accumulator, which counts NaN/Inf samples instead of adding them.
//
// Random numbers: rng(seed, frame, pixel, dim) with, for the vertex of bounce b, dim = kDimFirstFree + 16 b + k:
// k = 0 emitter choice, 1-2 point on it, 3-4 sun cone, 5-6 BSDF direction, 7 lobe choice, 8 roulette. The
// generator uses its own dimensions (core/rng.h) for the first bounce. Every array is filled per ray or per pixel
// and compacted in a fixed order, so a frame is the same bits for any thread count.
#include "shading/path_tracer.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>

#include "core/bsdf.h"
#include "core/error.h"
#include "core/rng.h"
#include "generators/pixel_order.h"
#include "generators/primary.h"

namespace raycoh {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

constexpr int kPrimaryTile = 8;
constexpr uint32_t kDimsPerBounce = 16;
enum BounceDim : uint32_t {
  kEmitterPick = 0,
  kEmitterU = 1,
  kEmitterV = 2,
  kSunU = 3,
  kSunV = 4,
  kDirU = 5,
  kDirV = 6,
  kLobe = 7,
  kRoulette = 8
};
// Shadow rays stop this fraction short of the sampled light point, so that the light itself is not an occluder.
constexpr float kShadowEpsilon = 1e-4f;

float luminance(Vec3 c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

// Power heuristic (beta = 2) weight of the strategy with pdf a against b, written so that it never divides
// infinities: 1 / (1 + (b/a)^2).
float power_heuristic(float a, float b) {
  if (!(a > 0.f)) return 0.f;
  const float r = b / a;
  return 1.f / (1.f + r * r);
}

bool is_delta(MaterialClass c) { return c == MaterialClass::Transmissive; }

float sun_cone_pdf(const Environment& env) {
  return static_cast<float>(1.0 / (2.0 * 3.14159265358979323846 * (1.0 - static_cast<double>(env.sun_cos_half_angle))));
}

bool sun_on(const Environment& env) {
  return env.enabled && max_component(env.sun_radiance) > 0.f && env.sun_cos_half_angle < 1.f;
}

// How the light a ray finds is weighted (MIS state): the pdf and delta flag of the direction chosen at the
// last scattering event that was not a straight pass through a thin pane, and the distance travelled since that
// event before this ray's origin (the light pdf of an emitter is measured from there).
struct MisState {
  float pdf = 0.f;
  uint8_t delta = 1;  // a camera ray: nothing else could have found the light
  float dist = 0.f;
};

// Rays of one batch with what shading needs next to each.
struct Wave {
  PrimaryBatch rays;  // rays + the slot each belongs to (make_gbuffer reads this type)
  std::vector<uint32_t> pixel;
  std::vector<Vec3> beta;  // path throughput including this ray's f cos / pdf
  std::vector<MisState> mis;
  void resize(size_t n) {
    rays.rays.resize(n);
    rays.pixel.resize(n);
    pixel.resize(n);
    beta.resize(n);
    mis.resize(n);
  }
};

// Path vertices of one bounce.
struct Vertices {
  std::vector<ShadingPoint> sp;
  std::vector<uint32_t> pixel;
  std::vector<Vec3> beta;
  std::vector<MisState> mis;  // of the ray that arrived here
  size_t size() const { return sp.size(); }
};

// Shading points of a batch's hits in batch order: make_gbuffer on a one-row "image" whose pixel i is ray i.
GBuffer shade_hits(const Scene& scene, PrimaryBatch& rays, const std::vector<Hit>& hits, uint32_t frame) {
  const size_t n = rays.rays.size();
  rays.width = static_cast<int>(n);
  rays.height = 1;
  rays.frame = frame;
  rays.pixel.resize(n);
  std::iota(rays.pixel.begin(), rays.pixel.end(), 0u);
  return make_gbuffer(scene, rays, hits);
}

bool is_thin_pane(const Material& m) { return m.cls == MaterialClass::Transmissive && m.thin_walled; }

// Fraction of light a thin pane lets through straight, seen along wo from the side of ns (core/bsdf.h's
// thin-walled dielectric: transmitted with probability 1 - F and weight base colour).
Vec3 pane_transmittance(const Material& m, const ShadingPoint& sp) {
  const float cos_i = std::clamp(dot(sp.wo, sp.ns), 0.f, 1.f);
  return m.base_color * (1.f - fresnel_dielectric(cos_i, m.ior));
}

// Keeps the entries with keep[i] != 0 of every array, in order.
template <typename... Arrays>
size_t compact(const std::vector<uint8_t>& keep, Arrays&... arrays) {
  size_t n = 0;
  for (size_t i = 0; i < keep.size(); ++i) {
    if (!keep[i]) continue;
    if (n != i) ((arrays[n] = arrays[i]), ...);
    ++n;
  }
  (arrays.resize(n), ...);
  return n;
}

}  // namespace

// Emissive triangles with a power-proportional discrete distribution. The probability of each triangle is the
// exact probability that pick() returns it for a uniform number on rng_float's grid of 2^-24 steps, so NEE and
// the MIS weights of BSDF hits use the same number even for triangles too dim to be picked at all (probability
// 0: then only BSDF sampling finds them, with weight 1).
struct PathTracer::Emitters {
  std::vector<uint32_t> tris;
  std::vector<float> cdf;          // inclusive, last = 1
  std::vector<float> pmf_by_prim;  // probability of picking triangle prim (0 for non-emitters), sized per triangle
  std::vector<float> area_by_prim;
  bool empty() const { return tris.empty(); }

  explicit Emitters(const Scene& scene) {
    std::vector<double> power, area;
    for (uint32_t t : scene.emissive_tris) {
      const uint32_t* idx = &scene.indices[3 * static_cast<size_t>(t)];
      const Vec3 e1 = scene.positions[idx[1]] - scene.positions[idx[0]];
      const Vec3 e2 = scene.positions[idx[2]] - scene.positions[idx[0]];
      const double a = 0.5 * static_cast<double>(length(cross(e1, e2)));
      const double p = a * luminance(scene.materials[scene.tri_material[t]].emission);
      if (!(p > 0.0) || !std::isfinite(p)) continue;
      tris.push_back(t);
      power.push_back(p);
      area.push_back(a);
    }
    if (tris.empty()) return;
    pmf_by_prim.assign(scene.triangle_count(), 0.f);
    area_by_prim.assign(scene.triangle_count(), 0.f);
    const double total = std::accumulate(power.begin(), power.end(), 0.0);
    constexpr double kGrid = 16777216.0;  // rng_float's values are k / 2^24
    double run = 0, below = 0;            // below: grid points under the previous cdf entry
    cdf.resize(tris.size());
    for (size_t i = 0; i < tris.size(); ++i) {
      run += power[i];
      cdf[i] = i + 1 == tris.size() ? 1.f : static_cast<float>(run / total);
      const double upto = std::ceil(static_cast<double>(cdf[i]) * kGrid);
      pmf_by_prim[tris[i]] = static_cast<float>((upto - below) / kGrid);
      area_by_prim[tris[i]] = static_cast<float>(area[i]);
      below = upto;
    }
  }

  // The first triangle whose cdf entry exceeds u (u in [0, 1)).
  size_t pick(float u) const {
    const size_t i = static_cast<size_t>(std::upper_bound(cdf.begin(), cdf.end(), u) - cdf.begin());
    return std::min(i, tris.size() - 1);
  }
};

void RenderSettings::validate() const {
  if (width < 1 || width > 16384 || height < 1 || height > 16384)
    throw Error(fmt::format("resolution {}x{}: width and height must be in [1, 16384]", width, height));
  if (max_depth < 1 || max_depth > 64) throw Error(fmt::format("max depth {}: must be in [1, 64]", max_depth));
  if (rr_depth < 1 || rr_depth > 64) throw Error(fmt::format("roulette depth {}: must be in [1, 64]", rr_depth));
}

void FrameStats::add(const FrameStats& f) {
  wall_s += f.wall_s;
  trace_s += f.trace_s;
  gen_s += f.gen_s;
  primary_rays += f.primary_rays;
  secondary_rays += f.secondary_rays;
  bounce_rays += f.bounce_rays;
  shadow_rays += f.shadow_rays;
  non_finite += f.non_finite;
  merge_stats(generation, f.generation);
}

Vec3 sky_radiance(const Environment& env, Vec3 d) {
  if (!env.enabled) return Vec3(0.f);
  // +y is up (glTF); below the horizon the sky keeps the horizon colour (scenes close their floors).
  const float t = std::clamp(d.y, 0.f, 1.f);
  return env.sky_horizon * (1.f - t) + env.sky_zenith * t;
}

bool in_sun_cone(const Environment& env, Vec3 d) {
  return sun_on(env) && dot(d, env.sun_dir) >= env.sun_cos_half_angle;
}

Vec3 environment_radiance(const Environment& env, Vec3 d) {
  return sky_radiance(env, d) + (in_sun_cone(env, d) ? env.sun_radiance : Vec3(0.f));
}

PathTracer::PathTracer(const Scene& scene, Tracer& tracer, Generator& generator, const RenderSettings& settings)
    : scene_(scene), tracer_(tracer), generator_(generator), settings_(settings) {
  settings_.validate();
  primary_order_ = make_pixel_order(settings_.width, settings_.height, RayOrder::Tile, kPrimaryTile, kPrimaryTile);
  emitters_ = std::make_unique<Emitters>(scene);
}

PathTracer::~PathTracer() = default;

FrameStats PathTracer::render_frames(uint32_t first, int count, Accumulator& acc) {
  FrameStats total;
  for (int i = 0; i < count; ++i) total.add(render_frame(first + static_cast<uint32_t>(i), acc));
  return total;
}

FrameStats PathTracer::render_frame(uint32_t frame, Accumulator& acc) {
  RAYCOH_CHECK(acc.width() == settings_.width && acc.height() == settings_.height,
               fmt::format("accumulator {}x{} for a {}x{} render", acc.width(), acc.height(), settings_.width,
                           settings_.height));
  const auto t_frame = Clock::now();
  FrameStats st;
  const Scene& scene = scene_;
  const Environment& env = scene.env;
  const Emitters& emitters = *emitters_;
  const uint32_t seed = settings_.seed;
  const size_t npix = static_cast<size_t>(settings_.width) * static_cast<size_t>(settings_.height);
  std::vector<Vec3> radiance(npix, Vec3(0.f));
  std::vector<Hit> hits;

  auto trace = [&](const std::vector<Ray>& rays, uint64_t& counter) {
    hits.resize(rays.size());
    if (rays.empty()) return;
    const auto t0 = Clock::now();
    tracer_.trace(rays.data(), rays.size(), hits.data());
    st.trace_s += seconds_since(t0);
    counter += rays.size();
  };
  auto par = [](size_t n, auto&& body) {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1024), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i < r.end(); ++i) body(i);
    });
  };
  auto dim = [](int bounce, BounceDim k) { return kDimFirstFree + kDimsPerBounce * static_cast<uint32_t>(bounce) + k; };
  auto emission = [&](const ShadingPoint& sp) {
    return sp.cls == MaterialClass::Emissive && sp.front_face ? scene.materials[sp.material].emission : Vec3(0.f);
  };

  // 1. Camera rays.
  const PrimaryBatch primary =
      make_primary_rays(scene.camera, settings_.width, settings_.height, primary_order_, seed, frame, true);
  trace(primary.rays, st.primary_rays);
  const GBuffer gbuffer = make_gbuffer(scene, primary, hits);
  Vertices verts;
  for (size_t i = 0; i < primary.rays.size(); ++i) {
    const uint32_t p = primary.pixel[i];
    if (!hits[i].valid()) {
      radiance[p] = environment_radiance(env, primary.rays[i].dir);
      continue;
    }
    radiance[p] = emission(gbuffer.points[p]);
    verts.sp.push_back(gbuffer.points[p]);
    verts.pixel.push_back(p);
    verts.beta.push_back(Vec3(1.f));
    verts.mis.push_back(MisState{});
  }

  Wave wave;
  std::vector<uint8_t> keep;
  for (int bounce = 0; bounce < settings_.max_depth && verts.size() > 0; ++bounce) {
    const size_t nv = verts.size();

    // 2. Next-event estimation: slot 2i for an emitter, 2i + 1 for the sun.
    {
      Wave shadow;
      shadow.resize(2 * nv);
      std::vector<uint8_t> panes_left(2 * nv, static_cast<uint8_t>(std::min(255, settings_.max_depth - 1 - bounce)));
      keep.assign(2 * nv, 0);
      const bool sun = sun_on(env);
      const float sun_pdf = sun ? sun_cone_pdf(env) : 0.f;
      const float sun_one_minus_cos = 1.f - env.sun_cos_half_angle;
      const Frame sun_frame = make_frame(env.sun_dir);
      par(nv, [&](size_t i) {
        const ShadingPoint& sp = verts.sp[i];
        if (is_delta(sp.cls)) return;
        const uint32_t p = verts.pixel[i];
        const BsdfParams m = bsdf_params(scene.materials[sp.material]);
        auto light_ray = [&](size_t slot, Vec3 dir, float tmax, Vec3 radiance_over_pdf, float light_pdf) {
          const DirectionSample e = evaluate_direction(m, sp.ns, sp.ng, sp.wo, dir);
          if (!(max_component(e.weight) > 0.f) || !(e.pdf > 0.f)) return;
          const Vec3 f_cos = e.weight * e.pdf;
          shadow.beta[slot] = verts.beta[i] * f_cos * radiance_over_pdf * power_heuristic(light_pdf, e.pdf);
          Ray& r = shadow.rays.rays[slot];
          r.org = offset_ray_origin(sp.position, dot(dir, sp.ng) >= 0.f ? sp.ng : -sp.ng);
          r.dir = dir;
          r.tmin = 0.f;
          r.tmax = tmax;
          shadow.pixel[slot] = p;
          keep[slot] = 1;
        };
        if (!emitters.empty()) {
          const size_t k = emitters.pick(rng_float(seed, frame, p, dim(bounce, kEmitterPick)));
          const uint32_t t = emitters.tris[k];
          const uint32_t* idx = &scene.indices[3 * static_cast<size_t>(t)];
          const Vec3 v0 = scene.positions[idx[0]], v1 = scene.positions[idx[1]], v2 = scene.positions[idx[2]];
          const float su = std::sqrt(rng_float(seed, frame, p, dim(bounce, kEmitterU)));
          const float b1 = 1.f - su, b2 = rng_float(seed, frame, p, dim(bounce, kEmitterV)) * su;
          const Vec3 y = v0 * (1.f - b1 - b2) + v1 * b1 + v2 * b2;
          const Vec3 origin = offset_ray_origin(sp.position, dot(y - sp.position, sp.ng) >= 0.f ? sp.ng : -sp.ng);
          const Vec3 d = y - origin;
          const float dist2 = dot(d, d);
          const Vec3 ny = cross(v1 - v0, v2 - v0);
          const float area = emitters.area_by_prim[t];
          if (dist2 > 0.f && area > 0.f) {
            const float dist = std::sqrt(dist2);
            const Vec3 dir = d * (1.f / dist);
            const float cos_y = -dot(normalize(ny), dir);
            if (cos_y > 0.f) {
              const float pdf = emitters.pmf_by_prim[t] / area * dist2 / cos_y;
              const Vec3 le = scene.materials[scene.tri_material[t]].emission;
              light_ray(2 * i, dir, dist * (1.f - kShadowEpsilon), le * (1.f / pdf), pdf);
            }
          }
        }
        if (sun) {
          const float one_minus = rng_float(seed, frame, p, dim(bounce, kSunU)) * sun_one_minus_cos;
          const float cos_t = 1.f - one_minus, sin_t = std::sqrt(std::max(0.f, one_minus * (2.f - one_minus)));
          float s, c;
          sincos_turns(rng_float(seed, frame, p, dim(bounce, kSunV)), s, c);
          const Vec3 dir = normalize(sun_frame.to_world({sin_t * c, sin_t * s, cos_t}));
          light_ray(2 * i + 1, dir, __builtin_huge_valf(), env.sun_radiance * (1.f / sun_pdf), sun_pdf);
        }
      });
      compact(keep, shadow.rays.rays, shadow.pixel, shadow.beta, panes_left);
      // Rounds: unoccluded rays deliver their light; rays stopped by a thin pane go on behind it.
      while (!shadow.rays.rays.empty()) {
        trace(shadow.rays.rays, st.shadow_rays);
        const GBuffer panes = shade_hits(scene, shadow.rays, hits, frame);
        const size_t n = shadow.rays.rays.size();
        keep.assign(n, 0);
        par(n, [&](size_t j) {
          if (!hits[j].valid()) return;
          const ShadingPoint& sp = panes.points[j];
          const Material& m = scene.materials[sp.material];
          if (!is_thin_pane(m) || panes_left[j] == 0) return;
          Ray& r = shadow.rays.rays[j];
          r.tmax -= hits[j].t;
          if (!(r.tmax > 0.f)) return;
          r.org = offset_ray_origin(sp.position, -sp.ng);
          shadow.beta[j] = shadow.beta[j] * pane_transmittance(m, sp);
          --panes_left[j];
          keep[j] = max_component(shadow.beta[j]) > 0.f;
        });
        // Each pixel has at most two shadow rays, in adjacent slots: adding in batch order keeps the order fixed.
        for (size_t j = 0; j < n; ++j)
          if (!hits[j].valid()) radiance[shadow.pixel[j]] += shadow.beta[j];
        compact(keep, shadow.rays.rays, shadow.pixel, shadow.beta, panes_left);
      }
    }

    // 3. Directions leaving this bounce's vertices.
    if (bounce == 0) {
      RayBatch batch;
      const auto t_gen = Clock::now();
      generator_.generate(scene, gbuffer, seed, batch, st.generation);
      st.gen_s = seconds_since(t_gen);
      wave.resize(batch.size());
      wave.rays.rays = batch.rays;
      par(batch.size(), [&](size_t i) {
        wave.pixel[i] = batch.pixel[i];
        wave.beta[i] = batch.weight[i];
        // A camera ray arrived here, so a pass through a pane keeps the camera's state (delta: weight 1).
        const bool pass = is_thin_pane(scene.materials[gbuffer.points[batch.pixel[i]].material]) &&
                          dot(batch.rays[i].dir, gbuffer.points[batch.pixel[i]].ng) < 0.f;
        wave.mis[i] = pass ? MisState{} : MisState{batch.pdf[i], is_delta(batch.material[i]), 0.f};
      });
    } else {
      wave.resize(nv);
      keep.assign(nv, 0);
      const bool roulette = bounce >= settings_.rr_depth;
      par(nv, [&](size_t i) {
        const ShadingPoint& sp = verts.sp[i];
        const uint32_t p = verts.pixel[i];
        const DirectionSample s = sample_direction(bsdf_params(scene.materials[sp.material]), sp.ns, sp.ng, sp.wo,
                                                   sp.front_face, rng_float(seed, frame, p, dim(bounce, kDirU)),
                                                   rng_float(seed, frame, p, dim(bounce, kDirV)),
                                                   rng_float(seed, frame, p, dim(bounce, kLobe)));
        Vec3 beta = verts.beta[i] * s.weight;
        if (!(max_component(beta) > 0.f)) return;
        if (roulette) {
          const float survive = std::min(1.f, max_component(beta));
          if (rng_float(seed, frame, p, dim(bounce, kRoulette)) >= survive) return;
          beta = beta * (1.f / survive);
        }
        Ray& r = wave.rays.rays[i];
        r.org = offset_ray_origin(sp.position, dot(s.dir, sp.ng) >= 0.f ? sp.ng : -sp.ng);
        r.dir = s.dir;
        r.tmin = 0.f;
        r.tmax = __builtin_huge_valf();
        wave.pixel[i] = p;
        wave.beta[i] = beta;
        const bool pass = (s.flags & kSampleTransmitted) != 0 && is_thin_pane(scene.materials[sp.material]);
        wave.mis[i] = pass ? verts.mis[i] : MisState{s.pdf, is_delta(sp.cls), 0.f};
        keep[i] = 1;
      });
      compact(keep, wave.rays.rays, wave.pixel, wave.beta, wave.mis);
    }

    // 4. Trace; light found by the BSDF rays; the hits become the next bounce's vertices.
    const size_t nr = wave.rays.rays.size();
    trace(wave.rays.rays, bounce == 0 ? st.secondary_rays : st.bounce_rays);
    const GBuffer next = shade_hits(scene, wave.rays, hits, frame);
    const bool last = bounce + 1 >= settings_.max_depth;
    keep.assign(nr, 0);
    par(nr, [&](size_t i) {
      const Vec3 beta = wave.beta[i];
      if (!(max_component(beta) > 0.f)) return;
      const Vec3 dir = wave.rays.rays[i].dir;
      Vec3 light(0.f);
      if (!hits[i].valid()) {
        light = sky_radiance(env, dir);
        if (in_sun_cone(env, dir))
          light += env.sun_radiance * (wave.mis[i].delta ? 1.f : power_heuristic(wave.mis[i].pdf, sun_cone_pdf(env)));
      } else {
        const ShadingPoint& sp = next.points[i];
        const Vec3 le = emission(sp);
        if (max_component(le) > 0.f) {
          float w = 1.f;
          const MisState& mis = wave.mis[i];
          if (!mis.delta && !emitters.empty() && emitters.pmf_by_prim[sp.prim] > 0.f) {
            const float cos_y = dot(sp.ng, sp.wo), dist = mis.dist + hits[i].t;
            const float light_pdf =
                emitters.pmf_by_prim[sp.prim] / emitters.area_by_prim[sp.prim] * dist * dist / cos_y;
            w = power_heuristic(mis.pdf, light_pdf);
          }
          light = le * w;
        }
        keep[i] = !last;
      }
      radiance[wave.pixel[i]] += beta * light;
    });
    verts.sp.resize(nr);
    verts.pixel = wave.pixel;
    verts.beta = wave.beta;
    verts.mis.resize(nr);
    par(nr, [&](size_t i) {
      verts.sp[i] = next.points[i];
      verts.mis[i] = wave.mis[i];
      verts.mis[i].dist += hits[i].t;
    });
    compact(keep, verts.sp, verts.pixel, verts.beta, verts.mis);
  }

  // 6. Accumulate; NaN/Inf samples are counted, not added.
  const uint64_t before = acc.non_finite_samples();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, npix, 4096), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t p = r.begin(); p < r.end(); ++p) acc.add(p, radiance[p]);
  });
  st.non_finite = acc.non_finite_samples() - before;
  st.wall_s = seconds_since(t_frame);
  return st;
}

}  // namespace raycoh

// A scene's shading data uploaded once (cuda/device_scene_shading.h). Host code only: the kernels that read it are
// cuda/device_shading.cu's.
#include <cuda_runtime.h>

#include <vector>

#include "core/error.h"
#include "cuda/cuda_check.cuh"
#include "cuda/device_gbuffer.h"
#include "cuda/device_scene_shading.h"
#include "generators/generator.h"

namespace raycoh::cuda {

struct DeviceSceneShading::Impl {
  explicit Impl(const Scene& scene) : mesh(scene) {}
  DeviceMesh mesh;  // what hit_surface reads: triangles, normals, materials' classes, surface textures
  DeviceBuffer<Vec3> emission;
  DeviceBuffer<uint32_t> emitter_tris;
  DeviceBuffer<BsdfParams> bsdf;
  DeviceBuffer<float> emitter_cdf, pmf_by_prim, area_by_prim, light_cdf, light_pmf;
  DeviceBuffer<PunctualLightView> lights;
  ShadingSceneView view;
};

namespace {

template <class T>
void upload(DeviceBuffer<T>& buffer, const std::vector<T>& host) {
  buffer.upload(host.data(), host.size());
}

// The emissive triangles' and punctual lights' distributions of host_lights.
void upload_lights(DeviceSceneShading::Impl& d, const LightsView& host, size_t triangles, LightsView& out) {
  out.count = host.count;
  if (host.count > 0) {
    d.emitter_tris.upload(host.tris, host.count);
    d.emitter_cdf.upload(host.cdf, host.count);
    d.pmf_by_prim.upload(host.pmf_by_prim, triangles);
    d.area_by_prim.upload(host.area_by_prim, triangles);
    out.tris = d.emitter_tris.get();
    out.cdf = d.emitter_cdf.get();
    out.pmf_by_prim = d.pmf_by_prim.get();
    out.area_by_prim = d.area_by_prim.get();
  }
  out.light_count = host.light_count;
  if (host.light_count > 0) {
    d.light_cdf.upload(host.light_cdf, host.light_count);
    d.light_pmf.upload(host.light_pmf, host.light_count);
    d.lights.upload(host.lights, host.light_count);
    out.light_cdf = d.light_cdf.get();
    out.light_pmf = d.light_pmf.get();
    out.lights = d.lights.get();
  }
}

}  // namespace

DeviceSceneShading::DeviceSceneShading(const Scene& scene, const LightsView& host_lights)
    : impl_(std::make_unique<Impl>(scene)) {
  Impl& d = *impl_;
  std::vector<BsdfParams> bsdf;
  std::vector<Vec3> emission;
  for (const Material& m : scene.materials) {
    bsdf.push_back(bsdf_params(m));
    emission.push_back(m.emission);
  }
  upload(d.bsdf, bsdf);
  upload(d.emission, emission);
  ShadingSceneView& v = d.view;
  v.mesh = d.mesh.view();
  v.bsdf = d.bsdf.get();
  v.emission = d.emission.get();
  v.lights.mesh = v.mesh;
  v.lights.material_emission = d.emission.get();
  upload_lights(d, host_lights, scene.triangle_count(), v.lights);
  v.env = scene.env;
  v.sun = SunSampler(scene.env);
}

DeviceSceneShading::~DeviceSceneShading() = default;

const ShadingSceneView& DeviceSceneShading::view() const { return impl_->view; }

}  // namespace raycoh::cuda

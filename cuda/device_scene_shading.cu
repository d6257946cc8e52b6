// A scene's shading data uploaded once (cuda/device_scene_shading.h). Host code only: the kernels that read it are
// cuda/device_shading.cu's.
#include <cuda_runtime.h>

#include <vector>

#include "core/error.h"
#include "cuda/cuda_check.cuh"
#include "cuda/device_scene_shading.h"
#include "generators/generator.h"

namespace raycoh::cuda {

struct DeviceSceneShading::Impl {
  DeviceBuffer<Vec3> positions, normals, emission;
  DeviceBuffer<uint32_t> indices, tri_material, tex_tri_material, emitter_tris;
  DeviceBuffer<MaterialClass> classes;
  DeviceBuffer<BsdfParams> bsdf;
  DeviceBuffer<float> tex_uv, tex_tangent, emitter_cdf, pmf_by_prim, area_by_prim, light_cdf, light_pmf;
  DeviceBuffer<TexturedMaterial> tex_materials;
  DeviceBuffer<SurfaceTexture> textures;
  DeviceBuffer<uint8_t> texels;
  DeviceBuffer<PunctualLightView> lights;
  ShadingSceneView view;
};

namespace {

template <class T>
void upload(DeviceBuffer<T>& buffer, const std::vector<T>& host) {
  buffer.upload(host.data(), host.size());
}

// The surface textures (only when the scene has them).
void upload_textures(DeviceSceneShading::Impl& d, const Scene& scene, MeshView& mesh) {
  mesh.textured = !scene.textures.empty();
  if (!mesh.textured) return;
  const SurfaceTextures& t = scene.textures;
  RAYCOH_CHECK(t.tri_material.size() == scene.triangle_count() && t.tri_uv.size() == 12 * t.tri_material.size() &&
                   t.tri_tangent.size() == 4 * t.tri_material.size(),
               "surface texture arrays do not match the scene's triangles");
  upload(d.tex_tri_material, t.tri_material);
  upload(d.tex_uv, t.tri_uv);
  upload(d.tex_tangent, t.tri_tangent);
  upload(d.tex_materials, t.materials);
  upload(d.textures, t.textures);
  upload(d.texels, t.texels);
  mesh.textures = {d.tex_tri_material.get(), d.tex_uv.get(),   d.tex_tangent.get(),
                   d.tex_materials.get(),    d.textures.get(), d.texels.get()};
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
    : impl_(std::make_unique<Impl>()) {
  Impl& d = *impl_;
  RAYCOH_CHECK(scene.normals.size() == scene.positions.size() && scene.tri_material.size() == scene.triangle_count(),
               "scene arrays do not match");
  std::vector<MaterialClass> classes;
  std::vector<BsdfParams> bsdf;
  std::vector<Vec3> emission;
  for (const Material& m : scene.materials) {
    classes.push_back(m.cls);
    bsdf.push_back(bsdf_params(m));
    emission.push_back(m.emission);
  }
  upload(d.positions, scene.positions);
  upload(d.normals, scene.normals);
  upload(d.indices, scene.indices);
  upload(d.tri_material, scene.tri_material);
  upload(d.classes, classes);
  upload(d.bsdf, bsdf);
  upload(d.emission, emission);
  ShadingSceneView& v = d.view;
  v.mesh.positions = d.positions.get();
  v.mesh.normals = d.normals.get();
  v.mesh.indices = d.indices.get();
  v.mesh.tri_material = d.tri_material.get();
  v.mesh.material_cls = d.classes.get();
  upload_textures(d, scene, v.mesh);
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

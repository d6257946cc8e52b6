// A scene's shading data on the device, uploaded once (cuda/device_scene_shading.cu; plain C++ header): triangles,
// per-vertex normals and each triangle's material (core/hit_surface.h MeshView), the scene materials' BSDF
// parameters, emission and class, the surface textures (core/surface_textures.h), the light distributions that
// next-event estimation samples (core/light_sampling.h LightsView: emissive triangles and punctual lights) and the
// environment with its sun sampler. The device path tracer (cuda/device_path_tracer.h) shades with it through the
// same host/device functions as the CPU path tracer.
//
// The light distributions are built on the host (shading/emitters.h EmitterDistribution, above this layer) and
// handed over as a LightsView of host arrays; this class copies every array it points to. Throws raycoh::Error on
// any CUDA error.
#pragma once

#include <memory>

#include "core/environment_light.h"
#include "core/hit_surface.h"
#include "core/light_sampling.h"
#include "core/material.h"
#include "scenes/scene.h"

namespace raycoh::cuda {

// Device pointers of one scene's shading data, passed to kernels by value.
struct ShadingSceneView {
  MeshView mesh{};
  const BsdfParams* bsdf = nullptr;  // per scene material (generators/generator.h bsdf_params)
  const Vec3* emission = nullptr;    // per scene material
  LightsView lights{};
  Environment env{};
  SunSampler sun{};
};

class DeviceSceneShading {
 public:
  // host_lights: EmitterDistribution(scene).view(scene) (or an equal view); read only during the constructor.
  DeviceSceneShading(const Scene& scene, const LightsView& host_lights);
  ~DeviceSceneShading();
  DeviceSceneShading(const DeviceSceneShading&) = delete;
  DeviceSceneShading& operator=(const DeviceSceneShading&) = delete;
  const ShadingSceneView& view() const;

  struct Impl;  // public: the upload helpers of the .cu fill it

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace raycoh::cuda

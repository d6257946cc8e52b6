// The camera pass's G-buffer made on the device (cuda/device_gbuffer.cu; plain C++ header), so that the device
// path tracer (cuda/device_path_tracer.h) and the device pipeline (cuda/device_pipeline.h) keep it there: from the
// camera rays, their pixels and their hits on the device, one thread per ray calls core/hit_surface.h hit_surface,
// the function make_gbuffer (generators/primary.h) calls per hit on the host, and writes its pixel's ShadingPoint
// and, in a scene with surface textures, its pixel's slot of the material table, laid out as make_gbuffer's
// HitMaterials: the scene's materials (entries [0, scene_count)), then one slot per pixel (scene_count + pixel:
// the texel's BSDF and emission on a textured hit, default entries elsewhere). A warp-aggregated atomic counts the
// hit pixels (GBuffer::hits). For the same rays and hits it equals make_gbuffer bit for bit, points and table
// (tests/gpu_gbuffer_test.cpp): both sides compile without floating-point contraction (CMakeLists.txt:
// --fmad=false for nvcc, -ffp-contract=off for g++) and the same IEEE division and square root.
//
// Every launch is queued on the default stream and waits for nothing; finish() waits for the hit count (4 bytes,
// the one value the host needs: the generator sizes its batch with it). Throws raycoh::Error on any CUDA error.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/hit_surface.h"
#include "core/material.h"
#include "core/ray.h"
#include "core/ray_batch.h"
#include "generators/primary.h"
#include "scenes/scene.h"

namespace raycoh::cuda {

// A G-buffer on the device (device pointers; passed by value).
struct DeviceGBufferView {
  int width = 0, height = 0;
  uint32_t frame = 0;
  const ShadingPoint* points = nullptr;  // width x height, pixel order (y * width + x)
  const BsdfParams* bsdf = nullptr;      // the material table (HitMaterials' layout)
  const Vec3* emission = nullptr;        // per table entry: radiance its front face emits
  size_t scene_count = 0;                // the scene's materials, first in the table
  bool per_hit = false;                  // the table has one slot per pixel after them (a textured scene)
  size_t hits = 0;                       // valid points; set by DeviceGBuffer::finish()
  size_t pixels() const { return static_cast<size_t>(width) * static_cast<size_t>(height); }
  size_t table_size() const { return scene_count + (per_hit ? pixels() : 0); }
};

// The scene's arrays that hit_surface reads (core/hit_surface.h MeshView: triangles, normals, each triangle's
// material and the materials' classes, the surface textures), uploaded once.
class DeviceMesh {
 public:
  explicit DeviceMesh(const Scene& scene);
  ~DeviceMesh();
  DeviceMesh(const DeviceMesh&) = delete;
  DeviceMesh& operator=(const DeviceMesh&) = delete;
  const MeshView& view() const;  // device pointers

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

class DeviceGBuffer {
 public:
  // mesh: scene's MeshView on the device (DeviceMesh::view, or cuda/device_scene_shading.h's view().mesh); its
  // arrays outlive this object. The scene's part of the material table is uploaded here, once.
  DeviceGBuffer(const Scene& scene, const MeshView& device_mesh);
  ~DeviceGBuffer();
  DeviceGBuffer(const DeviceGBuffer&) = delete;
  DeviceGBuffer& operator=(const DeviceGBuffer&) = delete;

  // Queues the G-buffer kernel for n = width x height camera rays, one per pixel (d_pixels a permutation of the
  // pixels), and their hits (device arrays). view() is valid from here, its hit count after finish().
  void launch(const Ray* d_rays, const uint32_t* d_pixels, const Hit* d_hits, size_t n, int width, int height,
              uint32_t frame);
  // Waits for the hit count and returns the view with it.
  const DeviceGBufferView& finish();
  const DeviceGBufferView& view() const;
  // The finished G-buffer downloaded, with its material table: make_gbuffer's GBuffer.
  GBuffer download() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The device G-buffer of host rays and hits (uploaded, made, downloaded): equal to make_gbuffer(scene, primary,
// hits) bit for bit. For the tests; primary.rays must hold one ray per pixel.
GBuffer make_gbuffer_gpu(const Scene& scene, const PixelRays& primary, const std::vector<Hit>& hits);

}  // namespace raycoh::cuda

// The camera pass's G-buffer on the device (cuda/device_gbuffer.h): one thread per camera ray, hit_surface as in
// make_gbuffer (generators/primary.cpp), the hit count by warp ballots and one atomic per warp.
#include <cuda_runtime.h>

#include "core/error.h"
#include "cuda/cuda_check.cuh"
#include "cuda/device_common.cuh"
#include "cuda/device_gbuffer.h"
#include "generators/generator.h"

namespace raycoh::cuda {

namespace {

constexpr int kBlock = 256;

// Ray i's pixel gets make_gbuffer's point and (per_hit) table slot: the hit's surface, or the defaults of a miss.
__global__ void gbuffer_kernel(MeshView mesh, const Ray* rays, const uint32_t* pixels, const Hit* hits, size_t n,
                               uint32_t scene_count, bool per_hit, ShadingPoint* points, BsdfParams* bsdf,
                               Vec3* emission, unsigned long long* count) {
  const size_t i = blockIdx.x * static_cast<size_t>(blockDim.x) + threadIdx.x;
  bool valid = false;
  if (i < n) {
    const uint32_t p = pixels[i];
    const Hit h = hits[i];
    ShadingPoint sp{};
    BsdfParams b{};
    Vec3 e{};
    if (h.valid()) {
      const HitSurface surface = hit_surface(mesh, rays[i], h);
      sp = surface.point;
      if (surface.textured) {
        b = surface.bsdf;
        e = surface.emission;
        sp.material = scene_count + p;
      }
    }
    valid = sp.valid();
    store_point(points, p, sp);  // four 16-byte stores (core/shading_point.h)
    if (per_hit) {
      bsdf[scene_count + p] = b;
      emission[scene_count + p] = e;
    }
  }
  const unsigned bits = __ballot_sync(kFullMask, valid);
  if ((threadIdx.x & 31u) == 0 && bits != 0) atomicAdd(count, static_cast<unsigned long long>(__popc(bits)));
}

template <class T>
void upload(DeviceBuffer<T>& buffer, const std::vector<T>& host) {
  buffer.upload(host.data(), host.size());
}

}  // namespace

struct DeviceMesh::Impl {
  DeviceBuffer<Vec3> positions, normals;
  DeviceBuffer<uint32_t> indices, tri_material, tex_tri_material;
  DeviceBuffer<MaterialClass> classes;
  DeviceBuffer<float> tex_uv, tex_tangent;
  DeviceBuffer<TexturedMaterial> tex_materials;
  DeviceBuffer<SurfaceTexture> textures;
  DeviceBuffer<uint8_t> texels;
  MeshView view;
};

DeviceMesh::DeviceMesh(const Scene& scene) : impl_(std::make_unique<Impl>()) {
  Impl& d = *impl_;
  RAYCOH_CHECK(scene.normals.size() == scene.positions.size() && scene.tri_material.size() == scene.triangle_count(),
               "scene arrays do not match");
  std::vector<MaterialClass> classes;
  for (const Material& m : scene.materials) classes.push_back(m.cls);
  upload(d.positions, scene.positions);
  upload(d.normals, scene.normals);
  upload(d.indices, scene.indices);
  upload(d.tri_material, scene.tri_material);
  upload(d.classes, classes);
  MeshView& v = d.view;
  v.positions = d.positions.get();
  v.normals = d.normals.get();
  v.indices = d.indices.get();
  v.tri_material = d.tri_material.get();
  v.material_cls = d.classes.get();
  v.textured = !scene.textures.empty();
  if (!v.textured) return;
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
  v.textures = {d.tex_tri_material.get(), d.tex_uv.get(),   d.tex_tangent.get(),
                d.tex_materials.get(),    d.textures.get(), d.texels.get()};
}

DeviceMesh::~DeviceMesh() = default;

const MeshView& DeviceMesh::view() const { return impl_->view; }

struct DeviceGBuffer::Impl {
  MeshView mesh;
  DeviceBuffer<ShadingPoint> points;
  DeviceBuffer<BsdfParams> bsdf;  // the table: scene materials, then one slot per pixel (textured scenes)
  DeviceBuffer<Vec3> emission;
  DeviceBuffer<unsigned long long> count{1};
  std::vector<BsdfParams> scene_bsdf;
  std::vector<Vec3> scene_emission;
  DeviceGBufferView view;
  bool launched = false, finished = false;
};

DeviceGBuffer::DeviceGBuffer(const Scene& scene, const MeshView& device_mesh) : impl_(std::make_unique<Impl>()) {
  Impl& d = *impl_;
  d.mesh = device_mesh;
  for (const Material& m : scene.materials) {
    d.scene_bsdf.push_back(bsdf_params(m));
    d.scene_emission.push_back(m.emission);
  }
  d.view.scene_count = scene.materials.size();
  d.view.per_hit = device_mesh.textured;
  upload(d.bsdf, d.scene_bsdf);
  upload(d.emission, d.scene_emission);
}

DeviceGBuffer::~DeviceGBuffer() = default;

void DeviceGBuffer::launch(const Ray* d_rays, const uint32_t* d_pixels, const Hit* d_hits, size_t n, int width,
                           int height, uint32_t frame) {
  Impl& d = *impl_;
  DeviceGBufferView& v = d.view;
  RAYCOH_CHECK(width > 0 && height > 0 && n == static_cast<size_t>(width) * static_cast<size_t>(height),
               "device G-buffer: one camera ray per pixel");
  if (v.per_hit && (v.width != width || v.height != height)) {
    // The table grows with the resolution; growing drops its contents, so the scene's part goes up again.
    d.bsdf.reserve(v.scene_count + n);
    d.emission.reserve(v.scene_count + n);
    d.bsdf.upload(d.scene_bsdf.data(), v.scene_count);
    d.emission.upload(d.scene_emission.data(), v.scene_count);
  }
  d.points.reserve(n);
  v.width = width;
  v.height = height;
  v.frame = frame;
  v.hits = 0;
  v.points = d.points.get();
  v.bsdf = d.bsdf.get();
  v.emission = d.emission.get();
  d.count.zero(1);
  gbuffer_kernel<<<blocks_for(n, kBlock), kBlock>>>(d.mesh, d_rays, d_pixels, d_hits, n,
                                                    static_cast<uint32_t>(v.scene_count), v.per_hit, d.points.get(),
                                                    d.bsdf.get(), d.emission.get(), d.count.get());
  RAYCOH_CUDA_CHECK_LAUNCH();
  d.launched = true;
  d.finished = false;
}

const DeviceGBufferView& DeviceGBuffer::finish() {
  Impl& d = *impl_;
  if (!d.launched) throw Error("cuda: DeviceGBuffer::finish before launch");
  unsigned long long hits = 0;
  d.count.download(&hits, 1);
  d.view.hits = static_cast<size_t>(hits);
  d.finished = true;
  return d.view;
}

const DeviceGBufferView& DeviceGBuffer::view() const { return impl_->view; }

GBuffer DeviceGBuffer::download() const {
  const Impl& d = *impl_;
  if (!d.finished) throw Error("cuda: DeviceGBuffer::download before finish");
  const DeviceGBufferView& v = d.view;
  GBuffer g;
  g.width = v.width;
  g.height = v.height;
  g.frame = v.frame;
  g.hits = v.hits;
  g.points.resize(v.pixels());
  d.points.download(g.points.data(), g.points.size());
  auto table = std::make_shared<HitMaterials>();
  table->scene_count = v.scene_count;
  table->bsdf.resize(v.table_size());
  table->emission.resize(v.table_size());
  d.bsdf.download(table->bsdf.data(), table->bsdf.size());
  d.emission.download(table->emission.data(), table->emission.size());
  g.materials = std::move(table);
  return g;
}

GBuffer make_gbuffer_gpu(const Scene& scene, const PixelRays& primary, const std::vector<Hit>& hits) {
  const size_t n = primary.rays.size();
  RAYCOH_CHECK(primary.pixel.size() == n && hits.size() == n, "make_gbuffer_gpu: one pixel and hit per ray");
  DeviceMesh mesh(scene);
  DeviceGBuffer gbuffer(scene, mesh.view());
  DeviceBuffer<Ray> rays;
  DeviceBuffer<uint32_t> pixels;
  DeviceBuffer<Hit> device_hits;
  rays.upload(primary.rays.data(), n);
  pixels.upload(primary.pixel.data(), n);
  device_hits.upload(hits.data(), n);
  gbuffer.launch(rays.get(), pixels.get(), device_hits.get(), n, primary.width, primary.height, primary.frame);
  gbuffer.finish();
  return gbuffer.download();
}

}  // namespace raycoh::cuda

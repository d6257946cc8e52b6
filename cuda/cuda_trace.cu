// One-thread-per-ray closest-hit kernel over the shared BVH2 layout, using core/traverse.h unchanged.
// (No fmt here: its consteval format strings do not compile under nvcc 13.)
#include "cuda/cuda_trace.h"

#include <cuda_runtime.h>
#include <string>

#include "core/error.h"
#include "core/traverse.h"

namespace raycoh::cuda {

namespace {

void check(cudaError_t err, const char* what) {
  if (err != cudaSuccess) throw Error(std::string("CUDA error in ") + what + ": " + cudaGetErrorString(err));
}
#define RAYCOH_CUDA_CHECK(call) check((call), #call)

template <class T>
struct DeviceArray {
  T* ptr = nullptr;
  explicit DeviceArray(size_t n) { RAYCOH_CUDA_CHECK(cudaMalloc(&ptr, sizeof(T) * (n ? n : 1))); }
  ~DeviceArray() { cudaFree(ptr); }
  DeviceArray(const DeviceArray&) = delete;
  DeviceArray& operator=(const DeviceArray&) = delete;
};

__global__ void closest_hit_kernel(BvhView bvh, const Ray* rays, size_t count, Hit* hits) {
  const size_t i = blockIdx.x * static_cast<size_t>(blockDim.x) + threadIdx.x;
  if (i >= count) return;
  hits[i] = closest_hit(bvh, rays[i]);
}

}  // namespace

int device_count() {
  int n = 0;
  if (cudaGetDeviceCount(&n) != cudaSuccess) {
    cudaGetLastError();  // clear the sticky "no device" error
    return 0;
  }
  return n;
}

std::string device_name() {
  if (device_count() == 0) return "";
  cudaDeviceProp prop{};
  if (cudaGetDeviceProperties(&prop, 0) != cudaSuccess) return "";
  return std::string(prop.name) + " (sm_" + std::to_string(prop.major) + std::to_string(prop.minor) + ", " +
         std::to_string(prop.multiProcessorCount) + " SMs)";
}

void trace_closest(const BvhView& bvh, const Ray* rays, size_t count, Hit* hits, float* kernel_ms) {
  DeviceArray<BvhNode> d_nodes(bvh.node_count);
  DeviceArray<BvhTriangle> d_tris(bvh.tri_count);
  DeviceArray<Ray> d_rays(count);
  DeviceArray<Hit> d_hits(count);
  RAYCOH_CUDA_CHECK(cudaMemcpy(d_nodes.ptr, bvh.nodes, sizeof(BvhNode) * bvh.node_count, cudaMemcpyHostToDevice));
  RAYCOH_CUDA_CHECK(cudaMemcpy(d_tris.ptr, bvh.tris, sizeof(BvhTriangle) * bvh.tri_count, cudaMemcpyHostToDevice));
  RAYCOH_CUDA_CHECK(cudaMemcpy(d_rays.ptr, rays, sizeof(Ray) * count, cudaMemcpyHostToDevice));
  BvhView dview{d_nodes.ptr, d_tris.ptr, bvh.node_count, bvh.tri_count};
  cudaEvent_t start, stop;
  RAYCOH_CUDA_CHECK(cudaEventCreate(&start));
  RAYCOH_CUDA_CHECK(cudaEventCreate(&stop));
  const int block = 128;
  const unsigned grid = static_cast<unsigned>((count + block - 1) / block);
  RAYCOH_CUDA_CHECK(cudaEventRecord(start));
  if (count > 0) closest_hit_kernel<<<grid, block>>>(dview, d_rays.ptr, count, d_hits.ptr);
  RAYCOH_CUDA_CHECK(cudaGetLastError());
  RAYCOH_CUDA_CHECK(cudaEventRecord(stop));
  RAYCOH_CUDA_CHECK(cudaEventSynchronize(stop));
  float ms = 0.f;
  RAYCOH_CUDA_CHECK(cudaEventElapsedTime(&ms, start, stop));
  if (kernel_ms) *kernel_ms = ms;
  cudaEventDestroy(start);
  cudaEventDestroy(stop);
  RAYCOH_CUDA_CHECK(cudaMemcpy(hits, d_hits.ptr, sizeof(Hit) * count, cudaMemcpyDeviceToHost));
}

}  // namespace raycoh::cuda

// glTF textures deciding materials. Two uses of the same decoded textures (TEXCOORD_0/1, KHR_texture_transform,
// the sampler's wrap modes, bilinear):
// - Per hit (Scene::textures, core/surface_textures.h): every triangle of a material with a decoded base colour,
//   metallic-roughness, emissive, transmission or normal texture keeps its texture coordinates and its
//   material's textures, and the G-buffer looks the texels up at each hit: a shading point's BSDF parameters,
//   emission, class and normal are those of the texel it hit. Emitter sampling weighs each triangle by the mean
//   of its emissive texels (sampled at a density that follows the triangle's texel footprint) times its area.
// - Per triangle: the textures are also sampled at 16 points spread over each triangle (the centroids of its 16
//   sub-triangles after two midpoint subdivisions), and the mean of those texels times the factors becomes the
//   triangle's material (triangles with equal quantised values share one derived material). That average is
//   what `scenes info` counts per class, and what the scene's material table says; shading reads the per-hit
//   values.
// Alpha MASK: a triangle of a MASK material with a base-colour texture keeps its texture coordinates and the
// texture's alpha in Scene::alpha, and the tracers test every candidate hit against alphaCutoff (any-hit, per
// texel: core/alpha_mask.h); its derived material is the mean of its opaque samples only (of all 16 if none is). A
// MASK material without a texture has one alpha: below the cutoff its triangles are removed whole. BLEND is
// traced as opaque. Occlusion maps are not read; the TANGENT attribute is not read (normal maps use the tangent
// from each triangle's UV derivatives). Part of the glTF loader, the one adapter for tinygltf.
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

#include "scenes/gltf_reader.h"
#include "scenes/gltf_texture_sampling.h"

namespace raycoh::gltf {

void GltfReader::triangle_tangent(const SurfaceTexture& tex, const uint32_t* idx, const float* corner_uv,
                                  float* out) const {
  // The normal texture's coordinates at the corners, through its transform.
  float u[3], v[3];
  for (int k = 0; k < 3; ++k) {
    const float* c = corner_uv + 6 * tex.texcoord + 2 * k;
    texture_uv(tex, c[0], c[1], u[k], v[k]);
  }
  const Vec3 p0 = scene_.positions[idx[0]];
  const Vec3 e1 = scene_.positions[idx[1]] - p0, e2 = scene_.positions[idx[2]] - p0;
  const float du1 = u[1] - u[0], dv1 = v[1] - v[0], du2 = u[2] - u[0], dv2 = v[2] - v[0];
  const float det = du1 * dv2 - du2 * dv1;
  if (!(std::fabs(det) > 0.f) || !std::isfinite(det)) return;  // no UV frame: the map is not applied
  const float inv = 1.f / det;
  const Vec3 dpdu = (e1 * dv2 - e2 * dv1) * inv;
  const Vec3 dpdv = (e2 * du1 - e1 * du2) * inv;
  const float len = length(dpdu);
  if (!(len > 0.f) || !std::isfinite(len)) return;
  const Vec3 t = dpdu * (1.f / len);
  // glTF's v points down the image and normal maps' +Y up it: the bitangent is -dP/dv.
  const Vec3 n = cross(e1, e2);
  const float sign = dot(cross(n, t), -dpdv) < 0.f ? -1.f : 1.f;
  out[0] = t.x, out[1] = t.y, out[2] = t.z, out[3] = sign;
}

void GltfReader::emitter_means() {
  SurfaceTextures& st = scene_.textures;
  const bool any = std::any_of(st.materials.begin(), st.materials.end(), [](const TexturedMaterial& m) {
    return m.emissive != kNoTexture && max_component(m.emission) > 0.f;
  });
  if (!any) return;
  const SurfaceTexturesView view = st.view();
  st.tri_emission.assign(st.tri_material.size(), Vec3(0.f));
  for (size_t t = 0; t < st.tri_material.size(); ++t) {
    if (st.tri_material[t] == kNoTexture) continue;
    const TexturedMaterial& m = st.materials[st.tri_material[t]];
    if (m.emissive == kNoTexture || !(max_component(m.emission) > 0.f)) continue;
    // As many samples as the triangle covers texels (its area in the emissive texture), 16 to 4096.
    const SurfaceTexture& tex = st.textures[m.emissive];
    const float* c = &st.tri_uv[12 * t + 6 * tex.texcoord];
    float u[3], v[3];
    for (int k = 0; k < 3; ++k) texture_uv(tex, c[2 * k], c[2 * k + 1], u[k], v[k]);
    const double texels =
        0.5 * std::fabs((u[1] - u[0]) * (v[2] - v[0]) - (u[2] - u[0]) * (v[1] - v[0])) * tex.width * tex.height;
    const int n = static_cast<int>(std::clamp(std::ceil(std::sqrt(std::isfinite(texels) ? texels : 0.0)), 4.0, 64.0));
    double sum[3] = {0, 0, 0};
    for_subtriangle_centroids(n, [&](float b1, float b2) {
      float uv[2][2];
      hit_uv(view, static_cast<uint32_t>(t), b1, b2, uv);
      const Vec3 e = emission_of(view, m, uv);
      for (int k = 0; k < 3; ++k) sum[k] += e[k];
    });
    const double inv = 1.0 / (static_cast<double>(n) * n);
    st.tri_emission[t] =
        Vec3{static_cast<float>(sum[0] * inv), static_cast<float>(sum[1] * inv), static_cast<float>(sum[2] * inv)};
  }
}

void GltfReader::append_texcoords(const tinygltf::Primitive& prim, const std::string& where, size_t count) {
  for (int set = 0; set < 2; ++set) {
    std::vector<float>& uv = uv_[set];
    const auto it = prim.attributes.find(set == 0 ? "TEXCOORD_0" : "TEXCOORD_1");
    if (it == prim.attributes.end()) {
      uv.resize(uv.size() + 2 * count, 0.f);
      continue;
    }
    const std::vector<float> t =
        read_floats(it->second, TINYGLTF_TYPE_VEC2, fmt::format("TEXCOORD_{} of {}", set, where));
    if (t.size() != 2 * count)
      fail(fmt::format("{} has {} TEXCOORD_{} values for {} positions", where, t.size() / 2, set, count));
    uv.insert(uv.end(), t.begin(), t.end());
  }
}

namespace {

// The decoded textures of every material, and how many materials have some.
struct DecodedTextures {
  std::vector<MaterialTextures> of;  // per material
  size_t textured = 0;               // with a decoded texture that decides its material
  size_t normal_mapped = 0;          // with only a decoded normal map
  size_t referenced = 0;             // that reference a texture, decoded or not
};

DecodedTextures decode_textures(const tinygltf::Model& model, const std::vector<Material>& materials) {
  DecodedTextures d;
  d.of.resize(model.materials.size());
  for (size_t i = 0; i < model.materials.size(); ++i) {
    const tinygltf::Material& gm = model.materials[i];
    const auto& pbr = gm.pbrMetallicRoughness;
    MaterialTextures& t = d.of[i];
    t.base =
        texture_ref(model, pbr.baseColorTexture.index, pbr.baseColorTexture.texCoord, pbr.baseColorTexture.extensions);
    t.metal_rough = texture_ref(model, pbr.metallicRoughnessTexture.index, pbr.metallicRoughnessTexture.texCoord,
                                pbr.metallicRoughnessTexture.extensions);
    t.emissive =
        texture_ref(model, gm.emissiveTexture.index, gm.emissiveTexture.texCoord, gm.emissiveTexture.extensions);
    t.transmission = extension_texture(model, gm.extensions, "KHR_materials_transmission", "transmissionTexture");
    t.normal = texture_ref(model, gm.normalTexture.index, gm.normalTexture.texCoord, gm.normalTexture.extensions);
    t.normal_scale = static_cast<float>(gm.normalTexture.scale);
    d.textured += t.any();
    d.normal_mapped += t.normal && !t.any();
    d.referenced += materials[i].has_texture;
  }
  return d;
}

// Load notes on the textures that were not decoded, and on alpha BLEND (not read).
void note_undecoded(const tinygltf::Model& model, const DecodedTextures& d, std::vector<std::string>& notes) {
  if (d.referenced > d.textured)
    notes.push_back(fmt::format("{} of {} textured material(s) have no decoded texture: their factors are used",
                                d.referenced - d.textured, d.referenced));
  bool normal_maps = false, blend = false;
  for (const auto& gm : model.materials) {
    normal_maps |= gm.normalTexture.index >= 0;
    blend |= gm.alphaMode == "BLEND";
  }
  if (normal_maps && std::none_of(d.of.begin(), d.of.end(), [](const MaterialTextures& t) { return bool(t.normal); }))
    notes.push_back("normal maps were not decoded: shading normals are the interpolated vertex normals");
  if (blend) notes.push_back("alpha BLEND materials are traced as opaque surfaces");
}

// MASK materials: the alpha factor, and the mask texture (in `masks`) of those with a base-colour texture.
struct MaskPlan {
  std::vector<uint32_t> texture;   // per material: its AlphaTexture, or kNoAlphaMask
  std::vector<uint8_t> cut_whole;  // per material: a constant alpha below the cutoff
  size_t materials = 0;            // materials with a mask texture
};

MaskPlan plan_masks(const tinygltf::Model& model, const std::vector<MaterialTextures>& tex, AlphaMasks& masks) {
  const size_t nm = model.materials.size();
  MaskPlan plan{std::vector<uint32_t>(nm, kNoAlphaMask), std::vector<uint8_t>(nm, 0), 0};
  std::map<const tinygltf::Image*, uint64_t> image_offset;
  for (size_t i = 0; i < nm; ++i) {
    const tinygltf::Material& gm = model.materials[i];
    if (gm.alphaMode != "MASK") continue;
    const auto& f = gm.pbrMetallicRoughness.baseColorFactor;
    const float factor = f.size() >= 4 ? static_cast<float>(f[3]) : 1.f;
    const float cutoff = static_cast<float>(gm.alphaCutoff);
    if (!tex[i].base) {
      plan.cut_whole[i] = factor < cutoff;
      continue;
    }
    const TextureRef& r = tex[i].base;
    // A texture whose every texel is opaque enough cuts nothing out: no test is needed.
    uint8_t lowest = 255;
    for (size_t p = 3; p < r.image->image.size(); p += 4) lowest = std::min(lowest, r.image->image[p]);
    if (static_cast<float>(lowest) / 255.f * factor >= cutoff) continue;
    auto [at, fresh] = image_offset.try_emplace(r.image, masks.texels.size());
    if (fresh)
      for (size_t p = 3; p < r.image->image.size(); p += 4) masks.texels.push_back(r.image->image[p]);
    AlphaTexture t;
    t.width = static_cast<uint32_t>(r.image->width);
    t.height = static_cast<uint32_t>(r.image->height);
    t.offset = at->second;
    t.wrap_s = alpha_wrap_mode(r.wrap_s);
    t.wrap_t = alpha_wrap_mode(r.wrap_t);
    t.factor = factor;
    t.cutoff = cutoff;
    plan.texture[i] = static_cast<uint32_t>(masks.textures.size());
    masks.textures.push_back(t);
    ++plan.materials;
  }
  return plan;
}

// The per-hit textures: every decoded image's RGBA once, a SurfaceTexture per reference, a TexturedMaterial per
// material with a texture (its index per material, else kNoTexture).
std::vector<uint32_t> hit_materials(const std::vector<MaterialTextures>& tex, const std::vector<Material>& materials,
                                    SurfaceTextures& st) {
  std::vector<uint32_t> hit_material(tex.size(), kNoTexture);
  std::map<const tinygltf::Image*, uint64_t> image_offset;
  auto add = [&](const TextureRef& r) {
    if (!r) return kNoTexture;
    auto [at, fresh] = image_offset.try_emplace(r.image, st.texels.size());
    if (fresh) st.texels.insert(st.texels.end(), r.image->image.begin(), r.image->image.end());
    st.textures.push_back(surface_texture(r, at->second));
    return static_cast<uint32_t>(st.textures.size() - 1);
  };
  for (size_t i = 0; i < tex.size(); ++i) {
    if (!tex[i].at_hit()) continue;
    Material f = materials[i];
    sanitize_material(f);
    TexturedMaterial m;
    m.base = add(tex[i].base);
    m.metal_rough = add(tex[i].metal_rough);
    m.emissive = add(tex[i].emissive);
    m.transmission = add(tex[i].transmission);
    m.normal = add(tex[i].normal);
    m.base_color = f.base_color;
    m.roughness = f.roughness;
    m.metallic = f.metallic;
    m.transmission_factor = f.transmission;
    m.emission = f.emission;
    m.normal_scale = std::isfinite(tex[i].normal_scale) ? tex[i].normal_scale : 1.f;
    m.ior = f.ior;
    m.thin_walled = f.thin_walled;
    hit_material[i] = static_cast<uint32_t>(st.materials.size());
    st.materials.push_back(m);
  }
  return hit_material;
}

// A masked triangle's mask texture and its coordinates at the three corners, through its transform; the triangles
// before it (`kept` of them) without a mask get none.
void append_mask_uv(AlphaMasks& masks, uint32_t mask, const TextureRef& r, const std::vector<float> (&uv)[2],
                    const uint32_t* idx, size_t kept) {
  const int set = std::clamp(r.texcoord, 0, 1);
  masks.tri_texture.resize(kept, kNoAlphaMask);
  masks.tri_uv.resize(6 * kept, 0.f);
  masks.tri_texture.push_back(mask);
  for (int k = 0; k < 3; ++k) {
    const double u0 = uv[set][2 * idx[k]], v0 = uv[set][2 * idx[k] + 1];
    masks.tri_uv.push_back(static_cast<float>(r.m[0] * u0 + r.m[1] * v0 + r.m[2]));
    masks.tri_uv.push_back(static_cast<float>(r.m[3] * u0 + r.m[4] * v0 + r.m[5]));
  }
  ++masks.masked_tris;
}

// Load notes on what the textures decide: the per-hit textures, the alpha masks and the triangles cut out whole.
void note_texture_use(const SurfaceTextures& st, size_t derived, const AlphaMasks& masks, size_t mask_materials,
                      size_t cut, std::vector<std::string>& notes) {
  if (st.textured_tris > 0) {
    size_t normal_tris = 0;
    for (size_t t = 0; t < st.tri_material.size(); ++t)
      normal_tris += st.tri_material[t] != kNoTexture && st.materials[st.tri_material[t]].normal != kNoTexture;
    notes.push_back(fmt::format(
        "textures: {} triangle(s) of {} material(s) read base colour, metallic-roughness, emissive and transmission "
        "at the texel of every hit ({} with a normal map; {} MiB of texels); the material table holds each "
        "triangle's mean of 16 texels ({} derived material(s))",
        st.textured_tris, st.materials.size(), normal_tris, (st.texels.size() + (1 << 20) - 1) >> 20, derived));
  }
  if (masks.masked_tris > 0)
    notes.push_back(fmt::format(
        "alpha MASK: {} triangle(s) of {} material(s) cut out per texel at every hit (any-hit test in traversal, "
        "{} KiB of alpha texels)",
        masks.masked_tris, mask_materials, (masks.texels.size() + 1023) / 1024));
  if (cut > 0)
    notes.push_back(fmt::format("alpha MASK: {} triangle(s) removed whole (constant alpha below the cutoff)", cut));
}

}  // namespace

void GltfReader::append_hit_uv(uint32_t hit_material, bool normal_mapped, const uint32_t* idx) {
  SurfaceTextures& st = scene_.textures;
  st.tri_material.push_back(hit_material);
  float corner_uv[12] = {};
  float tangent[4] = {0.f, 0.f, 0.f, 1.f};
  if (hit_material != kNoTexture) {
    for (int set = 0; set < 2; ++set)
      for (int k = 0; k < 3; ++k) {
        corner_uv[6 * set + 2 * k] = uv_[set][2 * idx[k]];
        corner_uv[6 * set + 2 * k + 1] = uv_[set][2 * idx[k] + 1];
      }
    if (normal_mapped) triangle_tangent(st.textures[st.materials[hit_material].normal], idx, corner_uv, tangent);
    ++st.textured_tris;
  }
  st.tri_uv.insert(st.tri_uv.end(), corner_uv, corner_uv + 12);
  st.tri_tangent.insert(st.tri_tangent.end(), tangent, tangent + 4);
}

void GltfReader::apply_textures() {
  const size_t nm = model_.materials.size();
  const DecodedTextures decoded = decode_textures(model_, scene_.materials);
  const std::vector<MaterialTextures>& tex = decoded.of;
  auto& notes = scene_.load_notes;
  note_undecoded(model_, decoded, notes);
  AlphaMasks& masks = scene_.alpha;
  const MaskPlan mask_plan = plan_masks(model_, tex, masks);
  const std::vector<uint8_t>& cut_whole = mask_plan.cut_whole;
  if (decoded.textured + decoded.normal_mapped == 0 &&
      std::find(cut_whole.begin(), cut_whole.end(), 1) == cut_whole.end())
    return;

  SurfaceTextures& st = scene_.textures;
  const std::vector<uint32_t> hit_material = hit_materials(tex, scene_.materials, st);
  const auto points = sample_points();
  std::map<std::array<int, 11>, uint32_t> derived;
  std::vector<uint32_t> kept_indices, kept_materials;
  kept_indices.reserve(scene_.indices.size());
  kept_materials.reserve(scene_.tri_material.size());
  size_t cut = 0;
  for (size_t t = 0; t < scene_.tri_material.size(); ++t) {
    const uint32_t* idx = &scene_.indices[3 * t];
    uint32_t mat = scene_.tri_material[t];
    const uint32_t orig = mat;
    if (mat < nm && cut_whole[mat]) {
      ++cut;
      continue;
    }
    const uint32_t mask = mat < nm ? mask_plan.texture[mat] : kNoAlphaMask;
    if (mask != kNoAlphaMask) append_mask_uv(masks, mask, tex[mat].base, uv_, idx, kept_materials.size());
    if (mat < nm && tex[mat].any()) {
      const Material& base = scene_.materials[mat];
      const SampleSums sums = sample_triangle(tex[mat], model_.materials[mat], base, uv_, idx, points);
      const std::array<int, 11> key = derived_key(mat, sums, mask != kNoAlphaMask, points.size());
      auto [it, inserted] = derived.try_emplace(key, static_cast<uint32_t>(scene_.materials.size()));
      if (inserted) scene_.materials.push_back(derived_material(base, key, derived.size()));
      mat = it->second;
    }
    const uint32_t hm = orig < nm ? hit_material[orig] : kNoTexture;
    append_hit_uv(hm, hm != kNoTexture && tex[orig].normal, idx);
    kept_indices.insert(kept_indices.end(), idx, idx + 3);
    kept_materials.push_back(mat);
  }
  scene_.indices.swap(kept_indices);
  scene_.tri_material.swap(kept_materials);
  scene_.alpha_cut_tris = cut;
  if (!masks.tri_texture.empty()) {
    masks.tri_texture.resize(scene_.tri_material.size(), kNoAlphaMask);
    masks.tri_uv.resize(6 * scene_.tri_material.size(), 0.f);
  } else {
    masks = AlphaMasks{};
  }
  if (st.textured_tris == 0)
    st = SurfaceTextures{};
  else
    emitter_means();
  note_texture_use(st, derived.size(), masks, mask_plan.materials, cut, notes);
}

}  // namespace raycoh::gltf

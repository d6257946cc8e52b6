// The reference cache (key, files and reuse rule in reference.h).
#include "shading/reference.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/durable_file.h"
#include "core/error.h"
#include "generators/generator.h"
#include "raycoh_git.h"

namespace raycoh {

namespace fs = std::filesystem;

namespace {

struct Fnv1a {
  uint64_t h = 1469598103934665603ull;
  void add(const void* data, size_t n) {
    const auto* b = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < n; ++i) {
      h ^= b[i];
      h *= 1099511628211ull;
    }
  }
  void add(const std::string& s) { add(s.data(), s.size() + 1); }  // with the terminator, so "ab","c" != "a","bc"
  void add_u64(uint64_t v) { add(&v, sizeof v); }
};

void hash_file_bytes(Fnv1a& h, const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(fmt::format("{}: cannot read the scene file to fingerprint it", path.string()));
  std::vector<char> buf(1 << 20);
  while (in) {
    in.read(buf.data(), static_cast<std::streamsize>(buf.size()));
    h.add(buf.data(), static_cast<size_t>(in.gcount()));
  }
}

bool is_scene_file(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext == ".gltf" || ext == ".glb" || ext == ".obj";
}

std::string safe_name(const std::string& name) {
  std::string out;
  for (char c : name) out += std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' ? c : '_';
  return out.empty() ? "scene" : out;
}

uint64_t file_hash(const fs::path& path) {
  Fnv1a h;
  hash_file_bytes(h, path);
  return h.h;
}

// The sidecar's checksum: FNV-1a of its canonical JSON without the checksum field itself, so that an edited field
// (a key, the image hash, the render time) is found.
std::string sidecar_checksum(nlohmann::json side) {
  side.erase("checksum");
  Fnv1a h;
  h.add(side.dump());
  return fmt::format("{:016x}", h.h);
}

}  // namespace

std::string renderer_revision() { return fmt::format("r{}/{}", kRendererVersion, RAYCOH_GIT_REVISION); }

std::string default_cache_dir() {
  const char* env = std::getenv("RAYCOH_CACHE");
  return env && *env ? env : "results/cache";
}

std::string scene_fingerprint(const std::string& spec) {
  const std::vector<std::string> builtins = builtin_scene_names();
  // The same rule as load_scene: a built-in name wins unless the spec is a path.
  if (std::find(builtins.begin(), builtins.end(), parse_plugin_spec(spec).name) != builtins.end())
    return "builtin:" + spec;
  const fs::path path(spec);
  std::error_code ec;
  if (!fs::exists(path, ec)) throw Error(fmt::format("scene '{}': no such file or folder", spec));
  Fnv1a h;
  const fs::path dir = fs::is_directory(path) ? path : path.parent_path().empty() ? fs::path(".") : path.parent_path();
  std::vector<fs::path> entries;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (e.is_regular_file(ec)) entries.push_back(e.path());
  std::sort(entries.begin(), entries.end());
  for (const fs::path& e : entries) {
    h.add(e.filename().string());
    h.add_u64(fs::file_size(e, ec));
    h.add_u64(static_cast<uint64_t>(fs::last_write_time(e, ec).time_since_epoch().count()));
    const bool content = fs::is_directory(path) ? is_scene_file(e) : fs::equivalent(e, path, ec);
    if (content) hash_file_bytes(h, e);
  }
  return fmt::format("file:{:016x}", h.h);
}

std::string reference_key(const ReferenceRequest& r) {
  nlohmann::json key = {
      {"scene", r.scene_spec},
      {"scene_fingerprint", scene_fingerprint(r.scene_spec)},
      {"width", r.settings.width},
      {"height", r.settings.height},
      {"frames", r.frames},
      {"seed", r.settings.seed},
      {"max_depth", r.settings.max_depth},
      {"rr_depth", r.settings.rr_depth},
      {"tracer", r.tracer.text()},
      {"generator", "noopt"},
      {"renderer_revision", r.revision.empty() ? renderer_revision() : r.revision},
  };
  return key.dump();
}

Reference get_reference(const Scene& scene, const Bvh& bvh, const ReferenceRequest& r) {
  r.settings.validate();
  if (r.frames < 1 || r.frames > (1 << 20))
    throw Error(fmt::format("--ref-frames {}: must be in [1, {}]", r.frames, 1 << 20));
  const std::string key = reference_key(r);
  Fnv1a digest;
  digest.add(key);
  const fs::path dir = r.cache_dir.empty() ? fs::path(default_cache_dir()) : fs::path(r.cache_dir);
  const std::string stem = fmt::format("{}-{:016x}", safe_name(scene.name), digest.h);
  const fs::path image_path = dir / (stem + float_image_extension());
  const fs::path sidecar_path = dir / (stem + ".json");

  Reference ref;
  ref.path = image_path.string();
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw Error(fmt::format("reference cache {}: cannot create the folder: {}", dir.string(), ec.message()));
  // One run renders an entry; another run asking for the same one waits, then reads it.
  const OutputLock lock((dir / stem).string(), "reference cache entry " + stem, OutputLock::Wait::Yes);
  if (fs::is_regular_file(sidecar_path, ec) && fs::is_regular_file(image_path, ec)) {
    std::ifstream in(sidecar_path);
    const nlohmann::json side = nlohmann::json::parse(in, nullptr, false);
    const bool ours = !side.is_discarded() && side.is_object() && side.contains("key") && side["key"].is_object() &&
                      side["key"].dump() == key;
    const bool intact = ours && side.value("checksum", std::string()) == sidecar_checksum(side) &&
                        side.value("image_fnv1a", std::string()) == fmt::format("{:016x}", file_hash(image_path));
    if (ours && !intact)
      std::fprintf(stderr,
                   "reference cache: %s or its sidecar does not match the recorded checksum (edited or damaged); "
                   "rendering it again\n",
                   image_path.string().c_str());
    if (intact) {
      try {
        Image img = read_image(image_path.string());
        if (img.width == r.settings.width && img.height == r.settings.height) {
          ref.image = std::move(img);
          ref.from_cache = true;
          ref.non_finite = side.value("non_finite_samples", uint64_t{0});
          return ref;
        }
      } catch (const Error&) {
        // An unreadable cached image is rendered again below, as if it were missing.
      }
    }
  }

  auto tracer = make_tracer(r.tracer, scene, bvh);
  auto generator = make_generator({"noopt", ""});
  PathTracer pt(scene, *tracer, *generator, r.settings);
  Accumulator acc(r.settings.width, r.settings.height);
  const auto t0 = std::chrono::steady_clock::now();
  for (int f = 0; f < r.frames; ++f) {
    pt.render_frame(static_cast<uint32_t>(f), acc);
    if (r.progress) r.progress(f + 1, r.frames);
  }
  ref.render_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ref.image = acc.mean();
  ref.non_finite = acc.non_finite_samples();

  fs::remove(sidecar_path, ec);  // an old sidecar must never describe the new image, even for a moment
  write_image(ref.image, image_path.string());
  nlohmann::json side = {
      {"key", nlohmann::json::parse(key)},       {"digest", fmt::format("{:016x}", digest.h)},
      {"render_seconds", ref.render_s},          {"non_finite_samples", ref.non_finite},
      {"image", image_path.filename().string()}, {"image_fnv1a", fmt::format("{:016x}", file_hash(image_path))}};
  side["checksum"] = sidecar_checksum(side);
  write_file_atomically(sidecar_path.string(), side.dump(2) + "\n");
  return ref;
}

}  // namespace raycoh

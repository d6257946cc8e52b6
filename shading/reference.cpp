// The reference cache (key, files and reuse rule in reference.h).
#include "shading/reference.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string_view>

#include "core/durable_file.h"
#include "core/error.h"
#include "generators/generator.h"
#include "plugins/tracer_registry.h"
#include "raycoh_git.h"
#include "shading/reference_store.h"

namespace raycoh {

namespace fs = std::filesystem;
using namespace reference_store;

namespace reference_store {

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

// An int field of a file's JSON, as nlohmann's get<int> but refusing (type_error) what is not an integer in int's
// range: get<int> casts a float such as 1e300 to int (undefined behaviour) and wraps a larger integer.
int int_field(const nlohmann::json& j) {
  const bool fits = j.is_number_unsigned()  ? j.get<uint64_t>() <= uint64_t{INT32_MAX}
                    : j.is_number_integer() ? j.get<int64_t>() >= INT32_MIN && j.get<int64_t>() <= INT32_MAX
                                            : false;
  if (!fits) throw nlohmann::json::type_error::create(302, "not an integer in int's range", &j);
  return static_cast<int>(j.get<int64_t>());
}

// A sidecar's text field; empty when it is missing or not text (value() would throw type_error).
std::string text_field(const nlohmann::json& side, const char* name) {
  const auto it = side.find(name);
  return it != side.end() && it->is_string() ? it->get<std::string>() : std::string();
}

// The sidecar's checksum: FNV-1a of its canonical JSON without the checksum field itself, so that an edited field
// (a key, the image hash, the render time) is found.
std::string sidecar_checksum(nlohmann::json side) {
  side.erase("checksum");
  Fnv1a h;
  h.add(side.dump());
  return fmt::format("{:016x}", h.h);
}

}  // namespace reference_store

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
      {"frame_block", r.frame_block},
      {"seed", r.settings.seed},
      {"max_depth", r.settings.max_depth},
      {"rr_depth", r.settings.rr_depth},
      {"tracer", r.tracer.text()},
      {"generator", "noopt"},
      {"renderer_revision", r.revision.empty() ? renderer_revision() : r.revision},
  };
  if (r.device != "cpu") key["device"] = r.device;  // its own entry (reference.h "Device"); CPU keys unchanged
  return key.dump();
}

namespace reference_store {

Entry entry_of(const std::string& stem_prefix, const std::string& key, const std::string& cache_dir) {
  Fnv1a digest;
  digest.add(key);
  Entry e;
  e.digest = digest.h;
  e.dir = cache_dir.empty() ? fs::path(default_cache_dir()) : fs::path(cache_dir);
  e.stem = fmt::format("{}-{:016x}", stem_prefix, digest.h);
  e.image = e.dir / (e.stem + float_image_extension());
  e.sidecar = e.dir / (e.stem + ".json");
  return e;
}

}  // namespace reference_store

std::string half_reference_path(const std::string& image_path) {
  const fs::path p(image_path);
  return (p.parent_path() / (p.stem().string() + "-half1" + p.extension().string())).string();
}

bool reference_halves(int frames, int frame_block) { return frames % (2 * frame_block) == 0; }

int reference_file_frames(const std::string& image_path) {
  const fs::path p(image_path), side_path = p.parent_path() / (p.stem().string() + ".json");
  std::ifstream in(side_path);
  if (!in) return 0;
  try {
    const nlohmann::json side = nlohmann::json::parse(in);
    if (side.value("image", std::string()) != p.filename().string()) return 0;
    const int frames = int_field(side.at("key").at("frames"));
    return frames > 0 ? frames : 0;
  } catch (const nlohmann::json::exception&) {
    return 0;  // not a sidecar of ours: the frame count stays unknown
  }
}

namespace reference_store {

void create_cache_dir(const fs::path& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw Error(fmt::format("reference cache {}: cannot create the folder: {}", dir.string(), ec.message()));
}

void check_request(const ReferenceRequest& r) {
  r.settings.validate();
  if (r.frames < 1 || r.frames > (1 << 20))
    throw Error(fmt::format("--ref-frames {}: must be in [1, {}]", r.frames, 1 << 20));
  if (r.frame_block < 1 || r.frame_block > (1 << 20))
    throw Error(fmt::format("frame block {}: must be in [1, {}]", r.frame_block, 1 << 20));
  if (r.device != "cpu" && !r.make_renderer)
    throw Error(fmt::format("reference on device {}: no renderer for its frames", r.device));
}

void store_entry(const Entry& e, const std::string& key, const Reference& ref, const nlohmann::json& extra) {
  std::error_code ec;
  fs::remove(e.sidecar, ec);  // an old sidecar must never describe the new image, even for a moment
  write_image(ref.image, e.image.string());
  nlohmann::json side = {{"key", nlohmann::json::parse(key)},
                         {"digest", fmt::format("{:016x}", e.digest)},
                         {"render_seconds", ref.render_s},
                         {"render_hosts", ref.render_hosts},
                         {"non_finite_samples", ref.non_finite},
                         {"image", e.image.filename().string()},
                         {"image_fnv1a", fmt::format("{:016x}", file_hash(e.image))}};
  side.update(extra);
  const fs::path half = half_reference_path(e.image.string());
  if (!ref.first_half.empty()) {
    write_image(ref.first_half, half.string());
    side["half_image"] = half.filename().string();
    side["half_image_fnv1a"] = fmt::format("{:016x}", file_hash(half));
  } else {
    fs::remove(half, ec);
  }
  side["checksum"] = sidecar_checksum(side);
  write_file_atomically(e.sidecar.string(), side.dump(2) + "\n");
}

std::string host_name() {
  char buf[256] = {};
  if (::gethostname(buf, sizeof buf - 1) != 0 || buf[0] == '\0') return "unknown";
  std::string h(buf);
  for (char& c : h)
    if (std::isspace(static_cast<unsigned char>(c))) c = '_';
  return h;
}

}  // namespace reference_store

Reference get_reference(const Scene& scene, const Bvh& bvh, const ReferenceRequest& r) {
  check_request(r);
  const std::string key = reference_key(r);
  const Entry e = entry_of(safe_name(scene.name), key, r.cache_dir);

  Reference ref;
  ref.path = e.image.string();
  create_cache_dir(e.dir);
  // One run renders an entry; another run asking for the same one waits, then reads it.
  const OutputLock lock((e.dir / e.stem).string(), "reference cache entry " + e.stem, OutputLock::Wait::Yes);
  std::error_code ec;
  if (fs::is_regular_file(e.sidecar, ec) && fs::is_regular_file(e.image, ec)) {
    std::ifstream in(e.sidecar);
    const nlohmann::json side = nlohmann::json::parse(in, nullptr, false);
    const bool ours = !side.is_discarded() && side.is_object() && side.contains("key") && side["key"].is_object() &&
                      side["key"].dump() == key;
    const bool intact = ours && text_field(side, "checksum") == sidecar_checksum(side) &&
                        text_field(side, "image_fnv1a") == fmt::format("{:016x}", file_hash(e.image));
    if (ours && !intact)
      std::fprintf(stderr,
                   "reference cache: %s or its sidecar does not match the recorded checksum (edited or damaged); "
                   "rendering it again\n",
                   e.image.string().c_str());
    if (intact) {
      try {
        Image img = read_image(e.image.string());
        if (img.width == r.settings.width && img.height == r.settings.height) {
          ref.image = img;
          ref.from_cache = true;
          const auto nf = side.find("non_finite_samples");
          ref.non_finite = nf != side.end() && nf->is_number_unsigned() ? nf->get<uint64_t>() : 0;
          const fs::path half = half_reference_path(e.image.string());
          if (side.contains("half_image") && fs::is_regular_file(half, ec) &&
              text_field(side, "half_image_fnv1a") == fmt::format("{:016x}", file_hash(half))) {
            Image h = read_image(half.string());
            if (h.width == img.width && h.height == img.height) ref.first_half = std::move(h);
          }
          return ref;
        }
      } catch (const Error&) {
        // An unreadable cached image is rendered again below, as if it were missing.
      }
    }
  }

  Accumulator total(r.settings.width, r.settings.height), first_half(r.settings.width, r.settings.height);
  ref.render_s = render_blocks(scene, bvh, r, {0, r.frames}, [&](const Accumulator& block, int start) {
    total.merge(block);
    if (start < r.frames / 2) first_half.merge(block);
  });
  ref.image = total.mean();
  if (reference_halves(r.frames, r.frame_block)) ref.first_half = first_half.mean();
  ref.non_finite = total.non_finite_samples();
  ref.render_hosts = {host_name()};
  store_entry(e, key, ref);
  return ref;
}

}  // namespace raycoh

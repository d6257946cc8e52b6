// Frame shards of a reference: the shard's frames, its part file (written block by block, resumable), and the
// combination of the parts into one cache entry (shading/reference.h). The cache itself: shading/reference.cpp.
#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string_view>

#include "core/durable_file.h"
#include "core/error.h"
#include "shading/reference.h"
#include "shading/reference_store.h"

namespace raycoh {

using namespace reference_store;

namespace {

template <class T>
std::string_view bytes_of(const std::vector<T>& v) {
  return {reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T)};
}

// Part files: format 2 (this one) follows each block's bytes with a line "block <index> <FNV-1a of its bytes>
// <render seconds> <host>", so that a stopped shard keeps its finished blocks and the combined entry can sum the
// render time; format 1 (revision 4919fdd and before) has no such lines and is still read.
constexpr int kPartFormat = 2;

// One part file: its header, then its blocks read one at a time.
struct PartReader {
  std::string file;
  std::ifstream in;
  nlohmann::json head;
  int format = 0, width = 0, height = 0, blocks = 0;
  int shard = 0, shards = 0, first = 0, end = 0, frames = 0, block = 0;
  std::string stem;
  std::streamoff header_bytes = 0;
  double seconds = 0;              // render time of the blocks read (format 2)
  std::vector<std::string> hosts;  // where they were rendered (format 2), each once

  explicit PartReader(const std::string& path) : file(path), in(path, std::ios::binary) {
    if (!in) throw Error(fmt::format("{}: cannot read the reference part", file));
    std::string line;
    std::getline(in, line);
    header_bytes = in.tellg();
    head = nlohmann::json::parse(line, nullptr, false);
    const std::string damaged =
        fmt::format("{}: not a raycoh reference part (format 1 or {}), or its header is damaged", file, kPartFormat);
    try {
      if (head.is_discarded() || !head.is_object() || !head.at("key").is_object()) throw Error(damaged);
      format = int_field(head.at("raycoh_reference_part"));
      width = int_field(head.at("width"));
      height = int_field(head.at("height"));
      shard = int_field(head.at("shard"));
      shards = int_field(head.at("shards"));
      first = int_field(head.at("first_frame"));
      end = int_field(head.at("end_frame"));
      stem = head.at("stem").get<std::string>();
      frames = int_field(head.at("key").at("frames"));
      block = int_field(head.at("key").at("frame_block"));
      // The ranges a part raycoh writes keeps (frames and blocks as check_request allows, shards of whole
      // blocks), so that no count below overflows and a damaged header never asks for a huge allocation.
      const bool in_range = width <= (1 << 16) && height <= (1 << 16) && frames >= 1 && frames <= (1 << 20) &&
                            block <= (1 << 20) && first >= 0 && end <= frames && shards <= frames &&
                            width == int_field(head.at("key").at("width")) &&
                            height == int_field(head.at("key").at("height"));
      if ((format != 1 && format != kPartFormat) || width < 1 || height < 1 || block < 1 || end <= first ||
          shards < 1 || header_bytes <= 0 || !in_range)
        throw Error(damaged);
      blocks = (end - first + block - 1) / block;
    } catch (const nlohmann::json::exception&) {
      throw Error(damaged);
    }
  }

  // Block b (the next one in the file), its bytes added to `total`; nothing when the file ends within it or, in
  // format 2, its line is missing or does not match its bytes.
  uint64_t block_bytes() const { return uint64_t{32} * static_cast<uint64_t>(width) * static_cast<uint64_t>(height); }
  // The file's bytes after `from`: checked before anything of the header's image size is allocated.
  uint64_t bytes_after(std::streamoff from) const {
    std::error_code ec;
    const uint64_t size = fs::file_size(file, ec);
    return ec || from < 0 || size < static_cast<uint64_t>(from) ? 0 : size - static_cast<uint64_t>(from);
  }
  // Combining needs every block: a part cut short is refused before the image is allocated.
  void check_whole() const {
    const uint64_t have = bytes_after(header_bytes);
    if (have / block_bytes() < static_cast<uint64_t>(blocks))
      throw Error(
          fmt::format("{}: the reference part is cut short ({} bytes of pixel data, {} blocks of {} expected); "
                      "render that shard again",
                      file, have, blocks, block_bytes()));
  }

  std::optional<Accumulator> read_block(int b, Fnv1a& total) {
    if (bytes_after(in.tellg()) < block_bytes()) return std::nullopt;  // cut short (or a damaged size)
    const size_t n = static_cast<size_t>(width) * static_cast<size_t>(height);
    std::vector<double> sums(3 * n);
    std::vector<uint32_t> samples(n), non_finite(n);
    Fnv1a h = total, own;
    const auto read = [&](auto& v) {
      in.read(reinterpret_cast<char*>(v.data()), static_cast<std::streamsize>(v.size() * sizeof(v[0])));
      h.add(v.data(), v.size() * sizeof(v[0]));
      own.add(v.data(), v.size() * sizeof(v[0]));
      return static_cast<bool>(in);
    };
    if (!read(sums) || !read(samples) || !read(non_finite)) return std::nullopt;
    if (format >= 2) {
      std::string line;
      std::getline(in, line);
      if (in.eof()) return std::nullopt;  // no newline: the line was being written
      char hash[17] = {}, host[256] = {};
      int index = -1;
      double s = 0;
      if (std::sscanf(line.c_str(), "block %d %16s %lf %255s", &index, hash, &s, host) != 4 || index != b ||
          std::string(hash) != fmt::format("{:016x}", own.h))
        return std::nullopt;
      // A host name as host_name() writes it (printable ASCII): it goes into the sidecar's JSON, which holds UTF-8.
      if (std::any_of(host, host + std::strlen(host), [](char c) { return c < 0x21 || c > 0x7e; }) ||
          !std::isfinite(s) || s < 0)
        return std::nullopt;
      seconds += s;
      if (std::find(hosts.begin(), hosts.end(), host) == hosts.end()) hosts.push_back(host);
    }
    total = h;
    return Accumulator::from_parts(width, height, std::move(sums), std::move(samples), std::move(non_finite));
  }

  // Reads every block, in order, into on_block; checks the closing checksum.
  template <class OnBlock>
  void read_blocks(OnBlock&& on_block) {
    Fnv1a h;
    for (int b = 0; b < blocks; ++b) {
      std::optional<Accumulator> acc = read_block(b, h);
      if (!acc)
        throw Error(
            fmt::format("{}: the reference part is cut short or damaged (block {} of {}); render that shard "
                        "again (it keeps the blocks before)",
                        file, b, blocks));
      on_block(*acc, first + b * block);
    }
    std::string line;
    std::getline(in, line);
    if (line != fmt::format("end {:016x}", h.h))
      throw Error(
          fmt::format("{}: the reference part's checksum does not match (damaged or cut short); render "
                      "that shard again",
                      file));
  }
};

// The first field in which two keys differ, as "field (a vs b)".
std::string key_difference(const nlohmann::json& a, const nlohmann::json& b) {
  for (const auto& [field, value] : a.items())
    if (!b.contains(field) || b[field] != value)
      return fmt::format("{} ({} vs {})", field, value.dump(), b.contains(field) ? b[field].dump() : "missing");
  for (const auto& [field, value] : b.items())
    if (!a.contains(field)) return fmt::format("{} (missing vs {})", field, value.dump());
  return "";
}

}  // namespace

FrameRange reference_shard_frames(int frames, int frame_block, int index, int count) {
  if (count == 1) return {0, frames};
  if (frames % count == 0 && (frames / count) % frame_block == 0)
    return {index * (frames / count), (index + 1) * (frames / count)};
  std::vector<int> valid{1};
  if (frames % frame_block == 0)
    for (int n = 2; n <= frames / frame_block; ++n)
      if ((frames / frame_block) % n == 0) valid.push_back(n);
  std::string list;
  for (int n : valid) list += (list.empty() ? "" : ", ") + std::to_string(n);
  throw Error(
      fmt::format("--shard {}/{} with {} frames: a reference shard must be whole blocks of {} frames, all "
                  "shards the same size; valid shard counts: {}",
                  index, count, frames, frame_block, list));
}

namespace {

// The blocks of a stopped run of this very shard in `partial` that verify (their bytes added to `h`), and where
// the file is cut after the last of them (0: nothing kept, the header neither).
struct KeptBlocks {
  int count = 0;
  std::streamoff bytes = 0;
};

KeptBlocks kept_blocks(const std::string& partial, const nlohmann::json& head, int index, int count,
                       const FrameRange& range, int frame_block, int blocks, Fnv1a& h) {
  KeptBlocks k;
  std::unique_ptr<PartReader> rd;
  try {
    rd = std::make_unique<PartReader>(partial);
  } catch (const Error&) {
    // A header cut short (stopped at once): nothing to keep.
  }
  if (!rd) return k;
  const std::string diff = rd->head["key"] != head["key"] ? "key field " + key_difference(rd->head["key"], head["key"])
                           : rd->shard != index || rd->shards != count
                               ? fmt::format("shard {}/{} vs {}/{}", rd->shard, rd->shards, index, count)
                               : key_difference(rd->head, head);
  if (!diff.empty())
    throw Error(
        fmt::format("{} holds another reference part ({}); pass --force to replace it, or choose another "
                    "--out",
                    partial, diff));
  k.bytes = rd->header_bytes;
  while (k.count < blocks && rd->read_block(k.count, h)) {
    ++k.count;
    k.bytes = rd->in.tellg();
  }
  std::fprintf(stderr, "%s: resuming: %d of %d blocks already rendered%s\n", partial.c_str(), k.count, blocks,
               k.count > 0 ? fmt::format(" (frames {}..{} kept)", range.first,
                                         std::min(range.end, range.first + k.count * frame_block) - 1)
                                 .c_str()
                           : "");
  return k;
}

}  // namespace

double render_reference_part(const Scene& scene, const Bvh& bvh, const ReferenceRequest& r, int index, int count,
                             const std::string& path, bool replace) {
  check_request(r);
  const FrameRange range = reference_shard_frames(r.frames, r.frame_block, index, count);
  const std::string key = reference_key(r);
  const nlohmann::json head = {{"raycoh_reference_part", kPartFormat},
                               {"key", nlohmann::json::parse(key)},
                               {"stem", safe_name(scene.name)},
                               {"shard", index},
                               {"shards", count},
                               {"first_frame", range.first},
                               {"end_frame", range.end},
                               {"width", r.settings.width},
                               {"height", r.settings.height}};
  const int blocks = (range.end - range.first + r.frame_block - 1) / r.frame_block;
  // The blocks a stopped run of this very shard left in <path>.partial and that verify are kept; the file is cut
  // after the last of them and the rest is rendered after it.
  const std::string partial = path + ".partial";
  int kept = 0;
  std::streamoff keep_bytes = 0;
  Fnv1a h;  // of every block's bytes, for the closing line
  std::error_code ec;
  if (!replace && fs::exists(partial, ec)) {
    const KeptBlocks k = kept_blocks(partial, head, index, count, range, r.frame_block, blocks, h);
    kept = k.count;
    keep_bytes = k.bytes;
  }
  const int fd = ::open(partial.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) throw WriteError(fmt::format("{}: cannot create {}: {}", path, partial, std::strerror(errno)));
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  if (::ftruncate(fd, keep_bytes) != 0 || ::lseek(fd, keep_bytes, SEEK_SET) != keep_bytes)
    throw WriteError(
        fmt::format("{}: cannot cut {} after its finished blocks: {}", path, partial, std::strerror(errno)));
  if (keep_bytes == 0) write_all(fd, head.dump() + "\n", partial);
  const std::string host = host_name();
  double seconds = 0;
  if (kept < blocks) {
    int b = kept;
    auto t = std::chrono::steady_clock::now();
    seconds = render_blocks(
        scene, bvh, r, {range.first + kept * r.frame_block, range.end}, [&](const Accumulator& block, int) {
          const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
          Fnv1a own;
          for (std::string_view bytes :
               {bytes_of(block.sums()), bytes_of(block.sample_counts()), bytes_of(block.non_finite_counts())}) {
            write_all(fd, bytes, partial);
            h.add(bytes.data(), bytes.size());
            own.add(bytes.data(), bytes.size());
          }
          write_all(fd, fmt::format("block {} {:016x} {} {}\n", b++, own.h, s, host), partial);
          sync_file(fd, partial);  // a finished block survives a crash
          t = std::chrono::steady_clock::now();
        });
  }
  write_all(fd, fmt::format("end {:016x}\n", h.h), partial);
  sync_file(fd, partial);
  // Moved into place only when whole; a failed move leaves the finished part in <path>.partial.
  if (::rename(partial.c_str(), path.c_str()) != 0)
    throw WriteError(fmt::format("{}: cannot move {} into place: {} (the finished part stays there)", path, partial,
                                 std::strerror(errno)));
  sync_parent_folder(path);
  return seconds;
}

bool reference_part_done(const std::string& path, const ReferenceRequest& r, int index, int count) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return false;
  try {
    const PartReader rd(path);
    return rd.head["key"].dump() == reference_key(r) && rd.shard == index && rd.shards == count;
  } catch (const Error&) {
    return false;
  }
}

Reference combine_reference_parts(const std::vector<std::string>& parts, const std::string& cache_dir) {
  if (parts.empty()) throw Error("reference-combine: no part files given");
  std::vector<std::unique_ptr<PartReader>> readers;
  for (const std::string& p : parts) readers.push_back(std::make_unique<PartReader>(p));
  const PartReader& a = *readers[0];
  const int count = a.shards;
  std::vector<PartReader*> by_index(static_cast<size_t>(std::max(count, 0)), nullptr);
  for (auto& rd : readers) {
    const std::string diff = key_difference(a.head["key"], rd->head["key"]);
    if (!diff.empty())
      throw Error(fmt::format("{} and {} are parts of different references: key field {}", a.file, rd->file, diff));
    if (rd->width != a.width || rd->height != a.height)
      throw Error(fmt::format("{} and {} are parts of different image sizes ({}x{} vs {}x{})", a.file, rd->file,
                              a.width, a.height, rd->width, rd->height));
    if (rd->shards != count || rd->stem != a.stem)
      throw Error(fmt::format("{} and {} disagree on the shard count or scene ({} vs {} shards)", a.file, rd->file,
                              count, rd->shards));
    const int index = rd->shard;
    if (index < 0 || index >= count)
      throw Error(fmt::format("{}: shard {} of {} is out of range", rd->file, index, count));
    const FrameRange want = reference_shard_frames(a.frames, a.block, index, count);
    if (rd->first != want.first || rd->end != want.end)
      throw Error(
          fmt::format("{}: shard {}/{} should hold frames {}..{}", rd->file, index, count, want.first, want.end - 1));
    if (by_index[index])
      throw Error(fmt::format("{} and {} are both shard {}/{}", by_index[index]->file, rd->file, index, count));
    by_index[index] = rd.get();
  }
  std::string missing;
  int n_missing = 0;
  for (int i = 0; i < count; ++i)
    if (!by_index[i]) {
      // The first ten by name: a damaged "shards" field may claim a million.
      if (++n_missing <= 10) missing += (missing.empty() ? "" : ", ") + fmt::format("{}/{}", i, count);
    }
  if (n_missing > 0)
    throw Error(fmt::format("{} of {} reference shard(s) missing: {}{} (render them, then combine again)", n_missing,
                            count, missing, n_missing > 10 ? ", ..." : ""));

  for (const PartReader* rd : by_index) rd->check_whole();
  const std::string key = a.head["key"].dump();
  const Entry e = entry_of(safe_name(a.stem), key, cache_dir);
  Accumulator total(a.width, a.height), first_half(a.width, a.height);
  Reference ref;
  int untimed = 0;  // format-1 parts: no render time or host recorded
  for (PartReader* rd : by_index) {
    rd->read_blocks([&](const Accumulator& block, int start) {
      total.merge(block);
      if (start < a.frames / 2) first_half.merge(block);
    });
    ref.render_s += rd->seconds;
    untimed += rd->format < 2;
    for (const std::string& host : rd->hosts)
      if (std::find(ref.render_hosts.begin(), ref.render_hosts.end(), host) == ref.render_hosts.end())
        ref.render_hosts.push_back(host);
  }
  ref.path = e.image.string();
  ref.image = total.mean();
  if (reference_halves(a.frames, a.block)) ref.first_half = first_half.mean();
  ref.non_finite = total.non_finite_samples();
  // The sidecar's render_seconds is the parts' render time summed (rendering, not waiting in a queue).
  nlohmann::json extra = {{"parts", count}};
  if (untimed > 0) extra["parts_without_render_time"] = untimed;
  create_cache_dir(e.dir);
  const OutputLock lock((e.dir / e.stem).string(), "reference cache entry " + e.stem, OutputLock::Wait::Yes);
  store_entry(e, key, ref, extra);
  return ref;
}

}  // namespace raycoh

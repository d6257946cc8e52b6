// Fuzz target of the option values the commands parse themselves: --res, --shard, --crop, --time, --scenes lists,
// --tone-map, --metrics, --permute and integer options (harness/common/cli.h, records/shard.h, shading/,
// core/params.h).
#include <string>

#include "core/params.h"
#include "encoders/permute.h"
#include "harness/common/cli.h"
#include "harness/image/render_cli.h"
#include "records/shard.h"
#include "shading/image.h"
#include "shading/metrics.h"
#include "tests/fuzz/fuzz_targets.h"
#include "tests/fuzz/fuzz_util.h"

namespace raycoh::fuzz {

// First byte: which option; the rest: its value as typed. Every error must name the option.
void fuzz_option_values(const uint8_t* data, size_t size) {
  if (size < 1) return;
  const std::string text(reinterpret_cast<const char*>(data) + 1, size - 1);
  if (text.find('\0') != std::string::npos) return;  // a command-line argument cannot hold one
  switch (data[0] % 8) {
    case 0:
      expect_clean("--res", [&] { parse_res("--res", text); });
      break;
    case 1:
      expect_clean("--shard", [&] { parse_shard("--shard", text); });
      break;
    case 2:
      expect_clean("--crop", [&] { check_crop("--crop", parse_crop("--crop", text), 160, 120); });
      break;
    case 3:
      expect_clean("--time", [&] { parse_duration("--time", text); });
      break;
    case 4:
      expect_clean("--scenes", [&] { split_scenes("--scenes", text); });
      break;
    case 5:
      expect_clean("--metrics", [&] { parse_metric_space("--metrics", text); });
      break;
    case 6:
      expect_clean("", [&] { parse_tone_map(text); });
      expect_clean("", [&] { parse_permute_mode(text); });
      break;
    default:
      expect_clean("--tile", [&] { parse_size("--tile", text, 1, 4096); });
      expect_clean("--frames", [&] { parse_int("--frames", text, 1, 1 << 20); });
      break;
  }
}

}  // namespace raycoh::fuzz

#include "harness/provenance.h"

#include <ctime>
#include <embree3/rtcore_config.h>
#include <fstream>
#include <thread>

#include "raycoh_git.h"

#ifndef RAYCOH_BUILD_TYPE
#define RAYCOH_BUILD_TYPE "unknown"
#endif

namespace raycoh {

namespace {

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("model name", 0) == 0) {
      const size_t colon = line.find(':');
      if (colon != std::string::npos) return line.substr(colon + 2);
    }
  }
  return "unknown cpu";
}

std::string shell_quote(const std::string& arg) {
  if (!arg.empty() && arg.find_first_of(" \t\"'$`\\*?;&|<>()") == std::string::npos) return arg;
  std::string out = "'";
  for (char c : arg) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

}  // namespace

Provenance collect_provenance(int argc, char** argv, int threads) {
  Provenance p;
  p.git_revision = RAYCOH_GIT_REVISION;
  p.build_type = RAYCOH_BUILD_TYPE;
#if defined(__VERSION__)
  p.compiler = std::string("g++ ") + __VERSION__;
#endif
  p.cpu = cpu_model() + " x" + std::to_string(std::thread::hardware_concurrency());
  p.device = "cpu only";
  p.embree_version = RTC_VERSION_STRING;
  p.threads = threads;
  char buf[32];
  const std::time_t now = std::time(nullptr);
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  p.timestamp = buf;
  for (int i = 0; i < argc; ++i) p.command_line += (i ? " " : "") + shell_quote(argv[i]);
  return p;
}

std::vector<std::string> provenance_columns() {
  return {"git_revision", "build_type", "compiler", "cpu", "device", "embree_version", "threads", "started_utc",
          "command_line"};
}

std::vector<std::string> provenance_values(const Provenance& p) {
  return {p.git_revision, p.build_type, p.compiler,       p.cpu,         p.device,
          p.embree_version, std::to_string(p.threads), p.timestamp, p.command_line};
}

}  // namespace raycoh

#include "records/provenance.h"

#include <embree3/rtcore_config.h>
#include <unistd.h>

#include <ctime>
#include <fstream>
#include <thread>

#include "raycoh_git.h"
#if defined(RAYCOH_HAVE_CUDA)
#include "cuda/cuda_device.h"
#endif

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
  char host[256] = {};
  p.host = gethostname(host, sizeof host - 1) == 0 ? host : "unknown";
  p.device = "cpu";
  p.embree_version = RTC_VERSION_STRING;
  p.threads = threads;
  char buf[32];
  const std::time_t now = std::time(nullptr);
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  p.timestamp = buf;
  for (int i = 0; i < argc; ++i) p.command_line += (i ? " " : "") + shell_quote(argv[i]);
  return p;
}

std::string device_of(const PluginSpec& tracer) {
#if defined(RAYCOH_HAVE_CUDA)
  if (tracer.name == "cuda") return cuda::device_name();
#endif
  (void)tracer;
  return "cpu";
}

bool simulated_device(const PluginSpec& tracer) { return device_of(tracer).starts_with("simulated"); }

const Schema<Provenance>& provenance_schema() {
  using namespace csv_format;
  using P = Provenance;
  static const Schema<P> schema = {
      column("git_revision", &P::git_revision, Text{}, Key::Yes),
      column("build_type", &P::build_type, Text{}, Key::Yes),
      column("compiler", &P::compiler, Text{}),
      column("cpu", &P::cpu, Text{}, Key::Yes),
      column("host", &P::host, Text{}),
      column("device", &P::device, Text{}),
      column("embree_version", &P::embree_version, Text{}),
      column("threads", &P::threads, Integer<int>{}, Key::Yes),
      column("started_utc", &P::timestamp, Text{}),
      column("command_line", &P::command_line, Text{}),
  };
  return schema;
}

}  // namespace raycoh

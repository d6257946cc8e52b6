#include "records/provenance.h"

#include <embree3/rtcore_config.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
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

// "<host>-<8 hex digits>": FNV-1a of /etc/machine-id, the CPU model and core count and the memory size, so that
// two machines with one host name (a VM image's "vm") are told apart.
std::string machine_id(const std::string& host, const std::string& cpu) {
  std::string text = cpu;
  std::ifstream id("/etc/machine-id");
  std::string line;
  if (std::getline(id, line)) text += "|" + line;
  std::ifstream mem("/proc/meminfo");
  if (std::getline(mem, line)) text += "|" + line;
  uint32_t h = 2166136261u;
  for (unsigned char c : text) h = (h ^ c) * 16777619u;
  char hex[9];
  std::snprintf(hex, sizeof hex, "%08x", h);
  return host + "-" + hex;
}

// RAYCOH_RUN_UNDER, else what the CUDA injection library a profiler or sanitizer sets says, else "".
std::string run_under() {
  if (const char* v = std::getenv("RAYCOH_RUN_UNDER"); v && *v) return v;
  const char* inj = std::getenv("CUDA_INJECTION64_PATH");
  if (!inj || !*inj) return "";
  const std::string path = inj;
  if (path.find("anitizer") != std::string::npos) return "compute-sanitizer";
  if (path.find("ystems") != std::string::npos || path.find("nsys") != std::string::npos) return "nsys";
  if (path.find("ompute") != std::string::npos || path.find("ncu") != std::string::npos) return "ncu";
  return "profiler";
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
  p.machine = machine_id(p.host, p.cpu);
  p.run_under = run_under();
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

GpuProvenance gpu_provenance(const PluginSpec& tracer) {
  GpuProvenance g;
#if defined(RAYCOH_HAVE_CUDA)
  if (tracer.name != "cuda") return g;
  const cuda::DeviceFacts f = cuda::device_facts();
  if (f.sms > 0) g.sms = f.sms;
  g.driver = f.driver;
  g.runtime = f.runtime;
#else
  (void)tracer;
#endif
  return g;
}

void read_gpu_clocks(GpuProvenance& g, bool start) {
  if (!g.sms) return;  // not a GPU row
#if defined(RAYCOH_HAVE_CUDA)
  const cuda::DeviceClocks c = cuda::device_clocks();
  if (c.sm_mhz <= 0) return;
  (start ? g.sm_mhz_start : g.sm_mhz_end) = c.sm_mhz;
  (start ? g.mem_mhz_start : g.mem_mhz_end) = c.mem_mhz;
#else
  (void)start;
#endif
}

const Schema<GpuProvenance>& gpu_provenance_schema() {
  using namespace csv_format;
  using G = GpuProvenance;
  static const Schema<G> schema = {
      column("gpu_sms", &G::sms, Optional<Integer<int>>{}),
      column("gpu_driver", &G::driver, Text{}),
      column("cuda_runtime", &G::runtime, Text{}),
      column("gpu_sm_mhz_start", &G::sm_mhz_start, Optional<Integer<int>>{}),
      column("gpu_sm_mhz_end", &G::sm_mhz_end, Optional<Integer<int>>{}),
      column("gpu_mem_mhz_start", &G::mem_mhz_start, Optional<Integer<int>>{}),
      column("gpu_mem_mhz_end", &G::mem_mhz_end, Optional<Integer<int>>{}),
  };
  return schema;
}

const Schema<Provenance>& provenance_schema() {
  using namespace csv_format;
  using P = Provenance;
  static const Schema<P> schema = {
      column("git_revision", &P::git_revision, Text{}, Key::Yes),
      column("build_type", &P::build_type, Text{}, Key::Yes),
      column("compiler", &P::compiler, Text{}),
      column("cpu", &P::cpu, Text{}, Key::Yes),
      column("host", &P::host, Text{}),
      column("machine", &P::machine, Text{}),
      column("device", &P::device, Text{}),
      column("embree_version", &P::embree_version, Text{}),
      column("threads", &P::threads, Integer<int>{}, Key::Yes),
      column("started_utc", &P::timestamp, Text{}),
      column("command_line", &P::command_line, Text{}),
      column("run_under", &P::run_under, Text{}, Key::Yes),
  };
  return schema;
}

}  // namespace raycoh

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <fstream>

#include "tests/test_util.h"

namespace raycoh::test {

std::vector<std::filesystem::path> shared_scene_files() {
  std::vector<std::filesystem::path> files;
  const auto dir = shared_scenes_dir();
  if (dir.empty()) return files;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(dir))
    if (entry.path().extension() == ".glb") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  return files;
}

std::filesystem::path temp_dir(const std::string& name) {
  // A folder left by an earlier test process with the same process id (ids are reused) is that process's, never a
  // live one's: cleared once, so that no test resumes from another run's files.
  static const std::filesystem::path root = [] {
    auto r = std::filesystem::temp_directory_path() / ("raycoh_test_" + std::to_string(::getpid()));
    std::error_code ec;
    std::filesystem::remove_all(r, ec);
    return r;
  }();
  auto dir = root / name;
  std::filesystem::create_directories(dir);
  return dir;
}

void write_file(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out << bytes;
}

CommandResult run_raycoh(const std::string& args) { return run_shell("$R " + args); }

CommandResult run_shell(const std::string& script) {
  CommandResult result;
  // $RAYCOH_BINARY: the raycoh to run where the build's own path does not exist (scripts/gpu-check's bundle).
  const char* env = std::getenv("RAYCOH_BINARY");
  const std::string binary = env && *env ? env : RAYCOH_BINARY;
  const std::string cmd = "R='" + binary + "'; { " + script + "\n} 2>&1";
  FILE* pipe = ::popen(cmd.c_str(), "r");
  if (!pipe) return result;
  std::array<char, 4096> buf;
  size_t n;
  while ((n = std::fread(buf.data(), 1, buf.size(), pipe)) > 0) result.output.append(buf.data(), n);
  const int status = ::pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

}  // namespace raycoh::test

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}

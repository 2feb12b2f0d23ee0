#pragma once
// Helpers shared by the replay tests: temp folders, whole-file reads, the golden manifest.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace replay_test {

namespace fs = std::filesystem;

/// A fresh folder under /tmp, removed with everything in it.
struct TempDir {
  fs::path path;
  TempDir() {
    char name[] = "/tmp/ucon_replay_test_XXXXXX";
    path = mkdtemp(name) ? fs::path(name) : fs::temp_directory_path();
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  std::string file(const std::string& name) const { return (path / name).string(); }
};

inline std::vector<uint8_t> readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

inline void writeBytes(const std::string& path, const std::vector<uint8_t>& b) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
}

/// tests/data/replay/MANIFEST (written by scripts/regen-golden.sh): one record per line,
///   scenario <spec> | duration_s <s> | nodes <a,b> | input <channel> <events> <fnv64 hex> |
///   golden <node> <file>
struct Manifest {
  std::string scenario;
  double duration_s = 0.0;
  std::string nodes;
  std::map<std::string, std::pair<long long, std::string>> input;  // channel -> (events, hash)
  std::map<std::string, std::string> golden;                         // node -> file
  bool ok = false;
};

inline Manifest readManifest(const std::string& path) {
  Manifest m;
  std::ifstream in(path);
  if (!in) return m;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ss(line);
    std::string key;
    ss >> key;
    if (key == "scenario") ss >> m.scenario;
    if (key == "duration_s") ss >> m.duration_s;
    if (key == "nodes") ss >> m.nodes;
    if (key == "input") {
      std::string ch, hash;
      long long n = 0;
      ss >> ch >> n >> hash;
      m.input[ch] = {n, hash};
    }
    if (key == "golden") {
      std::string node, file;
      ss >> node >> file;
      m.golden[node] = file;
    }
  }
  m.ok = !m.scenario.empty() && m.duration_s > 0.0;
  return m;
}

}  // namespace replay_test

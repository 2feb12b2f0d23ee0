#include "ucon/runtime/config_file.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include "ucon/runtime/node_runtime.hpp"

namespace ucon {
namespace runtime {

std::optional<std::string> readTextFile(const std::string& path, std::string* error) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    if (error) *error = "cannot open '" + path + "': " + std::strerror(errno);
    return std::nullopt;
  }
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void printConfigErrors(const std::string& process, const std::vector<ConfigError>& errors) {
  for (const auto& e : errors) logLine(process, "error", e.toString());
}

}  // namespace runtime
}  // namespace ucon

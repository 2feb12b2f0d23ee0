#include "ucon/foxglove/lcm_json.hpp"

#include <cstring>

namespace ucon {
namespace foxglove {

const LcmTypeInfo* findLcmType(const void* data, std::size_t size) {
  if (size < 8) return nullptr;
  const auto* b = static_cast<const uint8_t*>(data);
  uint64_t hash = 0;
  for (int i = 0; i < 8; ++i) hash = (hash << 8) | b[i];
  for (const auto& t : lcmTypes()) {
    if (static_cast<uint64_t>(t.fingerprint) == hash) return &t;
  }
  return nullptr;
}

int64_t encodedUtime(const void* data, std::size_t size) {
  if (size < 16) return 0;
  const auto* b = static_cast<const uint8_t*>(data) + 8;
  uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v = (v << 8) | b[i];
  return static_cast<int64_t>(v);
}

const LcmTypeInfo* findLcmTypeByName(const char* name) {
  for (const auto& t : lcmTypes()) {
    if (std::strcmp(t.name, name) == 0) return &t;
  }
  return nullptr;
}

}  // namespace foxglove
}  // namespace ucon

#pragma once
// Little-endian loads and stores at unaligned addresses (private to ucon_livox).
#include <cstdint>
#include <cstring>

namespace ucon {
namespace livox {
namespace le {

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__,
              "the Livox wire format is little-endian; add byte swaps for this target");

template <class T>
inline T load(const uint8_t* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  return v;
}
template <class T>
inline void store(uint8_t* p, T v) {
  std::memcpy(p, &v, sizeof(T));
}

}  // namespace le
}  // namespace livox
}  // namespace ucon

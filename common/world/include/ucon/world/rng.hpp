#pragma once
/// @file rng.hpp
/// Small portable pseudo-random generators for the simulated world.
///
/// The standard library's distributions (std::uniform_real_distribution, std::normal_distribution)
/// are implementation-defined and differ between libstdc++, libc++ and MSVC, so the world never
/// uses them. Everything here is plain integer arithmetic plus IEEE-754 double multiplication,
/// so a seed gives the same numbers on every conforming machine. normal() uses std::log/std::cos,
/// which are correctly rounded on glibc but not guaranteed bit-identical on every libm; the
/// world *layout* (generator, pedestrian timelines) therefore uses uniform() only, and normal()
/// is used only for sensor noise.

#include <cmath>
#include <cstdint>

namespace ucon {
namespace world {

/// SplitMix64 step (Steele, Lea, Flood 2014): a good 64-bit mixer, used to seed and to derive
/// independent streams from (seed, index).
inline uint64_t splitmix64(uint64_t& state) {
  uint64_t z = (state += 0x9E3779B97F4A7C15ULL);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

/// Mixes a seed and a stream index into one 64-bit seed (independent streams per obstacle).
inline uint64_t deriveSeed(uint64_t seed, uint64_t stream) {
  uint64_t s = seed ^ (0xD1B54A32D192ED03ULL * (stream + 1));
  return splitmix64(s);
}

/// xoshiro256** 1.0 (Blackman & Vigna): fast, 256-bit state, seeded through SplitMix64.
class Rng {
 public:
  explicit Rng(uint64_t seed = 1) { reseed(seed); }

  void reseed(uint64_t seed) {
    uint64_t sm = seed;
    for (auto& w : s_) w = splitmix64(sm);
  }

  /// Next raw 64-bit value.
  uint64_t next() {
    const uint64_t result = rotl(s_[1] * 5, 7) * 9;
    const uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return result;
  }

  /// Uniform double in [0, 1): the top 53 bits times 2^-53 (exact, portable).
  double uniform01() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }

  /// Uniform double in [lo, hi).
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform01(); }

  /// Uniform integer in [0, n) for n > 0 (Lemire-free simple rejection: unbiased).
  uint64_t below(uint64_t n) {
    if (n <= 1) return 0;
    const uint64_t limit = UINT64_MAX - UINT64_MAX % n;
    uint64_t x;
    do {
      x = next();
    } while (x >= limit);
    return x % n;
  }

  /// Standard normal sample (Marsaglia polar method). For sensor noise only (see file note).
  double normal() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    double u, v, s;
    do {
      u = 2.0 * uniform01() - 1.0;
      v = 2.0 * uniform01() - 1.0;
      s = u * u + v * v;
    } while (s >= 1.0 || s == 0.0);
    const double m = std::sqrt(-2.0 * std::log(s) / s);
    spare_ = v * m;
    has_spare_ = true;
    return u * m;
  }

 private:
  static uint64_t rotl(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  uint64_t s_[4] = {0, 0, 0, 0};
  double spare_ = 0.0;
  bool has_spare_ = false;
};

}  // namespace world
}  // namespace ucon

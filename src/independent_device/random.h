#pragma once
// Deterministic random streams. Fixed, published algorithms so that one seed gives byte-identical data with any
// standard library (std::normal_distribution's algorithm is implementation-defined): splitmix64 (Steele, Lea &
// Flood 2014) expands the seed, xoshiro256** (Blackman & Vigna 2018) draws, Box-Muller gives normal deviates.
// Every noise source draws from its own named stream, so switching an effect on never shifts another stream: the
// "with" and "without" effects runs of a dataset share their noise realisation exactly.

#include <cmath>
#include <cstdint>
#include <string_view>

#include "independent_device/units.h"

namespace softwrist::independent {

class Rng {
 public:
  Rng(std::uint64_t seed, std::string_view stream, std::uint64_t index = 0) {
    std::uint64_t h = 1469598103934665603ull;  // FNV-1a hash of the stream name
    for (const char c : stream) {
      h ^= static_cast<unsigned char>(c);
      h *= 1099511628211ull;
    }
    std::uint64_t x = seed ^ (h * 0x9E3779B97F4A7C15ull) ^ ((index + 1) * 0xD1B54A32D192ED03ull);
    for (auto& s : state_) s = splitmix(x);
  }

  std::uint64_t next() {
    const std::uint64_t result = rotl(state_[1] * 5, 7) * 9;
    const std::uint64_t t = state_[1] << 17;
    state_[2] ^= state_[0];
    state_[3] ^= state_[1];
    state_[1] ^= state_[2];
    state_[0] ^= state_[3];
    state_[2] ^= t;
    state_[3] = rotl(state_[3], 45);
    return result;
  }
  // Uniform in [0, 1).
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  // Standard normal deviate (Box-Muller; both deviates of a pair are used).
  double normal() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    const double u1 = 1.0 - uniform();  // (0, 1]
    const double u2 = uniform();
    const double r = std::sqrt(-2.0 * std::log(u1));
    spare_ = r * std::sin(2.0 * kPi * u2);
    has_spare_ = true;
    return r * std::cos(2.0 * kPi * u2);
  }
  double normal(double mean, double sd) { return mean + sd * normal(); }

 private:
  static std::uint64_t splitmix(std::uint64_t& x) {
    std::uint64_t z = (x += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  static std::uint64_t rotl(std::uint64_t v, int k) { return (v << k) | (v >> (64 - k)); }

  std::uint64_t state_[4]{};
  bool has_spare_ = false;
  double spare_ = 0.0;
};

}  // namespace softwrist::independent

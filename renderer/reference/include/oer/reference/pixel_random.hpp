#pragma once
// The random numbers of one pixel: PCG32 (M. E. O'Neill, "PCG: A Family of Simple Fast
// Space-Efficient Statistically Good Algorithms for Random Number Generation", 2014), its
// state and stream chosen from the seed and the pixel's index by SplitMix64 (G. Steele,
// D. Lea and C. Flood, "Fast Splittable Pseudorandom Number Generators", OOPSLA 2014), so
// that a pixel's samples depend on nothing else (neither thread count nor order).
#include <cstdint>

namespace oer::reference {

constexpr std::uint64_t splitmix64(std::uint64_t x) {
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

class PixelRandom {
  public:
    PixelRandom(std::uint64_t seed, std::uint64_t pixel)
        : increment_((splitmix64(seed ^ splitmix64(pixel)) << 1) | 1u) {
        state_ = splitmix64(splitmix64(seed) + pixel) + increment_;
        next();
    }

    std::uint32_t next() {
        const std::uint64_t old = state_;
        state_ = old * 6364136223846793005ull + increment_;
        const auto xorshifted = std::uint32_t(((old >> 18u) ^ old) >> 27u);
        const auto rotation = std::uint32_t(old >> 59u);
        return (xorshifted >> rotation) | (xorshifted << ((32u - rotation) & 31u));
    }

    // Uniform in [0, 1), 53 bits from two draws.
    double uniform() {
        const std::uint64_t bits = (std::uint64_t(next()) << 21) ^ std::uint64_t(next());
        return double(bits & ((1ull << 53) - 1)) * 0x1p-53;
    }

  private:
    std::uint64_t state_ = 0;
    std::uint64_t increment_ = 1;
};

}  // namespace oer::reference

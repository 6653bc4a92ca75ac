// How a SparseHistogram stores its weights (chosen at build time, voxel.h).
// - FloatWeights: one float per entry, the paper's exact sums (default).
// - QuantisedWeights: one 16-bit integer per entry and a power-of-two scale
//   shared by the histogram. A weight sums a class's scores over all of a
//   voxel's pixels in all frames (1e4-1e5 at 5 cm over a long sequence), so a
//   fixed scale would overflow and half floats stop adding scores past 2048;
//   with a shared scale the largest entry keeps 15-16 significant bits, and
//   the scale grows (all entries halved, rounded) when a weight outgrows it.
//   Stored values are rounded with a dither that steps through a
//   low-discrepancy sequence at each write: rounding to nearest would drop
//   every update smaller than half a step once a voxel has seen ~65536 units
//   (its histogram would freeze); dithered, the updates add up on average.
//   Deterministic: the same writes in the same order give the same bits.
// Both keep the histogram's order rule: entry i > entry j compares what is
// stored, ties keep the older entry first.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <utility>

namespace pndt
{
template <int Capacity>
struct FloatWeights
{
    float w[Capacity]{};

    float get(int i) const { return w[i]; }
    void set(int i, float v) { w[i] = v; }
    bool greater(int i, int j) const { return w[i] > w[j]; }
    void swapEntries(int i, int j) { std::swap(w[i], w[j]); }
    float sum(int n) const
    {
        float s = 0;
        for (int i = 0; i < n; ++i) s += w[i];
        return s;
    }
    /// The same stored bits.
    bool operator==(const FloatWeights& o) const { return std::memcmp(w, o.w, sizeof w) == 0; }
};

template <int Capacity>
struct QuantisedWeights
{
    /// Scale of a new histogram: 2^-16, so a single score (<= 1) is stored to
    /// 1.5e-5 and the first rescale happens past a total of 1.0.
    static constexpr int kFirstExponent = -16;
    static constexpr uint32_t kMaxMantissa = 0xFFFF;

    uint16_t m[Capacity]{};
    int8_t exponent = kFirstExponent;  ///< weight = m * 2^exponent
    uint16_t writes = 0;               ///< drives the rounding dither

    float get(int i) const { return float(m[i]) * pow2(exponent); }
    /// Stores v (>= 0, finite), rescaling every entry first if v needs it.
    /// A value the scale represents exactly is stored exactly.
    void set(int i, float v)
    {
        float q = v * pow2(-exponent);
        if (q > float(kMaxMantissa))  // rare: the scale grows (q may be inf here)
        {
            int bits = 0;
            std::frexp(v, &bits);  // v < 2^bits
            int e = std::max(int(exponent), bits - 16);
            q = std::ldexp(v, -e);
            if (q > float(kMaxMantissa))
            {
                ++e;
                q *= 0.5f;
            }
            rescale(e - exponent);
        }
        // In 1/512 steps (exact: q <= 65535). The dither (2d + 1)/512 is a
        // Weyl sequence (40503 / 2^16 ~ the golden ratio) over the writes: d
        // takes each of 0..255 equally often over the counter's period, also
        // along the every-k-th writes one entry may get, so the fraction f
        // carries f of the time; an integer q never carries.
        writes = uint16_t(writes + 1);
        const uint32_t d = (uint32_t(writes) * 40503u >> 8) & 255u;
        m[i] = uint16_t((uint32_t(q * 512.f) + 2 * d + 1) >> 9);
    }
    bool greater(int i, int j) const { return m[i] > m[j]; }
    void swapEntries(int i, int j) { std::swap(m[i], m[j]); }
    /// The same stored state, the dither's phase included.
    bool operator==(const QuantisedWeights& o) const
    {
        return std::memcmp(m, o.m, sizeof m) == 0 && exponent == o.exponent && writes == o.writes;
    }
    float sum(int n) const
    {
        uint32_t s = 0;
        for (int i = 0; i < n; ++i) s += m[i];
        return float(s) * pow2(exponent);
    }

    /// 2^e for the exponents a histogram can reach (|e| < 127), built
    /// directly: no libm call in the per-pixel loop.
    static float pow2(int e)
    {
        const uint32_t bits = uint32_t(e + 127) << 23;
        float f;
        std::memcpy(&f, &bits, sizeof f);
        return f;
    }

private:
    /// Halves every entry k (>= 1) times, rounding to nearest, and grows the scale.
    void rescale(int k)
    {
        for (auto& x : m)
            x = k >= 17 ? 0 : uint16_t((uint32_t(x) + (1u << (k - 1))) >> k);
        exponent = int8_t(exponent + k);
    }
};

}  // namespace pndt

// exp(x) for x ≤ 0 (softmax terms), written so GCC vectorises the loop around it and so the AVX2
// version in panoptic_postprocess.cpp computes the same operations:
// 2^(x·log2 e) = 2^n · 2^f with n integral (rounded by adding 1.5·2^23, which also leaves n in
// the low mantissa bits: no float↔int conversion) and 2^f, f ∈ [−0.5, 0.5], from a degree-5
// polynomial. Relative error < 3e-6 over [−87, 0]; below −87 it returns e^−87.
#pragma once

#include <cstdint>

namespace pndt::seg
{
constexpr float kExpLog2e = 1.44269504f;
constexpr float kExpRound = 12582912.f;  // 1.5·2^23: t + kExpRound rounds t to an integer
constexpr float kExpC1 = 0.693147182f, kExpC2 = 0.240226507f, kExpC3 = 0.0555041087f, kExpC4 = 0.00961812911f,
                kExpC5 = 0.00133335581f;  // 2^f = e^(f·ln 2): its Taylor series to degree 5

inline float fastExpNonPositive(float x)
{
    x = x < -87.f ? -87.f : x;
    const float t = x * kExpLog2e;
    const float r = t + kExpRound;             // = 1.5·2^23 + n exactly
    const float f = t - (r - kExpRound);       // [−0.5, 0.5]
    const float p = 1.f + f * (kExpC1 + f * (kExpC2 + f * (kExpC3 + f * (kExpC4 + f * kExpC5))));
    const uint32_t bits = (__builtin_bit_cast(uint32_t, r) + 127u) << 23;  // low bits of r = n: 2^n
    return p * __builtin_bit_cast(float, bits);  // a bit cast GCC can vectorise (memcpy it cannot)
}

}  // namespace pndt::seg

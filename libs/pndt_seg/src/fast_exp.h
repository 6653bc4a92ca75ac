// exp(x) for x ≤ 0 (softmax terms), written so GCC vectorises the loop around it:
// 2^(x·log2 e) = 2^n · 2^f with n integral (put into the exponent bits) and 2^f, f ∈ [−0.5, 0.5],
// from a degree-5 polynomial. Relative error < 3e-6 over [−87, 0]; below −87 it returns e^−87.
#pragma once

#include <cstdint>

namespace pndt::seg
{
inline float fastExpNonPositive(float x)
{
    x = x < -87.f ? -87.f : x;
    const float t = x * 1.44269504f;                 // log2(e)
    const int n = static_cast<int>(t - 0.5f);       // round to nearest for t ≤ 0
    const float f = t - static_cast<float>(n);       // [−0.5, 0.5]
    // 2^f: Taylor series of e^(f·ln 2) to degree 5 (|f| ≤ 0.5 keeps the error < 3e-6)
    const float p = 1.f + f * (0.693147182f + f * (0.240226507f + f * (0.0555041087f + f * (0.00961812911f + f * 0.00133335581f))));
    const int32_t bits = (n + 127) << 23;
    return p * __builtin_bit_cast(float, bits);  // 2^n; a bit cast GCC can vectorise (memcpy it cannot)
}

}  // namespace pndt::seg

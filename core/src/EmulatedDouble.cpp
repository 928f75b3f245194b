// Float arithmetic that must be evaluated exactly as written, as the shaders evaluate it: no
// fused multiply-add (core/CMakeLists.txt compiles this file with -ffp-contract=off; the pragma
// does the same for Clang wherever the file is built) and no extended precision.

#include "orbis/core/EmulatedDouble.h"

#include <cfloat>
#include <cmath>
#include <limits>

#if defined(__clang__)
#pragma clang fp contract(off)
#endif

static_assert(FLT_EVAL_METHOD == 0, "EmulatedDouble needs float arithmetic evaluated in float, as on a GPU");

namespace orbis {

namespace {

/// Veltkamp's split of a 24-bit significand into two halves of at most 12 bits: 2^12 + 1.
constexpr float kSplitter = 4097.0f;

/// |a| >= |b| or a == 0: s + e == a + b exactly (three operations).
EmulatedDouble fastTwoSum(float a, float b) noexcept
{
    const float s = a + b;
    const float e = b - (s - a);
    return {s, e};
}

EmulatedDouble split(float a) noexcept
{
    const float c = kSplitter * a;
    const float high = c - (c - a);
    const float low = a - high;
    return {high, low};
}

} // namespace

EmulatedDouble EmulatedDouble::fromDouble(double value) noexcept
{
    constexpr double largest = static_cast<double>(std::numeric_limits<float>::max());
    if (std::abs(value) > largest) {
        return {static_cast<float>(std::copysign(largest, value)), 0.0f};
    }
    const float high = static_cast<float>(value);
    // value - high is exact in double: high is value's nearest float.
    return {high, static_cast<float>(value - static_cast<double>(high))};
}

EmulatedDVec3 EmulatedDVec3::fromDVec3(const glm::dvec3& value) noexcept
{
    EmulatedDVec3 result;
    for (int i = 0; i < 3; ++i) {
        const EmulatedDouble component = EmulatedDouble::fromDouble(value[i]);
        result.high[i] = component.high;
        result.low[i] = component.low;
    }
    return result;
}

EmulatedDouble twoSum(float a, float b) noexcept
{
    const float s = a + b;
    const float bVirtual = s - a;
    const float aVirtual = s - bVirtual;
    const float e = (a - aVirtual) + (b - bVirtual);
    return {s, e};
}

EmulatedDouble twoProduct(float a, float b) noexcept
{
    const float p = a * b;
    const EmulatedDouble as = split(a);
    const EmulatedDouble bs = split(b);
    // Each partial product of 12-bit halves is exact; the sum telescopes to a * b - p exactly.
    const float e = ((as.high * bs.high - p) + as.high * bs.low + as.low * bs.high) + as.low * bs.low;
    return {p, e};
}

EmulatedDouble operator+(EmulatedDouble a, EmulatedDouble b) noexcept
{
    // The highs summed without error, the lows folded into the error, then renormalised.
    const EmulatedDouble s = twoSum(a.high, b.high);
    const float e = (s.low + a.low) + b.low;
    return fastTwoSum(s.high, e);
}

EmulatedDouble operator-(EmulatedDouble a) noexcept
{
    return {-a.high, -a.low};
}

EmulatedDouble operator-(EmulatedDouble a, EmulatedDouble b) noexcept
{
    return a + -b;
}

EmulatedDouble operator*(EmulatedDouble a, EmulatedDouble b) noexcept
{
    const EmulatedDouble p = twoProduct(a.high, b.high);
    const float e = p.low + (a.high * b.low + a.low * b.high);
    return fastTwoSum(p.high, e);
}

EmulatedDVec3 operator-(const EmulatedDVec3& a, const EmulatedDVec3& b) noexcept
{
    EmulatedDVec3 result;
    for (int i = 0; i < 3; ++i) {
        const EmulatedDouble d = EmulatedDouble{a.high[i], a.low[i]} - EmulatedDouble{b.high[i], b.low[i]};
        result.high[i] = d.high;
        result.low[i] = d.low;
    }
    return result;
}

glm::vec3 relativeToEye(const EmulatedDVec3& position, const EmulatedDVec3& eye) noexcept
{
    const EmulatedDVec3 d = position - eye;
    return d.high + d.low;
}

EmulatedDouble splitAt65536(double value) noexcept
{
    constexpr double largest = static_cast<double>(std::numeric_limits<float>::max());
    if (!(std::abs(value) <= largest)) {
        return std::isnan(value) ? EmulatedDouble{static_cast<float>(value), 0.0f}
                                 : EmulatedDouble{static_cast<float>(std::copysign(largest, value)), 0.0f};
    }
    // Truncation keeps the split symmetric about zero; value - high is exact in double.
    const double high = std::trunc(value / 65536.0) * 65536.0;
    return {static_cast<float>(high), static_cast<float>(value - high)};
}

EmulatedDVec3 splitAt65536(const glm::dvec3& value) noexcept
{
    EmulatedDVec3 result;
    for (int i = 0; i < 3; ++i) {
        const EmulatedDouble component = splitAt65536(value[i]);
        result.high[i] = component.high;
        result.low[i] = component.low;
    }
    return result;
}

glm::vec3 relativeToEyeSplitAt65536(const EmulatedDVec3& position, const EmulatedDVec3& eye) noexcept
{
    return (position.high - eye.high) + (position.low - eye.low);
}

} // namespace orbis

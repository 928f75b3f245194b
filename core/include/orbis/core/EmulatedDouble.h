#pragma once

#include <glm/vec3.hpp>

namespace orbis {

/// A double carried as two floats, value = high + low, for GPU relative-to-eye rendering (the
/// book's chapter 5, after DSFUN90's double-single arithmetic). The encoding keeps 48
/// significant bits: high + low is within 2^-48 of the double, relative (under 0.03 um at
/// Earth's radius, 0.15 um at geostationary distance), for magnitudes from 1e-30 (below which
/// the low part is subnormal and keeps fewer bits) to the float range.
///
/// The arithmetic below is plain float and follows, operation for operation, what the shaders
/// compute, so that tests on the CPU predict the GPU. Its file is compiled with
/// -ffp-contract=off (core/CMakeLists.txt; plus `#pragma clang fp contract(off)`): a compiler
/// that fuses some multiply-adds and not others (a fused Veltkamp split with an unfused error
/// term) loses the product's error term, and a fused one gives results the GPU may not. The
/// GLSL versions must guard against the same (`precise` where the GLSL version has it).
/// Operands and results must stay below about 1e34 in magnitude, beyond which the float
/// products overflow (the GPU would overflow the same way).
struct EmulatedDouble {
    float high = 0.0f;
    float low = 0.0f;

    /// high = value rounded to float, low = the remainder rounded to float. Values beyond the
    /// float range saturate to high = +-FLT_MAX, low = 0. NaN stays NaN.
    static EmulatedDouble fromDouble(double value) noexcept;
    /// high + low, exactly.
    double toDouble() const noexcept { return static_cast<double>(high) + static_cast<double>(low); }
};

/// Three EmulatedDoubles as the two vec3 vertex attributes (or uniforms) a shader receives.
struct EmulatedDVec3 {
    glm::vec3 high{0.0f};
    glm::vec3 low{0.0f};

    /// Each component encoded as EmulatedDouble::fromDouble does.
    static EmulatedDVec3 fromDVec3(const glm::dvec3& value) noexcept;
    /// high + low per component, exactly.
    glm::dvec3 toDVec3() const noexcept { return glm::dvec3(high) + glm::dvec3(low); }
};

/// s + e == a + b exactly, with s = a + b rounded (Knuth's two-sum, six float operations).
EmulatedDouble twoSum(float a, float b) noexcept;
/// a * b == p + e exactly, with p = a * b rounded (Dekker's product with Veltkamp's split, no
/// fused multiply-add: GLSL 3.3 has none).
EmulatedDouble twoProduct(float a, float b) noexcept;

/// DSFUN90's addition: error within about 2^-44 of |a| + |b|, relative.
EmulatedDouble operator+(EmulatedDouble a, EmulatedDouble b) noexcept;
/// DSFUN90's subtraction: as addition with b negated. For a position and an eye point the
/// result is within about 2^-47 of their distance plus 2^-48 of their size.
EmulatedDouble operator-(EmulatedDouble a, EmulatedDouble b) noexcept;
/// Exact negation.
EmulatedDouble operator-(EmulatedDouble a) noexcept;
/// Double-single product: error within about 2^-45 of |a b|, relative.
EmulatedDouble operator*(EmulatedDouble a, EmulatedDouble b) noexcept;

/// Component-wise subtraction, as operator-(EmulatedDouble, EmulatedDouble).
EmulatedDVec3 operator-(const EmulatedDVec3& a, const EmulatedDVec3& b) noexcept;

/// What the relative-to-eye vertex shader computes: position - eye in double-single, then
/// high + low rounded to one float per component. Its error is relative to the distance from
/// the eye (2^-24 of it, plus the subtraction's), not to the distance from the Earth's centre
/// as with float(position) - float(eye).
glm::vec3 relativeToEye(const EmulatedDVec3& position, const EmulatedDVec3& eye) noexcept;

} // namespace orbis

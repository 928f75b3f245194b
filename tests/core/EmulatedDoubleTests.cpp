#include <orbis/core/EmulatedDouble.h>
#include <orbis/core/Math.h>

#include <glm/geometric.hpp>

#include <catch2/catch.hpp>

#include <cfloat>
#include <cmath>
#include <random>

using namespace orbis;

namespace {

constexpr double kTwoToMinus48 = 3.552713678800501e-15;

/// A random double of either sign in [2^(e-1), 2^e) for e uniform in [minExponent, maxExponent].
double randomDouble(std::mt19937_64& random, int minExponent, int maxExponent)
{
    std::uniform_real_distribution<double> mantissa(0.5, 1.0);
    std::uniform_int_distribution<int> exponent(minExponent, maxExponent);
    const double sign = random() % 2 ? 1.0 : -1.0;
    return sign * std::ldexp(mantissa(random), exponent(random));
}

float randomFloat(std::mt19937_64& random, int minExponent, int maxExponent)
{
    return static_cast<float>(randomDouble(random, minExponent, maxExponent));
}

EmulatedDouble randomPair(std::mt19937_64& random, int minExponent, int maxExponent)
{
    return EmulatedDouble::fromDouble(randomDouble(random, minExponent, maxExponent));
}

glm::dvec3 randomUnit(std::mt19937_64& random)
{
    std::normal_distribution<double> normal;
    return glm::normalize(glm::dvec3(normal(random), normal(random), normal(random)));
}

} // namespace

TEST_CASE("EmulatedDouble keeps 48 bits of a double", "[core][geometry][emulated]")
{
    const auto seed = GENERATE(take(1, random(0u, 1000000u)));
    INFO("seed " << seed);
    std::mt19937_64 random(seed);
    for (int i = 0; i < 100000; ++i) {
        // 2^-100 to 2^120: inside the float range, with a low part above the subnormals.
        const double value = randomDouble(random, -99, 120);
        const EmulatedDouble e = EmulatedDouble::fromDouble(value);
        INFO("value " << value);
        REQUIRE(e.high == static_cast<float>(value));
        // The low float rounds a remainder of at most 2^-24 |value|: 2^-48 |value| (and 1% for
        // the rounding of the bound at powers of two).
        REQUIRE(std::abs(e.toDouble() - value) <= 1.01 * kTwoToMinus48 * std::abs(value));
    }
    // Earth radius and GEO to well under a micrometre (2^-48 x 4.2e7 m = 0.15 um).
    for (double value : {6378137.123456789, 42164000.987654321, -6356752.314245179}) {
        REQUIRE(std::abs(EmulatedDouble::fromDouble(value).toDouble() - value) <= 1.5e-7);
    }
    // Beyond the float range: saturated, finite.
    const EmulatedDouble big = EmulatedDouble::fromDouble(1e300);
    REQUIRE(big.high == FLT_MAX);
    REQUIRE(big.low == 0.0f);
    REQUIRE(EmulatedDouble::fromDouble(-1e39).high == -FLT_MAX);
    const EmulatedDVec3 v = EmulatedDVec3::fromDVec3({1.0 / 3.0, -6378137.1, 1e-30});
    REQUIRE(glm::length(v.toDVec3() - glm::dvec3(1.0 / 3.0, -6378137.1, 1e-30)) <= 6378137.1 * kTwoToMinus48);
}

TEST_CASE("twoSum and twoProduct are error-free", "[core][geometry][emulated]")
{
    // Exact checks. (Contraction everywhere happens to keep them exact: a fused split leaves
    // the whole float in the high half and the fused error term is then exact by itself. Fusing
    // some operations and not others, as a shader compiler may, loses the error term.)
    const auto seed = GENERATE(take(1, random(0u, 1000000u)));
    INFO("seed " << seed);
    std::mt19937_64 random(seed);
    std::uniform_int_distribution<int> shift(-20, 20);
    for (int i = 0; i < 100000; ++i) {
        // Products from 2^-80 to 2^80: their error terms stay clear of float underflow.
        const float a = randomFloat(random, -30, 30);
        const float b = randomFloat(random, 0, 0) * std::ldexp(1.0f, shift(random) + std::ilogb(a));
        INFO("a " << a << " b " << b);
        // Exponents within 21 of each other: the double sum of two floats is exact.
        const EmulatedDouble s = twoSum(a, b);
        REQUIRE(s.high == a + b);
        REQUIRE(static_cast<double>(s.high) + static_cast<double>(s.low) ==
                static_cast<double>(a) + static_cast<double>(b));
        // A product of two floats is exact in double (48 bits).
        const EmulatedDouble p = twoProduct(a, b);
        REQUIRE(p.high == a * b);
        REQUIRE(static_cast<double>(p.high) + static_cast<double>(p.low) ==
                static_cast<double>(a) * static_cast<double>(b));
    }
}

TEST_CASE("EmulatedDouble arithmetic keeps about 44 bits", "[core][geometry][emulated]")
{
    // DSFUN90's double-single bounds: addition within 2^-44 of |a| + |b| (cancellation leaves
    // the error relative to the operands, not the result), product within 2^-44 of |a b|.
    // Measured worst cases are about 2^-47; the double reference rounds at 2^-53.
    const auto seed = GENERATE(take(1, random(0u, 1000000u)));
    INFO("seed " << seed);
    std::mt19937_64 random(seed);
    const double bound = std::ldexp(1.0, -44);
    for (int i = 0; i < 100000; ++i) {
        const EmulatedDouble a = randomPair(random, -30, 30);
        const EmulatedDouble b = i % 3 == 0 ? EmulatedDouble::fromDouble(-a.toDouble() * (1.0 + std::ldexp(1.0, -20)))
                                            : randomPair(random, -30, 30);
        const double x = a.toDouble(), y = b.toDouble();
        INFO("a " << x << " b " << y);
        REQUIRE(std::abs((a + b).toDouble() - (x + y)) <= bound * (std::abs(x) + std::abs(y)));
        REQUIRE(std::abs((a - b).toDouble() - (x - y)) <= bound * (std::abs(x) + std::abs(y)));
        REQUIRE(std::abs((a * b).toDouble() - x * y) <= bound * std::abs(x * y));
        REQUIRE((-a).toDouble() == -x);
    }
}

TEST_CASE("Relative to eye: emulated subtraction stays within 1 cm where float is off by decimetres to metres", "[core][geometry][emulated][hard]")
{
    const auto seed = GENERATE(take(1, random(0u, 1000000u)));
    INFO("seed " << seed);
    std::mt19937_64 random(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    struct Shell {
        const char* name;
        double radius;
        double floatErrorAtLeast; // what plain float must exceed somewhere in the sweep
    };
    // Float spacing is 0.5 m from 4.2e6 to 8.4e6 m and 4 m from 3.4e7 to 6.7e7 m: rounding the
    // position and the eye separately costs up to half of that each, per coordinate.
    const Shell shells[] = {{"Earth radius", 6378137.0, 0.25}, {"GEO", 42164000.0, 2.0}};
    for (const Shell& shell : shells) {
        INFO(shell.name);
        double worstPair = 0.0, worstFloat = 0.0, worstSmallOffsets = 0.0;
        for (int i = 0; i < 50000; ++i) {
            const glm::dvec3 position = shell.radius * randomUnit(random) + glm::dvec3(unit(random), unit(random), unit(random));
            const double offset = std::pow(10.0, 7.0 * unit(random)); // 1 m to 10,000 km
            const glm::dvec3 eye = position + offset * randomUnit(random);
            const glm::dvec3 expected = position - eye; // exact to 2^-53 of the shell: 5 nm at GEO

            const EmulatedDVec3 p = EmulatedDVec3::fromDVec3(position);
            const EmulatedDVec3 e = EmulatedDVec3::fromDVec3(eye);
            const double pairError = glm::length((p - e).toDVec3() - expected);
            const glm::dvec3 gpu(relativeToEye(p, e));
            const double gpuError = glm::length(gpu - expected);
            const glm::dvec3 plain(glm::vec3(position) - glm::vec3(eye));
            const double floatError = glm::length(plain - expected);
            INFO("i " << i << " offset " << offset);
            // The double-single difference: 1 cm (in practice 0.2 um at GEO).
            REQUIRE(pairError <= 0.01);
            // Collapsed to one float per coordinate, as the shader goes on: the error is relative
            // to the distance from the eye, 2^-24 per coordinate (sqrt(3) 2^-24 as a vector),
            // so within 1 cm of the eye up to 100 km (0.7 cm at most there).
            REQUIRE(gpuError <= std::sqrt(3.0) * std::ldexp(offset, -24) + 1e-6);
            if (offset <= 1e5) {
                REQUIRE(gpuError <= 0.01);
                worstSmallOffsets = std::max(worstSmallOffsets, floatError);
            }
            worstPair = std::max(worstPair, pairError);
            worstFloat = std::max(worstFloat, floatError);
        }
        INFO("worst double-single " << worstPair << " m, worst float " << worstFloat << " m, worst float within 100 km " << worstSmallOffsets << " m");
        REQUIRE(worstPair <= 1e-6);
        // Plain float subtraction is off by more than 25 times the 1 cm bound at Earth radius and
        // 200 times at GEO, at every offset, small ones included.
        REQUIRE(worstFloat >= shell.floatErrorAtLeast);
        REQUIRE(worstSmallOffsets >= shell.floatErrorAtLeast);
    }
}

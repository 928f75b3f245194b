#include "RobustPredicates.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace orbis::detail {

namespace {

// Error-free transformations: each returns the rounded result and the exact rounding error, so
// that hi + lo equals the exact result.
struct Pair {
    double hi;
    double lo;
};

Pair twoSum(double a, double b) noexcept
{
    const double s = a + b;
    const double bVirtual = s - a;
    const double aVirtual = s - bVirtual;
    return {s, (a - aVirtual) + (b - bVirtual)};
}

Pair twoDiff(double a, double b) noexcept
{
    const double s = a - b;
    const double bVirtual = a - s;
    const double aVirtual = s + bVirtual;
    return {s, (a - aVirtual) + (bVirtual - b)};
}

Pair twoProduct(double a, double b) noexcept
{
    const double p = a * b;
    return {p, std::fma(a, b, -p)};
}

// The exact sum of up to 16 doubles kept as a nonoverlapping expansion ordered by increasing
// magnitude (each new term is added with a chain of error-free sums); the sign of the sum is the
// sign of its largest nonzero component.
class Expansion {
public:
    void add(double value) noexcept
    {
        double carry = value;
        for (std::size_t i = 0; i < _size; ++i) {
            const Pair s = twoSum(carry, _terms[i]);
            _terms[i] = s.lo;
            carry = s.hi;
        }
        _terms[_size++] = carry;
    }
    int sign() const noexcept
    {
        for (std::size_t i = _size; i-- > 0;) {
            if (_terms[i] != 0.0) {
                return _terms[i] > 0.0 ? 1 : -1;
            }
        }
        return 0;
    }

private:
    std::array<double, 17> _terms{};
    std::size_t _size = 0;
};


} // namespace

int exactOrient2d(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c) noexcept
{
    // det = (ax - cx)(by - cy) - (ay - cy)(bx - cx), each difference split exactly in two parts.
    const Pair acx = twoDiff(a.x, c.x);
    const Pair bcy = twoDiff(b.y, c.y);
    const Pair acy = twoDiff(a.y, c.y);
    const Pair bcx = twoDiff(b.x, c.x);
    Expansion sum;
    for (const double u : {acx.hi, acx.lo}) {
        for (const double v : {bcy.hi, bcy.lo}) {
            const Pair p = twoProduct(u, v);
            sum.add(p.lo);
            sum.add(p.hi);
        }
    }
    for (const double u : {acy.hi, acy.lo}) {
        for (const double v : {bcx.hi, bcx.lo}) {
            const Pair p = twoProduct(u, v);
            sum.add(-p.lo);
            sum.add(-p.hi);
        }
    }
    return sum.sign();
}

bool onSegment(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& p) noexcept
{
    // The box first: it rejects most points without the orientation test.
    return std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= p.y &&
           p.y <= std::max(a.y, b.y) && orient2d(a, b, p) == 0;
}

bool segmentsIntersect(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c, const glm::dvec2& d) noexcept
{
    const int o1 = orient2d(a, b, c);
    const int o2 = orient2d(a, b, d);
    const int o3 = orient2d(c, d, a);
    const int o4 = orient2d(c, d, b);
    if (o1 * o2 < 0 && o3 * o4 < 0) {
        return true;
    }
    return (o1 == 0 && onSegment(a, b, c)) || (o2 == 0 && onSegment(a, b, d)) || (o3 == 0 && onSegment(c, d, a)) ||
           (o4 == 0 && onSegment(c, d, b));
}

} // namespace orbis::detail

#pragma once

#include <cstdint>

namespace orbis {

/// The four-point interpolating subdivision (Dyn, Levin and Gregory; the filter of Losasso and
/// Hoppe 2004) at the midpoint between b and c of four equally spaced samples a, b, c, d:
/// (9 (b + c) - (a + d)) / 16. Exact for cubics, so a smooth surface upsampled from a coarser
/// level shows no facets of the coarse grid (bilinear would).
constexpr double fourPointMidpoint(double a, double b, double c, double d) noexcept
{
    return (9.0 * (b + c) - (a + d)) / 16.0;
}

/// A finer level's post (x, y) (global post numbers of the finer level, spacing half the
/// coarser's) from the coarser level: coarse(X, Y) returns the coarser post (X, Y) as a double.
/// Where x and y are both even the post is a coarse post; where one is odd, the four-point filter
/// along that axis; where both are odd, its tensor product over the 4 x 4 coarse posts around.
/// Reads coarse posts up to two away from the point, which the caller keeps inside the coarser
/// level's window (a finer level lies m - 1 posts or more inside it).
template <typename Coarse>
double fourPointUpsample(const Coarse& coarse, std::int64_t x, std::int64_t y)
{
    // Arithmetic shift: floor division by 2 for negative posts too.
    const std::int64_t X = x >> 1, Y = y >> 1;
    const bool oddX = (x & 1) != 0, oddY = (y & 1) != 0;
    auto alongX = [&](std::int64_t row) {
        return oddX ? fourPointMidpoint(coarse(X - 1, row), coarse(X, row), coarse(X + 1, row), coarse(X + 2, row))
                    : coarse(X, row);
    };
    if (!oddY) {
        return alongX(Y);
    }
    return fourPointMidpoint(alongX(Y - 1), alongX(Y), alongX(Y + 1), alongX(Y + 2));
}

} // namespace orbis

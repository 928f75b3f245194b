#include "orbis/core/ScreenSpaceError.h"

#include "orbis/core/Math.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

namespace orbis {

double screenSpaceError(double geometricErrorMeters, double distanceMeters, double viewportWidthPixels,
                        double fieldOfViewRadians) noexcept
{
    assert(fieldOfViewRadians > 0.0 && fieldOfViewRadians < kPi);
    if (!(geometricErrorMeters > 0.0) || !(viewportWidthPixels > 0.0)) {
        return 0.0;
    }
    if (!(distanceMeters > 0.0)) {
        return std::numeric_limits<double>::infinity();
    }
    constexpr double kSmallestAngle = 1e-9;
    const double fieldOfView = fieldOfViewRadians > kSmallestAngle ? std::min(fieldOfViewRadians, kPi - kSmallestAngle)
                                                                   : kSmallestAngle; // NaN too
    const double halfWidth = std::tan(0.5 * fieldOfView); // in [5e-10, 2e9]
    const double rho = geometricErrorMeters * viewportWidthPixels / (2.0 * distanceMeters * halfWidth);
    if (rho > 0.0 && std::isfinite(rho)) {
        return rho;
    }
    // A factor over- or underflowed (inputs beyond about 1e150): the same quotient in logarithms
    // gives the right 0, +infinity or finite value instead of 0 * infinity.
    return std::exp(std::log(geometricErrorMeters) + std::log(viewportWidthPixels) -
                    std::log(2.0 * halfWidth) - std::log(distanceMeters));
}

} // namespace orbis

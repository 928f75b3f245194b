#pragma once

namespace orbis {

/// The screen-space error in pixels of geometry whose geometric error is geometricErrorMeters,
/// seen from distanceMeters across a viewport viewportWidthPixels wide with a horizontal field
/// of view fieldOfViewRadians: rho = epsilon x / (2 d tan(theta / 2)) (the book's equation 12.1,
/// exact at the centre of the view). Edge cases, never NaN: 0 when the geometric error or the
/// viewport width is <= 0; +infinity when the distance is <= 0 (the viewer touches the volume:
/// refine, as the course says); the field of view is clamped to [1e-9, pi - 1e-9] radians
/// (asserted in (0, pi) in debug); +infinity when the quotient overflows.
double screenSpaceError(double geometricErrorMeters, double distanceMeters, double viewportWidthPixels,
                        double fieldOfViewRadians) noexcept;

} // namespace orbis

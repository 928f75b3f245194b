#pragma once

namespace orbis {

/// Heading (clockwise from north), pitch (up from the horizontal) and roll (clockwise about the
/// view direction), radians. headingPitchRollToView() (Transforms.h) turns one into a view.
struct HeadingPitchRoll {
    double heading = 0.0;
    double pitch = 0.0;
    double roll = 0.0;

    friend bool operator==(const HeadingPitchRoll&, const HeadingPitchRoll&) = default;
};

} // namespace orbis

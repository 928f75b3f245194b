#pragma once

// A double as two floats for GPU relative-to-eye rendering: high = float(x), low = float(x - high).
// Private.

namespace orbis::renderer::detail {

/// Splits x so that double(high) + double(low) holds x to about 48 bits.
///
/// The rounded value passes through a volatile: GCC 12 at -O3 was seen to turn double(float(x)) into
/// x for two vectorised components (GCC may keep values in more precision than their type:
/// -fexcess-precision=fast, its C++ default before GCC 13), which left low = 0. A volatile store
/// forces the rounding.
inline void splitDouble(double x, float& high, float& low) noexcept
{
    volatile float rounded = static_cast<float>(x);
    high = rounded;
    low = static_cast<float>(x - static_cast<double>(high));
}

} // namespace orbis::renderer::detail

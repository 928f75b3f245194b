#pragma once

namespace orbis {

/// How depth precision is won per frame (ARCHITECTURE.md, "Precision rules").
enum class DepthStrategy {
    Automatic,     ///< "auto": the cheapest strategy that resolves the frame
    MultiFrustum,  ///< "multifrustum"
    Logarithmic,   ///< "logarithmic"
    Complementary, ///< "complementary": reversed floating-point depth
    Single,        ///< "single": one frustum, for comparisons
};

} // namespace orbis

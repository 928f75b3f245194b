#pragma once

// The precision measurements of docs/precision.md, as functions: the bench's tables, the tests'
// claims and the chapter 5 and 6 examples call the same code. Not part of the installed library:
// the static library orbis_precision_measurement (bench/measurement/CMakeLists.txt).

#include <orbis/core/Ellipsoid.h>
#include <orbis/core/Geodetic.h>
#include <orbis/scene/ClipmapTerrain.h>
#include <orbis/scene/DepthStrategy.h>
#include <orbis/scene/FrameStatistics.h>
#include <orbis/scene/VertexTransform.h>

#include <cstddef>
#include <cstdint>

namespace orbis::renderer {
class Context;
} // namespace orbis::renderer

namespace orbis::bench {

// ---- Vertex transform jitter (book chapter 5) ------------------------------------------------

struct JitterOptions {
    int width = 1920;  ///< the window the error is counted in pixels of
    int height = 1080;
    double fieldOfViewYRadians = 0.7853981633974483; ///< 45 degrees
    int gridSize = 9;  ///< gridSize^2 points spread over the middle of the view
    /// The measured points belong to an object whose bounding sphere is this large, centred this
    /// far to one side of them (a 200 km terrain tile or polyline seen from near one end): the
    /// case where relative-to-centre degrades.
    double objectRadiusMeters = 100e3;
};

/// Error of the GPU's window positions against a double-precision reference; infinite when the
/// GPU put a point at or behind the eye (relative to world at GEO, 1 m away).
struct JitterResult {
    double maxPixels = 0.0;
    double maxMeters = 0.0; ///< the same error as a distance across the view at the point's depth
};

/// Points around `target` seen by a camera `eyeDistance` away along the ellipsoid's normal at
/// target (looking at it): the vertex shader MeshPrimitive uses for `transform`, its gl_Position
/// read back with transform feedback, projected to the window in double, against the window
/// position P V p computed in double from the double positions. Automatic is resolved as a
/// MeshPrimitive would resolve it for the frame.
JitterResult measureVertexJitter(renderer::Context& context, scene::VertexTransform transform, const glm::dvec3& target,
                                 double eyeDistance, const JitterOptions& options = {});

/// Clipmap terrain's jitter: its window error where the eye stands over the ground.
struct ClipmapJitterResult {
    JitterResult error;        ///< maxMeters: the worst vertex's error as a distance at its depth
    std::size_t vertices = 0;  ///< measured: in front of the eye and in the view
    std::size_t within10m = 0; ///< of them, within 10 m of the eye
    double groundHeight = 0.0;   ///< the drawn ground's height above the ellipsoid under the eye
    double eyeAboveGround = 0.0; ///< the eye's height over it, as measured
    int finestLevelDrawn = -1;
    bool converged = false;
};

/// ClipmapTerrain made from `clipmap` (its loader should be deterministic) over `place`, the eye
/// `eyeAboveGround` over the ground it draws there looking north 20 degrees down (converged from
/// 9 km first): every drawn vertex's clip position read back from the clipmap's own vertex shader
/// (ClipmapTerrain::captureDrawnClipPositions), projected to the window in double, against P V p
/// of the same triangles computed in double (ClipmapTerrain::drawnTriangles).
ClipmapJitterResult measureClipmapJitter(renderer::Context& context, const scene::ClipmapTerrainOptions& clipmap,
                                         const Geodetic2D& place, double eyeAboveGround, const JitterOptions& options = {});

/// A point on the WGS84 surface, 700 km above it and at geostationary height (35,786 km), above
/// (10 E, 45 N): the jitter measurement's targets.
glm::dvec3 jitterTarget(double heightMeters);

// ---- Z-fighting (book chapter 6, course chapter 2) --------------------------------------------

struct ZFightingOptions {
    int size = 64;               ///< square image, pixels
    double nearObjectDistance = 1.0; ///< a small cube this far in front of the eye (0: none)
    double nearLimit = 1.0;          ///< MultiFrustumOptions::nearLimit: Single's fixed near plane
    /// Tilt the squares by about 1 % of the distance across the view (see measureZFighting);
    /// false: both face the eye squarely, every pixel at one depth (the lucky case).
    bool tilted = true;
};

struct ZFightingResult {
    double wrongFraction = 0.0; ///< of the pixels where the near square is in front
    int pixels = 0;
    scene::FrameStatistics statistics; ///< of the first of the four frames
};

/// Two parallel squares nearly facing the eye, the near one `distance` away at its middle and the
/// far one `separation` behind it (drawn once half as large again and once smaller: a pixel is
/// wrong when it is wrong in either, since triangles of different sizes round their depths
/// differently, which may favour either order), at Earth scale (the eye 10 m over the North Pole
/// looking up), rendered by a Scene under `strategy` at options.size square. They are tilted so
/// that their distance changes by about 1 % across the view: the counted pixels sample many depth
/// steps, not one, and a rounding that happens to separate two constant depths does not pass for
/// precision. The far square is submitted first, so a depth tie leaves it showing and counts as wrong. A
/// small cube options.nearObjectDistance from the eye, in a corner, makes the frame span from there
/// to the squares, as a view with an aircraft in front of distant terrain does. Offsets from the
/// eye are rounded to float as the vertex stage sees them (DSFUN90 relative to eye, exact to that
/// rounding), so that only depth is measured; separations below the float spacing at `distance`
/// (1 m at 10,000 km) are raised to it.
ZFightingResult measureZFighting(renderer::Context& context, scene::DepthStrategy strategy, double distance, double separation,
                                 const ZFightingOptions& options = {});

/// The smallest separation at which measureZFighting finds no pixel wrongly ordered, nor at any
/// larger one tried: separations from `distance` down by factors of 10^(1/stepsPerDecade) to the
/// float spacing at `distance` (returned when even that is resolved); infinity when `distance`
/// itself is not. Wrong pixels come and go as the depth steps fall, hence the scan from above.
double measureMinimumSeparation(renderer::Context& context, scene::DepthStrategy strategy, double distance,
                                const ZFightingOptions& options = {}, int stepsPerDecade = 4);

// ---- The two-sum on the GPU ---------------------------------------------------------------------

/// How og_emulatedDoubleSubtract is compiled: with `precise`, with og_opaqueOne, or neither.
enum class TwoSumProtection : std::uint8_t { Precise, OpaqueOne, Unprotected };

struct TwoSumSurvival {
    std::size_t samples = 0;
    std::size_t errorTermMatters = 0;   ///< samples where the two-sum differs from (aHigh - bHigh) + (aLow - bLow)
    std::size_t matchesTwoSum = 0;      ///< GPU result bit for bit equal to the CPU's relativeToEye
    std::size_t matchesCollapsed = 0;   ///< ... equal to the collapsed (reassociated) form
};

/// Runs og_emulatedDoubleSubtract on the GPU for random positions at Earth radius and GEO with eyes
/// 1 m to 10,000 km away, reads the results back with transform feedback and compares them bit for
/// bit with the CPU mirror. Throws orbis::Error for Precise on a device without GL_ARB_gpu_shader5.
TwoSumSurvival measureTwoSumSurvival(renderer::Context& context, TwoSumProtection protection, std::size_t samples = 4096,
                                     std::uint64_t seed = 5);

} // namespace orbis::bench

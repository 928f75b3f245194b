#include "GoldenImage.h"
#include "SceneTestSupport.h"
#include "VectorTestSupport.h"

#include <orbis/core/BoxTessellator.h>
#include <orbis/scene/FeaturePrimitives.h>
#include <orbis/scene/MeshPrimitive.h>
#include <orbis/scene/PolylineCollection.h>
#include <orbis/scene/SceneBuilder.h>
#include <orbis/world/SceneFile.h>

#include <glm/geometric.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <span>

using namespace orbis;
using namespace orbis::world;
using namespace orbis::scene;
using namespace orbis::test;
using Catch::Matchers::WithinAbs;

namespace {

const Ellipsoid kEarth = Ellipsoid::wgs84();
const glm::ivec4 kRedPixel(255, 0, 0, 255);

/// The chord sag bound the class documents: a (a / b)^2 (1 - cos(g / 2)), with its 1% margin.
double documentedLift(double granularity)
{
    const double a = kEarth.maximumRadius();
    const double b = kEarth.minimumRadius();
    return 1.01 * a * (a / b) * (a / b) * (1.0 - std::cos(0.5 * granularity));
}

PolylineStyle solid(const glm::vec4& color, float width)
{
    PolylineStyle style;
    style.color = color;
    style.widthPixels = width;
    return style;
}

/// The unlit blue globe and, over it, a red line `widthPixels` wide through `positions` (closed
/// when `loop`) in a collection of its own made with `options`.
void addRedLineOverGlobe(Scene& scene, std::span<const Geodetic3D> positions, float widthPixels,
                         const PolylineCollectionOptions& options = {}, bool loop = false)
{
    auto lines = std::make_shared<PolylineCollection>(kEarth, options);
    lines->add(positions, solid({1, 0, 0, 1}, widthPixels), loop);
    scene.add(unlitGlobe(kEarth, kBlue));
    scene.add(lines);
}

} // namespace

TEST_CASE("A polyline from 179 E to 179 W crosses the antimeridian the short way", "[polyline][antimeridian]")
{
    const Geodetic3D ends[] = {Geodetic3D::fromDegrees(179.0, 10.0), Geodetic3D::fromDegrees(-179.0, 10.0)};
    for (const CurveType curve : {CurveType::PlaneSection, CurveType::Geodesic}) {
        INFO((curve == CurveType::PlaneSection ? "plane section" : "geodesic"));
        PolylineCollectionOptions options;
        options.granularityRadians = toRadians(0.25);
        options.curve = curve;
        PolylineCollection lines(kEarth, options);
        lines.add(ends);
        const auto positions = lines.positions(0);
        // 2 degrees of longitude at 10 N subtend 1.97 degrees: 8 pieces of at most 0.25.
        REQUIRE(positions.size() == 9);
        double length = 0.0;
        for (std::size_t i = 0; i < positions.size(); ++i) {
            const Geodetic3D g = kEarth.toGeodetic3D(positions[i]);
            REQUIRE(std::abs(g.longitude) >= toRadians(179.0) - 1e-12);
            if (i > 0) {
                length += glm::distance(positions[i - 1], positions[i]);
            }
        }
        // The short way is 219 km (2 degrees of longitude at 10 N); the long way 39,200 km.
        REQUIRE_THAT(length, WithinAbs(219.3e3, 0.5e3));
    }

    // Drawn: seen from over the antimeridian the line spans the view between its ends; seen from
    // over the prime meridian nothing of it shows, and its commands are culled below the horizon.
    Scene scene(kEarth);
    addRedLineOverGlobe(scene, ends, 5.0f);
    const int size = 96;
    lookDownAt(scene, Geodetic3D::fromDegrees(180.0, 10.0), 1e6);
    const RenderedFrame across = renderFrame(scene, size, size);
    const glm::ivec2 west = projectToPixel(scene, kEarth.toCartesian(ends[0]), size, size);
    const glm::ivec2 east = projectToPixel(scene, kEarth.toCartesian(ends[1]), size, size);
    REQUIRE(west.x < size / 2 - 10);
    REQUIRE(east.x > size / 2 + 10);
    for (int x = west.x + 2; x <= east.x - 2; ++x) {
        INFO("x " << x << ": " << describePixel(across.image, x, size / 2));
        REQUIRE(countPixelsNear(across.image, kRedPixel, 2, x, size / 2 - 3, x + 1, size / 2 + 4) >= 3);
    }
    REQUIRE(countPixelsNear(across.image, kRedPixel, 2, 0, 0, west.x - 3, size) == 0);
    REQUIRE(countPixelsNear(across.image, kRedPixel, 2, east.x + 4, 0, size, size) == 0);

    lookDownAt(scene, Geodetic3D::fromDegrees(0.0, 10.0), 2e7);
    const RenderedFrame opposite = renderFrame(scene, size, size);
    REQUIRE(countPixelsNear(opposite.image, kRedPixel, 60) == 0);
    REQUIRE(opposite.statistics.commandsCulledByHorizon == 1);
}

TEST_CASE("No segment of any country border dips below the ellipsoid, at any granularity", "[polyline][natural-earth]")
{
    // Every drawn segment is sampled at 16 points with the exact Ellipsoid::toGeodetic3D. Tolerance
    // 1 mm: the conversion and the sums are good to nanometres, while an uncompensated chord dips
    // by 2.4 m at 0.1 degrees and 243 m at 1 degree.
    const double tolerance = 1e-3;
    for (const CurveType curve : {CurveType::PlaneSection, CurveType::Geodesic}) {
        for (const double degrees : {5.0, 1.0, 0.25}) {
            const double g = toRadians(degrees);
            INFO((curve == CurveType::PlaneSection ? "plane section" : "geodesic") << ", granularity " << degrees);
            FeatureStyle style;
            style.fill = false;
            style.curve = curve;
            style.granularityRadians = g;
            const FeaturePrimitives primitives = buildFeaturePrimitives(kEarth, countries110m(), style);
            const PolylineCollection& borders = *primitives.borders;
            REQUIRE(borders.size() >= 280); // every ring of 177 countries, holes included

            double lowest = 1e30;
            double highestAboveLift = -1e30;
            double widest = 0.0;
            double largestLift = 0.0;
            int degenerate = 0;
            for (std::size_t i = 0; i < borders.size(); ++i) {
                const auto p = borders.positions(i);
                if (p.size() < 2) {
                    ++degenerate;
                    continue;
                }
                const std::size_t segments = borders.isLoop(i) ? p.size() : p.size() - 1;
                largestLift = std::max(largestLift, borders.liftMeters(i));
                for (std::size_t s = 0; s < segments; ++s) {
                    const glm::dvec3& a = p[s];
                    const glm::dvec3& b = p[(s + 1) % p.size()];
                    widest = std::max(widest, std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b)));
                    for (int k = 0; k <= 16; ++k) {
                        const double h = kEarth.toGeodetic3D(glm::mix(a, b, k / 16.0)).height;
                        lowest = std::min(lowest, h);
                        highestAboveLift = std::max(highestAboveLift, h - borders.liftMeters(i));
                    }
                }
            }
            REQUIRE(degenerate == 1); // North Korea's ring of one position four times
            INFO("lowest " << lowest << " m, largest lift " << largestLift << " m, widest segment "
                           << toDegrees(widest) << " deg");
            REQUIRE(lowest >= -tolerance);
            // The lift is what the class documents for the widest piece, and it is tight: the deepest chord comes down
            // to within 3% of the lift of the surface (the bound's 1% margin and the ellipsoid's
            // curvature varying with place and direction, 0.7%).
            // (widest is measured between lifted positions, moved along geodetic normals, which
            // turns the angle by a few 1e-6 of itself.)
            REQUIRE(largestLift <= documentedLift(widest) * (1.0 + 1e-5));
            REQUIRE(lowest <= 0.03 * largestLift);
            // Vertices at the lift, chords below them.
            REQUIRE(highestAboveLift <= tolerance);
            // Pieces no wider than the granularity (the geodesic spaces its points on an auxiliary
            // sphere: up to 0.4% wider at the centre, Geodesic.h).
            REQUIRE(widest <= g * (curve == CurveType::PlaneSection ? 1.0 + 1e-12 : 1.005));
        }
    }
}

TEST_CASE("Wide polylines draw their colour, outline, mitred joins and translucency", "[polyline][golden]")
{
    auto lines = std::make_shared<PolylineCollection>(kEarth);
    PolylineStyle outlined = solid({1, 0, 0, 1}, 7.0f);
    outlined.outlineColor = {1, 1, 1, 1};
    outlined.outlineWidthPixels = 2.0f;
    const Geodetic3D across[] = {Geodetic3D::fromDegrees(0, 45), Geodetic3D::fromDegrees(20, 45)};
    const Geodetic3D upwards[] = {Geodetic3D::fromDegrees(10, 38), Geodetic3D::fromDegrees(10, 52)};
    const Geodetic3D zigzag[] = {Geodetic3D::fromDegrees(12, 38.5), Geodetic3D::fromDegrees(15, 42),
                                 Geodetic3D::fromDegrees(18, 38.5), Geodetic3D::fromDegrees(20, 41)};
    const Geodetic3D ring[] = {Geodetic3D::fromDegrees(2, 48), Geodetic3D::fromDegrees(7, 48),
                               Geodetic3D::fromDegrees(7, 51), Geodetic3D::fromDegrees(2, 51)};
    lines->add(across, outlined);
    lines->add(upwards, solid({0, 1, 0, 0.5f}, 5.0f));
    lines->add(zigzag, solid({1, 1, 0, 1}, 6.0f));
    lines->add(ring, solid({0, 1, 1, 1}, 3.0f), true);

    Scene scene(kEarth);
    scene.add(unlitGlobe(kEarth, {0.2f, 0.2f, 0.2f, 1.0f}));
    scene.add(lines);
    lookDownAt(scene, Geodetic3D::fromDegrees(10, 45), 3e6);
    const int size = 128;
    const RenderedFrame frame = renderFrame(scene, size, size);
    REQUIRE(frame.statistics.opaquePasses == 1);
    REQUIRE(frame.statistics.translucentPasses == 1);

    // The red line's centre, and its white outline 4.5 to 6.5 pixels from the centre.
    const glm::ivec2 red = projectToPixel(scene, kEarth.toCartesian(Geodetic3D::fromDegrees(4, 45.4)), size, size);
    INFO("red centre " << describePixel(frame.image, red.x, red.y));
    REQUIRE(pixelNear(frame.image, red.x, red.y, kRedPixel, 2));
    REQUIRE(countPixelsNear(frame.image, {255, 255, 255, 255}, 2, red.x, red.y - 8, red.x + 1, red.y - 3) >= 1);
    REQUIRE(countPixelsNear(frame.image, {255, 255, 255, 255}, 2, red.x, red.y + 3, red.x + 1, red.y + 8) >= 1);
    // The translucent green line: half green over the grey globe (51 -> 25 or 26, 153).
    const glm::ivec2 green = projectToPixel(scene, kEarth.toCartesian(Geodetic3D::fromDegrees(10, 40)), size, size);
    INFO("green " << describePixel(frame.image, green.x, green.y));
    REQUIRE(pixelNear(frame.image, green.x, green.y, {26, 153, 26, 255}, 2));

    ORBIS_REQUIRE_GOLDEN(frame.image, "scene/polylines_styles", GoldenTolerance{3, 0.002});
}

TEST_CASE("Lines on the ray-cast globe win the depth test in a frustum 1000 times deeper than its near plane", "[polyline][zfighting]")
{
    // A marker 10 km in front of the eye pulls the near plane in: the globe 2,000 km away is drawn
    // in a frustum from 10 km to 10,000 km, whose depth step there is about 24 m, far more than
    // the lift of a line at 0.02 degree granularity (0.1 m). The line runs through the middle of
    // the view, where the surface faces the eye, so that the depth step is what it fights over.
    // Without the depth offset it loses at many pixels; with it every pixel of its centre shows it.
    const Geodetic3D below = Geodetic3D::fromDegrees(0, 0);
    const glm::dvec3 eye = kEarth.toCartesian(Geodetic3D(below.longitude, below.latitude, 2e6));
    const int size = 128;
    auto centreRedFraction = [&](bool depthOffset, FrameStatistics* statistics) {
        PolylineCollectionOptions options;
        options.granularityRadians = toRadians(0.02);
        options.depthOffset = depthOffset;
        const Geodetic3D ends[] = {Geodetic3D::fromDegrees(-5, 0), Geodetic3D::fromDegrees(5, 0)};
        Scene scene(kEarth);
        addRedLineOverGlobe(scene, ends, 3.0f, options);
        scene.camera().lookAt(eye, kEarth.toCartesian(below), {0, 0, 1});
        // In a corner of the view, 10 km out.
        const glm::dvec3 marker = eye + 1e4 * glm::normalize(kEarth.toCartesian(below) - eye) + glm::dvec3(0, 3e3, 3e3);
        scene.add(std::make_shared<MeshPrimitive>(BoxTessellator::cube(marker, 5.0), glm::vec4(0, 1, 0, 1)));
        const RenderedFrame frame = renderFrame(scene, size, size);
        if (statistics) {
            *statistics = frame.statistics;
        }
        int red = 0;
        int total = 0;
        for (double longitude = -1.0; longitude <= 1.0; longitude += 0.01) {
            const glm::ivec2 p =
                projectToPixel(scene, kEarth.toCartesian(Geodetic3D::fromDegrees(longitude, 0)), size, size);
            red += pixelNear(frame.image, p.x, p.y, kRedPixel, 2) ? 1 : 0;
            ++total;
        }
        return static_cast<double>(red) / total;
    };
    FrameStatistics statistics;
    const double withOffset = centreRedFraction(true, &statistics);
    const double without = centreRedFraction(false, nullptr);
    INFO("frustums " << statistics.frustums.size() << ", nearest " << statistics.frustums.front().nearDistance
                     << " m; red with the offset " << withOffset << ", without " << without);
    REQUIRE(statistics.frustums.front().nearDistance < 1.1e4);
    REQUIRE(statistics.frustums.front().farDistance > 2e6);
    REQUIRE(withOffset == 1.0);
    REQUIRE(without < 0.5);
}

TEST_CASE("A wide line seen at a grazing angle keeps its whole width on the globe", "[polyline][zfighting]")
{
    // The eye 3 km up looks north along the surface; an east-west line 60 km ahead is seen at about
    // 5 degrees. Its near side would sink into the globe by metresPerPixel / tan(5 deg) per pixel
    // without the slope term of the depth offset.
    const glm::dvec3 eye = kEarth.toCartesian(Geodetic3D::fromDegrees(0, 0, 3e3));
    const glm::dvec3 target = kEarth.toCartesian(Geodetic3D::fromDegrees(0, 0.54, 0));
    const int size = 128;
    auto redRows = [&](bool depthOffset) {
        PolylineCollectionOptions options;
        options.granularityRadians = toRadians(0.01);
        options.depthOffset = depthOffset;
        const Geodetic3D ends[] = {Geodetic3D::fromDegrees(-1, 0.54), Geodetic3D::fromDegrees(1, 0.54)};
        Scene scene(kEarth);
        addRedLineOverGlobe(scene, ends, 9.0f, options);
        scene.camera().lookAt(eye, target, {0, 0, 1});
        const Image image = renderFrame(scene, size, size).image;
        return countPixelsNear(image, kRedPixel, 2, size / 2, 0, size / 2 + 1, size);
    };
    const int with = redRows(true);
    const int without = redRows(false);
    INFO("rows of red in the middle column: with the offset " << with << ", without " << without);
    REQUIRE(with >= 8); // 9 pixels wide, its anti-aliased edges aside
    REQUIRE(without < with);
}

TEST_CASE("A world of borders is drawn in groups the scene culls, and setStyle recolours and hides one line", "[polyline][culling]")
{
    FeatureStyle style;
    style.fill = false;
    style.border = solid({1, 0, 0, 1}, 2.0f);
    const FeaturePrimitives primitives = buildFeaturePrimitives(kEarth, countries110m(), style);
    PolylineCollection& borders = *primitives.borders;
    Scene scene(kEarth);
    scene.add(unlitGlobe(kEarth, kBlue));
    primitives.addTo(scene);
    lookDownAt(scene, Geodetic3D::fromDegrees(20, 0), 8e6); // Africa
    const int size = 96;
    const RenderedFrame first = renderFrame(scene, size, size);
    const std::size_t groups = first.statistics.commandsSubmitted - 1;
    INFO(first.statistics.toText());
    REQUIRE(groups >= 20);
    REQUIRE(groups <= 30);
    REQUIRE(first.statistics.commandsCulledByHorizon >= groups / 3);
    REQUIRE(countPixelsNear(first.image, kRedPixel) > 100);

    // A line added after the first frame rebuilds the buffers; setStyle then rewrites its colour
    // and hides it.
    const Geodetic3D square[] = {Geodetic3D::fromDegrees(15, -5), Geodetic3D::fromDegrees(25, -5),
                                 Geodetic3D::fromDegrees(25, 5), Geodetic3D::fromDegrees(15, 5)};
    const std::size_t added = borders.add(square, solid({0, 1, 0, 1}, 3.0f), true);
    const RenderedFrame withSquare = renderFrame(scene, size, size);
    REQUIRE(countPixelsNear(withSquare.image, {0, 255, 0, 255}) > 20);
    borders.setStyle(added, solid({1, 1, 0, 1}, 3.0f));
    const RenderedFrame recoloured = renderFrame(scene, size, size);
    REQUIRE(countPixelsNear(recoloured.image, {0, 255, 0, 255}) == 0);
    REQUIRE(countPixelsNear(recoloured.image, {255, 255, 0, 255}) > 20);
    PolylineStyle hiddenStyle = borders.style(added);
    hiddenStyle.show = false;
    borders.setStyle(added, hiddenStyle);
    const RenderedFrame hidden = renderFrame(scene, size, size);
    REQUIRE(countPixelsNear(hidden.image, {255, 255, 0, 255}) == 0);
    REQUIRE(countPixelsNear(hidden.image, kRedPixel) > 100);
}

TEST_CASE("Relative to centre and relative to eye draw the same lines", "[polyline][precision]")
{
    auto render = [](VertexEncoding encoding) {
        PolylineCollectionOptions options;
        options.encoding = encoding;
        options.granularityRadians = toRadians(0.01);
        const Geodetic3D square[] = {Geodetic3D::fromDegrees(2.30, 48.85), Geodetic3D::fromDegrees(2.36, 48.85),
                                     Geodetic3D::fromDegrees(2.36, 48.87), Geodetic3D::fromDegrees(2.30, 48.87)};
        Scene scene(kEarth);
        addRedLineOverGlobe(scene, square, 4.0f, options, true);
        lookDownAt(scene, Geodetic3D::fromDegrees(2.33, 48.86), 8e3);
        return renderFrame(scene, 96, 96).image;
    };
    const Image relativeToEye = render(VertexEncoding::RelativeToEye);
    const Image relativeToCenter = render(VertexEncoding::RelativeToCenter);
    REQUIRE(countPixelsNear(relativeToEye, kRedPixel) > 200);
    // Both precise to millimetres here (one group 2 km across): at most a few edge pixels differ.
    const ImageDifference difference = compareImages(relativeToCenter, relativeToEye, 8);
    INFO("differing pixels " << difference.differingPixels);
    REQUIRE(difference.differingFraction < 0.005);
}

TEST_CASE("Empty collections and lines of fewer than two positions submit nothing", "[polyline]")
{
    auto lines = std::make_shared<PolylineCollection>(kEarth);
    Scene scene(kEarth);
    scene.add(lines);
    lookDownAt(scene, Geodetic3D::fromDegrees(0, 0), 1e7);
    REQUIRE_FALSE(lines->boundingSphere().has_value());
    REQUIRE(renderFrame(scene, 16, 16).statistics.commandsSubmitted == 0);

    const Geodetic3D one[] = {Geodetic3D::fromDegrees(0, 0)};
    const Geodetic3D twice[] = {Geodetic3D::fromDegrees(0, 0), Geodetic3D::fromDegrees(0, 0)};
    REQUIRE(lines->add(one) == 0);
    REQUIRE(lines->add(twice) == 1);
    REQUIRE(lines->positions(1).empty());
    REQUIRE(lines->segmentCount() == 0);
    REQUIRE(renderFrame(scene, 16, 16).statistics.commandsSubmitted == 0);
}

TEST_CASE("Scene files draw GeoJSON layers as borders and fills, and polyline layers as lines", "[polyline][polygon][scenefile]")
{
    const std::string text = R"({"version": 2,
        "camera": {"position": {"lon": 20, "lat": 10, "height": 15000000}, "target": {"lon": 20, "lat": 10, "height": 0}},
        "globe": {"method": "raycast"},
        "layers": [
          {"type": "geojson", "source": "natural-earth/countries-110m.geojson",
           "stroke": {"color": "#ff0000", "width": 2}, "fill": {"color": "#00ff00"}},
          {"type": "polyline", "positions": [[-10, -30], [50, -30]], "width": 4, "color": "#ffff00"}]})";
    const SceneDescription description = parseSceneText(text, "layers.json", ORBIS_SOURCE_DIR "/data");
    Scene scene(kEarth);
    populateScene(description, scene);
    REQUIRE(scene.primitives().size() == 4); // globe, fills, borders, line
    const Image image = renderFrame(scene, 96, 96).image;
    REQUIRE(countPixelsNear(image, {0, 255, 0, 255}) > 300);   // Africa filled
    REQUIRE(countPixelsNear(image, kRedPixel) > 50);            // its borders
    REQUIRE(countPixelsNear(image, {255, 255, 0, 255}) > 40);  // the line across the South Atlantic and Africa

    // A layer that cannot be drawn (here a model whose file is missing) names itself.
    const std::string points = R"({"version": 2, "layers": [{"type": "model", "source": "m.glb",
        "position": {"lon": 0, "lat": 0}}]})";
    const SceneDescription unsupported =
        parseSceneText(points, "model.json", ORBIS_SOURCE_DIR "/data", SceneParseOptions{false});
    Scene other(kEarth);
    REQUIRE_THROWS_WITH(populateScene(unsupported, other), Catch::Contains("/layers/0: ") && Catch::Contains("m.glb: no such file"));
}

TEST_CASE("Scene file layers draw their lines at the granularity and along the curve they name", "[polyline][scenefile]")
{
    const Geodetic3D ends[] = {Geodetic3D::fromDegrees(-10, -30), Geodetic3D::fromDegrees(50, -30)};
    const auto linesOf = [](const std::string& layer) {
        const std::string text = R"({"version": 2, "layers": [)" + layer + "]}";
        Scene scene(kEarth);
        populateScene(parseSceneText(text, "lines.json", ORBIS_SOURCE_DIR "/data"), scene);
        std::vector<std::shared_ptr<PolylineCollection>> lines;
        for (const auto& primitive : scene.primitives()) {
            if (auto collection = std::dynamic_pointer_cast<PolylineCollection>(primitive)) {
                lines.push_back(std::move(collection));
            }
        }
        return lines;
    };

    // A polyline layer draws what a PolylineCollection with the same options draws.
    for (const auto& [curveName, curve] : {std::pair{"section", CurveType::PlaneSection}, std::pair{"geodesic", CurveType::Geodesic}}) {
        INFO(curveName);
        const auto fromFile = linesOf(std::string(R"({"type": "polyline", "positions": [[-10, -30], [50, -30]], "granularity": 0.5, "curve": ")") +
                                      curveName + "\"}");
        REQUIRE(fromFile.size() == 1);
        PolylineCollectionOptions options;
        options.granularityRadians = toRadians(0.5);
        options.curve = curve;
        PolylineCollection expected(kEarth, options);
        expected.add(ends);
        const auto drawn = fromFile[0]->positions(0);
        REQUIRE(std::vector<glm::dvec3>(drawn.begin(), drawn.end()) ==
                std::vector<glm::dvec3>(expected.positions(0).begin(), expected.positions(0).end()));
    }
    const auto coarse = linesOf(R"({"type": "polyline", "positions": [[-10, -30], [50, -30]]})");
    const auto fine = linesOf(R"({"type": "polyline", "positions": [[-10, -30], [50, -30]], "granularity": 0.5})");
    const auto geodesic = linesOf(R"({"type": "polyline", "positions": [[-10, -30], [50, -30]], "granularity": 0.5, "curve": "geodesic"})");
    // 60 degrees of longitude at 30 S subtend 51.3 degrees: 52 pieces at 1 degree, 103 at 0.5.
    REQUIRE(coarse[0]->positions(0).size() == 53);
    REQUIRE(fine[0]->positions(0).size() == 104);
    // The geodesic leaves the plane section by kilometres halfway (its own route, not a relabelling).
    const std::size_t middle = fine[0]->positions(0).size() / 2;
    REQUIRE(glm::distance(fine[0]->positions(0)[middle], geodesic[0]->positions(0)[middle]) > 1e3);

    // A GeoJSON layer's borders follow its granularity too: finer cuts give more vertices.
    const std::string borders = R"({"type": "geojson", "source": "natural-earth/countries-110m.geojson")";
    const std::size_t atOneDegree = linesOf(borders + "}")[0]->vertexCount();
    const std::size_t atQuarterDegree = linesOf(borders + R"(, "granularity": 0.25})")[0]->vertexCount();
    REQUIRE(atQuarterDegree > 2 * atOneDegree);
}

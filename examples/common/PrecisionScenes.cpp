#include "PrecisionScenes.h"

#include "SceneExample.h"

#include <orbis/core/Transforms.h>
#include <orbis/renderer/Font.h>
#include <orbis/scene/FontLookup.h>
#include <orbis/scene/Globe.h>
#include <orbis/scene/MeshPrimitive.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>

using namespace orbis::renderer;
using namespace orbis::scene;

namespace orbis::examples {

namespace {

const Geodetic3D kJitterTarget = Geodetic3D::fromDegrees(10.0, 45.0, 0.0);

/// A point in a local east-north-up frame.
glm::dvec3 local(const glm::dmat4& frame, double east, double north, double up)
{
    return glm::dvec3(frame * glm::dvec4(east, north, up, 1.0));
}

/// An axis-aligned box in a local frame, counter-clockwise from outside, with face normals.
Mesh localBox(const glm::dmat4& frame, const glm::dvec3& centre, const glm::dvec3& half)
{
    Mesh mesh;
    const glm::dmat3 rotation(frame);
    for (int axis = 0; axis < 3; ++axis) {
        for (const double sign : {-1.0, 1.0}) {
            glm::dvec3 normal(0.0);
            normal[axis] = sign;
            const int u = (axis + 1) % 3;
            const int v = (axis + 2) % 3;
            const auto base = static_cast<std::uint32_t>(mesh.positions.size());
            for (const glm::dvec2 corner : {glm::dvec2(-1, -1), glm::dvec2(1, -1), glm::dvec2(1, 1), glm::dvec2(-1, 1)}) {
                glm::dvec3 p = centre + normal * half;
                p[u] += corner.x * half[u] * sign;
                p[v] += corner.y * half[v];
                mesh.positions.push_back(local(frame, p.x, p.y, p.z));
                mesh.normals.push_back(glm::vec3(glm::normalize(rotation * normal)));
            }
            mesh.indices.insert(mesh.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
        }
    }
    return mesh;
}

void append(Mesh& to, const Mesh& from)
{
    const auto base = static_cast<std::uint32_t>(to.positions.size());
    to.positions.insert(to.positions.end(), from.positions.begin(), from.positions.end());
    to.normals.insert(to.normals.end(), from.normals.begin(), from.normals.end());
    for (const std::uint32_t i : from.indices) {
        to.indices.push_back(base + i);
    }
}

/// Synthetic mountains: metres above the ellipsoid at a local east, north (metres).
double terrainHeight(double east, double north)
{
    const double x = east / 5e3;
    const double y = north / 5e3;
    return 2000.0 + 900.0 * std::sin(1.3 * x + 0.4) * std::cos(0.9 * y - 0.3) + 500.0 * std::sin(0.7 * x - 1.1 * y) +
           300.0 * std::cos(2.1 * y + 0.5 * x);
}

/// Terrain cells of `cell` metres over [east0, east1] x [north0, north1], following the ellipsoid,
/// `lift` metres above terrainHeight, with vertex normals. With a minimum height, only the cells
/// whose corners all stand above it and lie `minimumDistance` or more from the origin (snow on the
/// distant peaks).
Mesh terrainMesh(const Ellipsoid& ellipsoid, const Geodetic3D& origin, double east0, double east1, double north0,
                 double north1, double cell, double lift, double minimumHeight = -1e9, double minimumDistance = 0.0)
{
    const int columns = static_cast<int>(std::round((east1 - east0) / cell));
    const int rows = static_cast<int>(std::round((north1 - north0) / cell));
    const double radius = ellipsoid.maximumRadius();
    auto world = [&](double east, double north) {
        const Geodetic3D g(origin.longitude + east / (radius * std::cos(origin.latitude)),
                           origin.latitude + north / radius, terrainHeight(east, north) + lift);
        return ellipsoid.toCartesian(g);
    };
    Mesh mesh;
    for (int j = 0; j <= rows; ++j) {
        for (int i = 0; i <= columns; ++i) {
            const double east = east0 + i * cell;
            const double north = north0 + j * cell;
            mesh.positions.push_back(world(east, north));
            const glm::dvec3 de = world(east + 10.0, north) - world(east - 10.0, north);
            const glm::dvec3 dn = world(east, north + 10.0) - world(east, north - 10.0);
            mesh.normals.push_back(glm::vec3(glm::normalize(glm::cross(de, dn))));
        }
    }
    for (int j = 0; j < rows; ++j) {
        for (int i = 0; i < columns; ++i) {
            const auto a = static_cast<std::uint32_t>(j * (columns + 1) + i);
            const std::uint32_t b = a + 1;
            const auto c = static_cast<std::uint32_t>(a + columns + 1);
            const std::uint32_t d = c + 1;
            const double east = east0 + i * cell;
            const double north = north0 + j * cell;
            const double lowest = std::min({terrainHeight(east, north), terrainHeight(east + cell, north),
                                            terrainHeight(east, north + cell), terrainHeight(east + cell, north + cell)});
            if (lowest >= minimumHeight && std::hypot(east, north) >= minimumDistance) {
                mesh.indices.insert(mesh.indices.end(), {a, b, d, a, d, c});
            }
        }
    }
    return mesh;
}

const Font* captionFont()
{
    static const std::optional<Font> font = []() -> std::optional<Font> {
        const std::optional<std::filesystem::path> path = scene::findFont(scene::kDefaultFontFamily);
        if (!path) {
            return std::nullopt;
        }
        return Font(*path);
    }();
    return font ? &*font : nullptr;
}

} // namespace

glm::dvec3 jitterSceneTarget()
{
    return Ellipsoid::wgs84().toCartesian(kJitterTarget);
}

void buildJitterScene(Scene& scene, VertexTransform transform)
{
    const Ellipsoid& ellipsoid = scene.ellipsoid();
    const glm::dmat4 frame = eastNorthUpToFixedFrame(ellipsoid, jitterSceneTarget());
    // Eight by eight squares of 12.5 cm, alternately dark and light, in two meshes; each mesh also
    // reaches 200 km east (a sliver far out of view), which puts its centre 100 km away.
    Mesh squares[2];
    for (int j = 0; j < 8; ++j) {
        for (int i = 0; i < 8; ++i) {
            Mesh& mesh = squares[(i + j) % 2];
            const double x0 = -0.5 + 0.125 * i;
            const double y0 = -0.5 + 0.125 * j;
            const auto base = static_cast<std::uint32_t>(mesh.positions.size());
            for (const glm::dvec2 c : {glm::dvec2(0, 0), glm::dvec2(1, 0), glm::dvec2(1, 1), glm::dvec2(0, 1)}) {
                mesh.positions.push_back(local(frame, x0 + 0.125 * c.x, y0 + 0.125 * c.y, 0.0));
            }
            mesh.indices.insert(mesh.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
        }
    }
    for (Mesh& mesh : squares) {
        const auto base = static_cast<std::uint32_t>(mesh.positions.size());
        mesh.positions.push_back(local(frame, 200e3, 0.0, 0.0));
        mesh.positions.push_back(local(frame, 200e3, 1.0, 0.0));
        mesh.positions.push_back(local(frame, 199e3, 0.5, 0.0));
        mesh.indices.insert(mesh.indices.end(), {base, base + 1, base + 2});
    }
    scene.add(std::make_shared<MeshPrimitive>(squares[0], glm::vec4(0.95f, 0.85f, 0.3f, 1.0f), Pass::Opaque, transform));
    scene.add(std::make_shared<MeshPrimitive>(squares[1], glm::vec4(0.15f, 0.2f, 0.5f, 1.0f), Pass::Opaque, transform));
    const glm::dvec3 target = jitterSceneTarget();
    scene.camera().lookAt(target + kJitterSceneEyeDistance * ellipsoid.geodeticSurfaceNormal(target), target,
                          glm::dvec3(frame[1]));
    scene.options().background = {0.05f, 0.05f, 0.05f, 1.0f};
}

void buildDepthScene(Scene& scene)
{
    const Ellipsoid& ellipsoid = scene.ellipsoid();
    const Geodetic3D origin = Geodetic3D::fromDegrees(86.9, 27.9, 0.0);

    GlobeOptions globe;
    globe.lighting = true;
    globe.dayTexture = xplanetDayImage();
    scene.add(std::make_shared<Globe>(ellipsoid, globe));

    // 200 km of mountains in 2.5 km cells, and snow 5 m thick on the cells above 2,600 m, 10 km
    // away and more.
    scene.add(std::make_shared<MeshPrimitive>(terrainMesh(ellipsoid, origin, -100e3, 100e3, -100e3, 100e3, 2.5e3, 0.0),
                                              glm::vec4(0.45f, 0.6f, 0.35f, 1.0f), Pass::Opaque,
                                              VertexTransform::Automatic));
    scene.add(std::make_shared<MeshPrimitive>(
        terrainMesh(ellipsoid, origin, -100e3, 100e3, -100e3, 100e3, 2.5e3, 5.0, 2600.0, 10e3),
        glm::vec4(0.85f, 0.9f, 1.0f, 1.0f), Pass::Opaque, VertexTransform::Automatic));

    // The aircraft, 2,500 m over the terrain at the origin, heading east; the camera 60 m behind it.
    const double ground = terrainHeight(0.0, 0.0);
    const glm::dvec3 aircraftPosition =
        ellipsoid.toCartesian(Geodetic3D(origin.longitude, origin.latitude, ground + 2500.0));
    const glm::dmat4 frame = eastNorthUpToFixedFrame(ellipsoid, aircraftPosition);
    Mesh aircraft = localBox(frame, {0.0, 0.0, 0.0}, {6.0, 0.6, 0.6});     // fuselage
    append(aircraft, localBox(frame, {0.5, 0.0, 0.2}, {1.0, 8.0, 0.1}));   // wings
    append(aircraft, localBox(frame, {-5.5, 0.0, 1.2}, {0.5, 0.1, 1.0}));  // fin
    append(aircraft, localBox(frame, {-5.5, 0.0, 0.4}, {0.4, 2.5, 0.08})); // tailplane
    scene.add(std::make_shared<MeshPrimitive>(aircraft, glm::vec4(0.85f, 0.85f, 0.9f, 1.0f), Pass::Opaque,
                                              VertexTransform::Automatic));

    const glm::dvec3 eye = local(frame, -60.0, 0.0, 15.0);
    const glm::dvec3 ahead = local(frame, 2000.0, 0.0, -500.0);
    scene.camera().lookAt(eye, ahead, glm::dvec3(frame[2]));

    // A satellite 36,000 km away, above the horizon to the right, drawn 300 km across so that it
    // shows as a few pixels.
    const glm::dvec3 forward = glm::normalize(ahead - eye);
    const glm::dvec3 up = glm::normalize(glm::dvec3(frame[2]) - glm::dot(glm::dvec3(frame[2]), forward) * forward);
    const glm::dvec3 right = glm::cross(forward, up);
    const glm::dvec3 satellite = eye + 3.6e7 * glm::normalize(forward + 0.33 * up + 0.3 * right);
    const glm::dmat4 satelliteFrame = eastNorthUpToFixedFrame(ellipsoid, satellite);
    scene.add(std::make_shared<MeshPrimitive>(localBox(satelliteFrame, {0.0, 0.0, 0.0}, {150e3, 150e3, 150e3}),
                                              glm::vec4(1.0f, 0.95f, 0.6f, 1.0f), Pass::Opaque,
                                              VertexTransform::Automatic));
    scene.options().background = {0.02f, 0.02f, 0.08f, 1.0f};
}

Image composeTiles(const std::vector<Image>& tiles, int columns, int gap)
{
    if (tiles.empty()) {
        return Image(1, 1, 4);
    }
    const int w = tiles.front().width;
    const int h = tiles.front().height;
    const int rows = (static_cast<int>(tiles.size()) + columns - 1) / columns;
    Image result(columns * w + (columns + 1) * gap, rows * h + (rows + 1) * gap, 4);
    std::fill(result.pixels.begin(), result.pixels.end(), std::uint8_t{90});
    for (std::size_t k = 0; k < tiles.size(); ++k) {
        const int x0 = gap + static_cast<int>(k % columns) * (w + gap);
        const int y0 = gap + static_cast<int>(k / columns) * (h + gap);
        for (int y = 0; y < h; ++y) {
            std::copy_n(tiles[k].pixel(0, y), static_cast<std::size_t>(w) * 4, result.pixel(x0, y0 + y));
        }
    }
    return result;
}

void drawCaption(Image& image, int x, int y, const std::string& text, float sizePixels)
{
    const Font* font = captionFont();
    if (!font || image.channels != 4) {
        return;
    }
    const FontVerticalMetrics metrics = font->verticalMetrics(sizePixels);
    float baseline = static_cast<float>(y) + metrics.ascent;
    float pen = static_cast<float>(x);
    int previous = -1;
    auto blend = [&](int px, int py, int coverage, std::uint8_t value) {
        if (px < 0 || py < 0 || px >= image.width || py >= image.height || coverage == 0) {
            return;
        }
        std::uint8_t* p = image.pixel(px, py);
        for (int c = 0; c < 3; ++c) {
            p[c] = static_cast<std::uint8_t>((p[c] * (255 - coverage) + value * coverage) / 255);
        }
    };
    for (const char character : text) {
        if (character == '\n') {
            baseline += metrics.lineHeight();
            pen = static_cast<float>(x);
            previous = -1;
            continue;
        }
        const int glyph = font->glyphIndex(static_cast<unsigned char>(character));
        if (previous >= 0) {
            pen += font->kerning(previous, glyph, sizePixels);
        }
        const GlyphBitmap bitmap = font->rasterize(glyph, sizePixels);
        const int left = static_cast<int>(std::lround(pen)) + bitmap.left;
        const int top = static_cast<int>(std::lround(baseline)) + bitmap.top;
        // A dark outline first (the coverage spread by a pixel), then the white glyph.
        for (int pass = 0; pass < 2; ++pass) {
            for (int gy = 0; gy < bitmap.coverage.height; ++gy) {
                for (int gx = 0; gx < bitmap.coverage.width; ++gx) {
                    const int coverage = bitmap.coverage.pixel(gx, gy)[0];
                    if (pass == 0) {
                        for (int dy = -1; dy <= 1; ++dy) {
                            for (int dx = -1; dx <= 1; ++dx) {
                                blend(left + gx + dx, top + gy + dy, coverage * 3 / 4, 0);
                            }
                        }
                    } else {
                        blend(left + gx, top + gy, coverage, 255);
                    }
                }
            }
        }
        pen += font->glyphMetrics(glyph, sizePixels).advance;
        previous = glyph;
    }
}

} // namespace orbis::examples

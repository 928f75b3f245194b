#pragma once

#include "orbis/world/BillboardShape.h"
#include "orbis/world/DepthStrategy.h"
#include "orbis/world/GlobeMethod.h"

#include <orbis/core/CurveType.h>
#include <orbis/core/Geodetic.h>
#include <orbis/core/GeodeticExtent.h>
#include <orbis/core/TilingScheme.h>
#include <orbis/core/HeadingPitchRoll.h>
#include <orbis/core/Math.h>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <chrono>
#include <filesystem>
#include <optional>
#include <string>
#include <variant>
#include <vector>

namespace orbis::world {

// What a scene file (docs/scene-format.md) describes, as plain values: angles in radians, heights
// in metres, sizes in pixels, colours as non-premultiplied RGBA in 0..1, paths absolute. A scene
// file is read into these by parseSceneFile (SceneFile.h); the scene layer turns them into objects
// (populateScene and makeCamera, orbis/scene/SceneBuilder.h).

/// Where the camera is and where it looks: at a target point, or along a heading, pitch and roll.
struct CameraDescription {
    Geodetic3D position = Geodetic3D::fromDegrees(10.0, 30.0, 20'000'000.0);
    /// A target position, or the orientation at the camera's position. Default: straight down.
    std::variant<Geodetic3D, HeadingPitchRoll> aim = HeadingPitchRoll{0.0, -kHalfPi, 0.0};
    double fieldOfViewY = toRadians(45.0); ///< radians, in (0, pi)

    friend bool operator==(const CameraDescription&, const CameraDescription&) = default;
};

/// What placed the Sun.
enum class SunSource {
    Camera,   ///< nothing in the file: no lighting; the direction points from the camera
    Position, ///< "sun": the point where the Sun is overhead
    Time,     ///< "time": computed from a UTC time
};

/// The Sun, always resolved to a direction whatever the file gave.
struct SunDescription {
    SunSource source = SunSource::Camera;
    Geodetic2D subsolarPoint;                        ///< where the Sun is overhead, radians
    std::optional<std::chrono::sys_seconds> time;    ///< only for SunSource::Time
    glm::dvec3 directionEarthFixed{1.0, 0.0, 0.0};   ///< unit, from the Earth's centre to the Sun

    friend bool operator==(const SunDescription&, const SunDescription&) = default;
};

/// A day texture: one image file, or a TMS tile folder (a folder with tilemapresource.xml).
struct GlobeTexture {
    enum class Kind { Image, TileMapService };
    std::filesystem::path path;
    Kind kind = Kind::Image;

    friend bool operator==(const GlobeTexture&, const GlobeTexture&) = default;
};

/// An imagery layer drawn as one virtual texture over the globe (docs/scene-format.md):
/// "globe": {"imagery": [{"source": ..., "virtualTexture": {...}}]}. The defaults are
/// scene::VirtualTextureOptions'.
struct VirtualTextureDescription {
    int pageSize = 256;              ///< texels a side of a page, a power of two 16..1024
    int border = 4;                  ///< 0 to pageSize / 4
    int physicalPages = 256;         ///< slots of the physical texture, 4..65536
    int feedbackDivisor = 4;         ///< the feedback pass at 1 / this of the frame's width and height, 1..16
    int feedbackLatencyFrames = 1;   ///< 1..8
    bool priorities = true;          ///< load the pages with the most pixels first
    bool trilinear = true;
    double maximumAnisotropy = 1.0;  ///< 1 to 2 x border
    double lodBias = 0.0;            ///< levels, -8..16
    bool dynamicLodBias = true;
    double uploadMegabytesPerFrame = 4.0; ///< > 0
    /// The hardware path where the device has GL_ARB_sparse_texture (scene::VirtualTextureOptions::sparse).
    bool sparse = false;

    friend bool operator==(const VirtualTextureDescription&, const VirtualTextureDescription&) = default;
};

/// One imagery layer of a tiled globe: a tile source and how it is drawn over the layers before it.
struct ImageryLayerDescription {
    /// An absolute path (a TMS folder, an .mbtiles file, a {z}/{x}/{y} template) or an http(s) URL.
    std::string source;
    /// The tiling of a template source; TMS folders and MBTiles say their own (and must agree).
    std::optional<TilingProjection> scheme;
    double alpha = 1.0;      ///< 0..1
    double brightness = 1.0; ///< >= 0
    double contrast = 1.0;   ///< >= 0
    double gamma = 1.0;      ///< > 0
    std::optional<GeodeticExtent> rectangle; ///< where the layer shows; empty: wherever it has tiles
    /// Levels of a template source (TMS folders and MBTiles say their own).
    std::optional<std::uint32_t> minimumLevel;
    std::optional<std::uint32_t> maximumLevel;
    /// Where tiles fetched over HTTP are kept on disk between runs; empty: nowhere.
    std::optional<std::filesystem::path> cacheFolder;
    /// Drawn as one virtual texture instead of per-tile textures; then it is the globe's only
    /// layer.
    std::optional<VirtualTextureDescription> virtualTexture;

    friend bool operator==(const ImageryLayerDescription&, const ImageryLayerDescription&) = default;
};

/// How terrain is drawn: the streamed tiles' quadtree (chunked LOD, book chapter 12) or geometry
/// clipmaps around the viewer (book chapter 13).
enum class TerrainMethod { Quadtree, Clipmap };

/// The heights under a tiled globe.
/// How the terrain is coloured and shaded beside the Sun's light (docs/scene-format.md, "shading").
struct TerrainShadingDescription {
    enum class Color { Base, Height, Slope };
    Color color = Color::Base;
    double minimumHeight = -6000.0, maximumHeight = 6000.0; ///< metres, "heightRange"
    double contourInterval = 0.0;                            ///< metres; 0: no "contours"
    glm::vec4 contourColor{1.0f, 1.0f, 1.0f, 1.0f};
    double contourWidth = 1.0;                               ///< pixels
    bool hillshade = false;
    double hillshadeAzimuth = 315.0, hillshadeAltitude = 45.0; ///< degrees
    bool water = false; ///< the terrain's water mask drawn as water (tile-streamed globes, lit)

    friend bool operator==(const TerrainShadingDescription&, const TerrainShadingDescription&) = default;
};

struct TerrainDescription {
    /// An absolute path (a folder or layer.json of quantized-mesh or heightmap tiles, an .mbtiles
    /// file, a TMS folder or {z}/{x}/{y} template of height PNGs, a folder of .hgt files, a DEM
    /// that GDAL reads) or an http(s) URL.
    std::string source;
    std::string format;        ///< one of world::kTerrainFormats; empty: told from the source
    double exaggeration = 1.0; ///< >= 0: heights multiplied by it
    TerrainShadingDescription shading;
    /// Where tiles fetched over HTTP are kept on disk between runs; empty: nowhere.
    std::optional<std::filesystem::path> cacheFolder;
    TerrainMethod method = TerrainMethod::Quadtree;
    int posts = 255; ///< Clipmap: posts a side of each level, 2^k - 1 from 15 to 1023
    /// Quadtree: the frames a refined tile takes to move from its parent's surface to its own
    /// (scene::TiledGlobeOptions::morphFrames); 0: at once.
    int morphFrames = 0;

    friend bool operator==(const TerrainDescription&, const TerrainDescription&) = default;
};

struct GlobeDescription {
    GlobeMethod method = GlobeMethod::RayCast;
    std::optional<GlobeTexture> texture;                 ///< empty: an untextured globe
    std::optional<std::filesystem::path> nightTexture;   ///< empty: no night lights
    bool grid = false;                                   ///< latitude-longitude grid lines
    /// Imagery streamed as tiles, drawn in order; non-empty: the globe's surface is a tile
    /// quadtree (method, texture, nightTexture and grid do not apply).
    std::vector<ImageryLayerDescription> imagery;
    /// Heights under the tiles; present: the globe's surface is a tile quadtree too.
    std::optional<TerrainDescription> terrain;
    double maximumScreenSpaceError = 2.0; ///< pixels, > 0: refine while a tile's error is larger
    double cacheMegabytes = 256.0;        ///< the tiles' hard cap, CPU and GPU together (MiB)

    friend bool operator==(const GlobeDescription&, const GlobeDescription&) = default;
};

/// Lines: GeoJSON (multi)line strings and polygon outlines.
struct StrokeStyle {
    glm::vec4 color{1.0f, 1.0f, 1.0f, 1.0f};
    double widthPixels = 1.0;                    ///< > 0
    glm::vec4 outlineColor{0.0f, 0.0f, 0.0f, 1.0f};
    double outlineWidthPixels = 0.0;             ///< on each side; 0: no outline

    friend bool operator==(const StrokeStyle&, const StrokeStyle&) = default;
};

/// Polygon interiors.
struct FillStyle {
    glm::vec4 color{1.0f, 1.0f, 1.0f, 0.5f};

    friend bool operator==(const FillStyle&, const FillStyle&) = default;
};

/// Which point of a billboard or label sits on its position.
enum class Origin { Center, Top, Bottom, Left, Right, TopLeft, TopRight, BottomLeft, BottomRight };

struct BillboardStyle {
    std::optional<std::filesystem::path> image;   ///< empty: the built-in shape
    BillboardShape shape = BillboardShape::Dot;   ///< drawn when there is no image
    double sizePixels = 8.0;                      ///< > 0, the larger side of the image
    glm::vec4 color{1.0f, 1.0f, 1.0f, 1.0f};      ///< multiplies the image
    Origin origin = Origin::Center;
    glm::dvec2 offsetPixels{0.0, 0.0};            ///< x right, y down
    /// Metres from the camera within which the markers are not depth-tested (infinity: never).
    double disableDepthTestDistance = 0.0;

    friend bool operator==(const BillboardStyle&, const BillboardStyle&) = default;
};

struct LabelStyle {
    std::string field;                           ///< the CSV column or GeoJSON property shown
    double fontSizePixels = 14.0;                ///< > 0
    glm::vec4 color{1.0f, 1.0f, 1.0f, 1.0f};
    glm::vec4 outlineColor{0.0f, 0.0f, 0.0f, 1.0f};
    double outlineWidthPixels = 1.0;             ///< 0: no outline
    bool declutter = false;                      ///< hide labels overlapping earlier ones shown
    /// Metres from the camera within which the labels are not depth-tested (infinity: never).
    double disableDepthTestDistance = 0.0;

    friend bool operator==(const LabelStyle&, const LabelStyle&) = default;
};

/// How lines follow the ellipsoid between their positions, and how finely polygons are cut.
struct LinePath {
    double granularityRadians = toRadians(1.0); ///< the largest angle at the centre between drawn vertices
    CurveType curve = CurveType::PlaneSection;  ///< lines only; polygon fills follow plane sections

    friend bool operator==(const LinePath&, const LinePath&) = default;
};

/// What a layer's heights are measured from (docs/scene-format.md, "heightReference"): the
/// ellipsoid, or the globe's terrain under each point (its most detailed height there, times the
/// exaggeration; 0 m without terrain).
enum class HeightReference {
    Absolute,         ///< heights above the ellipsoid, as given
    ClampToGround,    ///< on the terrain: the heights given are ignored
    RelativeToGround, ///< the heights given above the terrain
};

/// Lines and polygons from a GeoJSON file. With neither style given, lines are stroked with
/// the default StrokeStyle and polygons are outlined with it.
struct GeoJsonLayer {
    std::filesystem::path source;
    std::optional<StrokeStyle> stroke;
    std::optional<FillStyle> fill;
    LinePath path;
    /// Lines follow it as a polyline layer's do; fills on the ground (either ground reference)
    /// are draped over the terrain, their heights ignored as they always are.
    HeightReference heightReference = HeightReference::Absolute;
    /// Key "invalid": false ("error"), a feature the reader refuses or a polygon the triangulation
    /// refuses fails the layer; true ("skip"), each is left out and named in a warning (data
    /// invalid as published, such as a hole outside its polygon's outer ring).
    bool skipInvalid = false;

    friend bool operator==(const GeoJsonLayer&, const GeoJsonLayer&) = default;
};

/// Points from a CSV file (a header row with lon and lat columns) or a GeoJSON file, drawn as
/// billboards with optional labels.
struct PointsLayer {
    enum class Format { Csv, GeoJson };
    std::filesystem::path source;
    Format format = Format::Csv;
    BillboardStyle billboard;
    std::optional<LabelStyle> label;
    HeightReference heightReference = HeightReference::Absolute;

    friend bool operator==(const PointsLayer&, const PointsLayer&) = default;
};

/// A polyline through positions given in the file (at least two).
struct PolylineLayer {
    std::vector<Geodetic3D> positions; ///< radians, metres
    double widthPixels = 2.0;          ///< > 0
    glm::vec4 color{1.0f, 1.0f, 1.0f, 1.0f};
    LinePath path;
    /// Ground references apply to every drawn vertex of the curve, not only to the positions given.
    HeightReference heightReference = HeightReference::Absolute;

    friend bool operator==(const PolylineLayer&, const PolylineLayer&) = default;
};

/// A glTF model placed at a position, its +x east, +y north and +z up before the heading,
/// pitch and roll turn it: glTF's -x, +z (the asset's front) and +y (up), see gltfToEastNorthUp()
/// in orbis/scene/ModelPrimitive.h and docs/scene-format.md.
struct ModelLayer {
    enum class Format { Gltf, Glb };
    std::filesystem::path source;
    Format format = Format::Gltf;
    Geodetic3D position;              ///< radians, metres
    double scale = 1.0;               ///< > 0
    HeadingPitchRoll orientation;     ///< radians
    HeightReference heightReference = HeightReference::Absolute;

    friend bool operator==(const ModelLayer&, const ModelLayer&) = default;
};

/// One entry of "layers", drawn in file order.
using LayerDescription = std::variant<GeoJsonLayer, PointsLayer, PolylineLayer, ModelLayer>;

/// Everything a scene file says. Members a file leaves out hold the documented defaults.
struct SceneDescription {
    int version = 1;
    int width = 1280;   ///< pixels, 1..16384
    int height = 720;   ///< pixels, 1..16384
    int samples = 1;    ///< per pixel, 1..16: above 1, the scene's target is multisampled (MSAA)
    glm::vec4 background{0.0f, 0.0f, 0.0f, 1.0f};
    CameraDescription camera;
    SunDescription sun;
    DepthStrategy depth = DepthStrategy::Automatic;
    std::optional<GlobeDescription> globe;   ///< empty: no globe is drawn
    std::vector<LayerDescription> layers;

    friend bool operator==(const SceneDescription&, const SceneDescription&) = default;
};

} // namespace orbis::world

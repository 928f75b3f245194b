#pragma once

#include "orbis/scene/PolygonCollection.h"
#include "orbis/scene/PolylineCollection.h"

#include <orbis/world/Feature.h>

#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace orbis::scene {

class Scene;

/// How buildFeaturePrimitives draws features.
struct FeatureStyle {
    bool fill = true;                          ///< fill Polygon and MultiPolygon geometries
    glm::vec4 fillColor{1.0f, 1.0f, 1.0f, 0.5f};
    /// A colour per feature (by its properties, say); when set it replaces fillColor.
    std::function<glm::vec4(const world::Feature&)> fillColorOf;
    bool borders = true;                       ///< draw polygon rings and LineStrings as polylines
    PolylineStyle border{glm::vec4(1.0f), 1.5f, glm::vec4(0.0f, 0.0f, 0.0f, 1.0f), 0.0f, true};
    double granularityRadians = toRadians(1.0); ///< of both the fills and the borders
    CurveType curve = CurveType::PlaneSection;  ///< of the borders (fills follow plane sections)
    VertexEncoding encoding = VertexEncoding::RelativeToEye;
    /// Data cut at the antimeridian (a polygon split in two along 180 degrees) has ring edges along
    /// that meridian which are no border: leave them out of the borders. Edges from one longitude of
    /// +-180 degrees to another, at different latitudes, are such edges.
    bool skipAntimeridianEdges = true;
    /// false: a polygon that cannot be triangulated throws. true: a faulty hole is left out (see
    /// earClip's leftOutHoles), a polygon that still cannot be triangulated too, each described in
    /// FeaturePrimitives::warnings (their borders are still drawn).
    bool skipInvalidPolygons = false;
    /// Lines on the ground, as a polyline layer's (PolylineCollectionOptions::groundHeight; null:
    /// on the ellipsoid), with a drawn vertex at least every groundSpacingRadians (the terrain's
    /// sample spacing). clampLinesToGround drops the lines' own heights first (without
    /// groundHeight the lines then lie on the ellipsoid).
    std::function<double(const Geodetic2D&)> groundHeight;
    double groundSpacingRadians = std::numeric_limits<double>::infinity();
    bool clampLinesToGround = false;
    /// Fills draped over the ground the scene draws (PolygonCollectionOptions::draped); false: on
    /// the ellipsoid.
    bool drapeFills = false;
    /// With drapeFills and groundHeight: a polygon one of whose positions has a height other than
    /// 0 stands at its heights above the ground instead, following it with a drawn vertex every
    /// groundSpacingRadians (PolygonCollectionOptions::groundHeight, in FeaturePrimitives::
    /// raisedFills); one at 0 m is draped.
    bool raiseFillsByHeight = false;
};

/// What buildFeaturePrimitives made: null for what there was nothing of.
struct FeaturePrimitives {
    std::shared_ptr<PolygonCollection> fills;
    std::shared_ptr<PolygonCollection> raisedFills; ///< FeatureStyle::raiseFillsByHeight's
    std::shared_ptr<PolylineCollection> borders;
    std::vector<std::string> warnings; ///< one line per polygon or hole left out

    /// Adds the fills (draped or on the ellipsoid, then raised), then the borders (so borders draw
    /// over the fills).
    void addTo(Scene& scene) const;
};

/// Polylines and filled polygons for a FeatureCollection (loadGeoJson): fills from every Polygon and
/// MultiPolygon, borders from their rings (holes included) and from every LineString and
/// MultiLineString, inside GeometryCollections too; points are ignored. Each polygon of a
/// MultiPolygon is one PolygonCollection entry, named for messages as `name` property, feature
/// index and part ("Fiji (feature 0, polygon 1)"). Throws orbis::Error for a polygon the
/// triangulation rejects unless style.skipInvalidPolygons.
FeaturePrimitives buildFeaturePrimitives(const Ellipsoid& ellipsoid, const world::FeatureCollection& features,
                                         const FeatureStyle& style = {});

} // namespace orbis::scene

#include "orbis/scene/FeaturePrimitives.h"

#include "orbis/scene/Scene.h"

#include <orbis/core/Error.h>
#include <orbis/world/Diagnostics.h>

#include <algorithm>
#include <cmath>
#include <variant>

namespace orbis::scene {

namespace {

bool onAntimeridian(const Geodetic3D& g) noexcept
{
    return std::abs(std::abs(g.longitude) - kPi) < 1e-12;
}

class Builder {
public:
    Builder(const Ellipsoid& ellipsoid, const FeatureStyle& style, FeaturePrimitives& out)
        : _ellipsoid(ellipsoid)
        , _style(style)
        , _out(out)
    {
    }

    void feature(const world::Feature& feature)
    {
        _feature = &feature;
        _part = 0;
        if (feature.geometry) {
            geometry(*feature.geometry);
        }
    }

private:
    void geometry(const world::Geometry& geometry)
    {
        std::visit([this](const auto& value) { visit(value); }, geometry.value);
    }

    void visit(const world::Point&) {}
    void visit(const world::MultiPoint&) {}
    void visit(const world::LineString& line) { border(line.positions, false); }
    void visit(const world::MultiLineString& lines)
    {
        for (const world::LineString& line : lines.lines) {
            border(line.positions, false);
        }
    }
    void visit(const world::Polygon& polygon)
    {
        fill(polygon);
        for (const world::LinearRing& ring : polygon.rings) {
            ringBorder(ring);
        }
    }
    void visit(const world::MultiPolygon& polygons)
    {
        for (const world::Polygon& polygon : polygons.polygons) {
            visit(polygon);
        }
    }
    void visit(const world::GeometryCollection& collection)
    {
        for (const world::Geometry& geometry : collection.geometries) {
            this->geometry(geometry);
        }
    }

    void fill(const world::Polygon& polygon)
    {
        const std::size_t part = _part++;
        if (!_style.fill) {
            return;
        }
        const bool raised = _style.drapeFills && _style.raiseFillsByHeight && _style.groundHeight &&
                            std::any_of(polygon.rings.begin(), polygon.rings.end(), [](const world::LinearRing& ring) {
                                return std::any_of(ring.begin(), ring.end(),
                                                   [](const Geodetic3D& position) { return position.height != 0.0; });
                            });
        std::shared_ptr<PolygonCollection>& fills = raised ? _out.raisedFills : _out.fills;
        if (!fills) {
            PolygonCollectionOptions options;
            options.granularityRadians = _style.granularityRadians;
            options.encoding = _style.encoding;
            if (raised) {
                options.groundHeight = _style.groundHeight;
                options.granularityRadians = std::min(options.granularityRadians, _style.groundSpacingRadians);
            } else {
                options.draped = _style.drapeFills;
            }
            fills = std::make_shared<PolygonCollection>(_ellipsoid, options);
        }
        // A feature's name is data: cut, so that a hostile one cannot make a message megabytes long.
        std::string name = world::cutForMessage(_feature->name().value_or("feature"), 80);
        name.append(" (feature ").append(std::to_string(_feature->index));
        name.append(", polygon ").append(std::to_string(part)).append(")");
        const glm::vec4 color = _style.fillColorOf ? _style.fillColorOf(*_feature) : _style.fillColor;
        std::vector<LeftOutHole> leftOut;
        try {
            fills->add(polygon, color, name, _style.skipInvalidPolygons ? &leftOut : nullptr);
        } catch (const Error& error) {
            if (!_style.skipInvalidPolygons) {
                throw;
            }
            _out.warnings.push_back(std::string("left out: ") + error.what());
        }
        for (const LeftOutHole& hole : leftOut) {
            _out.warnings.push_back("polygon '" + name + "': left out hole ring " + std::to_string(hole.ring) + ": " +
                                    hole.reason);
        }
    }

    /// A ring as one loop, or as open pieces between the antimeridian edges that are left out.
    void ringBorder(const world::LinearRing& ring)
    {
        if (!_style.borders || ring.size() < 2) {
            return;
        }
        const std::size_t n = ring.size() - 1; // GeoJSON repeats the first position at the end
        auto cut = [&](std::size_t i) {
            const Geodetic3D& a = ring[i];
            const Geodetic3D& b = ring[i + 1];
            return _style.skipAntimeridianEdges && onAntimeridian(a) && onAntimeridian(b) && a.latitude != b.latitude;
        };
        std::size_t start = n;
        for (std::size_t i = 0; i < n; ++i) {
            if (cut(i)) {
                start = i;
                break;
            }
        }
        if (start == n) {
            border(ring, true);
            return;
        }
        // Walk once around from just after a cut edge, emitting the runs between cut edges.
        std::vector<Geodetic3D> piece;
        for (std::size_t step = 1; step <= n; ++step) {
            const std::size_t i = (start + step) % n;
            if (piece.empty()) {
                piece.push_back(ring[i]);
            }
            if (cut(i)) {
                border(piece, false);
                piece.clear();
            } else {
                piece.push_back(ring[i + 1]);
            }
        }
        border(piece, false);
    }

    void border(const std::vector<Geodetic3D>& positions, bool loop)
    {
        if (!_style.borders || positions.size() < 2) {
            return;
        }
        if (!_out.borders) {
            PolylineCollectionOptions options;
            options.granularityRadians = _style.granularityRadians;
            options.curve = _style.curve;
            options.encoding = _style.encoding;
            if (_style.groundHeight) {
                options.groundHeight = _style.groundHeight;
                options.granularityRadians = std::min(options.granularityRadians, _style.groundSpacingRadians);
            }
            _out.borders = std::make_shared<PolylineCollection>(_ellipsoid, options);
        }
        if (_style.clampLinesToGround) {
            std::vector<Geodetic3D> onGround = positions;
            for (Geodetic3D& position : onGround) {
                position.height = 0.0;
            }
            _out.borders->add(std::span<const Geodetic3D>(onGround), _style.border, loop);
            return;
        }
        _out.borders->add(std::span<const Geodetic3D>(positions), _style.border, loop);
    }

    const Ellipsoid& _ellipsoid;
    const FeatureStyle& _style;
    FeaturePrimitives& _out;
    const world::Feature* _feature = nullptr;
    std::size_t _part = 0;
};

} // namespace

void FeaturePrimitives::addTo(Scene& scene) const
{
    scene.add(fills);
    scene.add(raisedFills);
    scene.add(borders);
}

FeaturePrimitives buildFeaturePrimitives(const Ellipsoid& ellipsoid, const world::FeatureCollection& features,
                                         const FeatureStyle& style)
{
    FeaturePrimitives out;
    Builder builder(ellipsoid, style, out);
    for (const world::Feature& feature : features.features) {
        builder.feature(feature);
    }
    return out;
}

} // namespace orbis::scene

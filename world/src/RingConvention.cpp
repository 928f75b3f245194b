#include "RingConvention.h"

#include <orbis/core/PolygonCleanup.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <optional>

namespace orbis::world::detail {

namespace {

/// Directions from the centre of a unit sphere: the winding round the smaller region is the same
/// on any ellipsoid centred there.
std::vector<glm::dvec3> directions(const LinearRing& ring)
{
    std::vector<glm::dvec3> out;
    out.reserve(ring.size());
    for (const Geodetic3D& p : ring) {
        const double c = std::cos(p.latitude);
        out.emplace_back(c * std::cos(p.longitude), c * std::sin(p.longitude), std::sin(p.latitude));
    }
    return out;
}

std::optional<Winding> sphericalWinding(const LinearRing& ring)
{
    const std::vector<glm::dvec3> d = directions(ring);
    return winding(std::span<const glm::dvec3>(d));
}

/// Whether a ring bounds area of its polygon (an outer ring) under the convention; empty when its
/// winding cannot tell (no area, or two halves of the sphere).
std::optional<bool> boundsArea(const LinearRing& ring, RingConvention convention)
{
    const std::optional<Winding> turn = sphericalWinding(ring);
    if (!turn) {
        return std::nullopt;
    }
    return (*turn == Winding::CounterClockwise) == (convention == RingConvention::Rfc7946);
}

/// Whether p lies in the smaller region ring bounds: the ring seen from its centre through a
/// gnomonic projection (outer rings are smaller than a hemisphere), then the crossing count.
bool inside(const LinearRing& ring, const Geodetic3D& point)
{
    const std::vector<glm::dvec3> d = directions(ring);
    glm::dvec3 sum(0.0);
    for (const glm::dvec3& v : d) {
        sum += v;
    }
    if (glm::length(sum) == 0.0) {
        return false;
    }
    const glm::dvec3 centre = glm::normalize(sum);
    const glm::dvec3 e1 = glm::normalize(std::abs(centre.z) < 0.9 ? glm::cross(glm::dvec3(0, 0, 1), centre)
                                                                   : glm::cross(glm::dvec3(1, 0, 0), centre));
    const glm::dvec3 e2 = glm::cross(centre, e1);
    auto project = [&](const glm::dvec3& v) {
        const double along = glm::dot(v, centre);
        return along > 0.0 ? std::optional<glm::dvec2>(glm::dvec2(glm::dot(v, e1), glm::dot(v, e2)) / along) : std::nullopt;
    };
    const std::optional<glm::dvec2> p = project(directions({point}).front());
    if (!p) {
        return false;
    }
    bool in = false;
    for (std::size_t i = 0; i + 1 < d.size(); ++i) {
        const std::optional<glm::dvec2> a = project(d[i]);
        const std::optional<glm::dvec2> b = project(d[i + 1]);
        if (!a || !b) {
            continue;
        }
        if ((a->y > p->y) != (b->y > p->y) && p->x < a->x + (p->y - a->y) * (b->x - a->x) / (b->y - a->y)) {
            in = !in;
        }
    }
    return in;
}

/// The polygons a polygon's rings make once outer rings go first (one, unchanged, in most files).
std::vector<Polygon> reorganize(Polygon polygon, RingConvention convention)
{
    if (polygon.rings.size() < 2 || boundsArea(polygon.rings[0], convention).value_or(true)) {
        return {std::move(polygon)};
    }
    std::vector<Polygon> outers;
    std::vector<LinearRing> holes;
    for (LinearRing& ring : polygon.rings) {
        if (boundsArea(ring, convention).value_or(false)) {
            outers.push_back(Polygon{{std::move(ring)}});
        } else {
            holes.push_back(std::move(ring));
        }
    }
    if (outers.empty()) {
        polygon.rings = std::move(holes); // none bounds area: as the file has them
        return {std::move(polygon)};
    }
    for (LinearRing& hole : holes) {
        std::size_t holder = 0;
        for (std::size_t o = 0; o < outers.size(); ++o) {
            if (!hole.empty() && inside(outers[o].rings[0], hole.front())) {
                holder = o;
                break;
            }
        }
        outers[holder].rings.push_back(std::move(hole));
    }
    return outers;
}

template <typename Visit>
void forEachGeometry(Geometry& geometry, Visit&& visit)
{
    if (auto* collection = std::get_if<GeometryCollection>(&geometry.value)) {
        for (Geometry& member : collection->geometries) {
            forEachGeometry(member, visit);
        }
        return;
    }
    visit(geometry);
}

template <typename Visit>
void forEachPolygon(const FeatureCollection& features, Visit&& visit)
{
    auto geometryVisit = [&](const Geometry& geometry, auto&& self) -> void {
        if (const auto* collection = std::get_if<GeometryCollection>(&geometry.value)) {
            for (const Geometry& member : collection->geometries) {
                self(member, self);
            }
        } else if (const auto* polygon = std::get_if<Polygon>(&geometry.value)) {
            visit(*polygon);
        } else if (const auto* multi = std::get_if<MultiPolygon>(&geometry.value)) {
            for (const Polygon& p : multi->polygons) {
                visit(p);
            }
        }
    };
    for (const Feature& feature : features.features) {
        if (feature.geometry) {
            geometryVisit(*feature.geometry, geometryVisit);
        }
    }
}

} // namespace

RingConvention detectRingConvention(const FeatureCollection& features)
{
    std::size_t clockwise = 0;
    std::size_t counterClockwise = 0;
    forEachPolygon(features, [&](const Polygon& polygon) {
        if (polygon.rings.empty()) {
            return;
        }
        if (const std::optional<Winding> turn = sphericalWinding(polygon.rings[0])) {
            ++(*turn == Winding::Clockwise ? clockwise : counterClockwise);
        }
    });
    return clockwise > counterClockwise ? RingConvention::Spherical : RingConvention::Rfc7946;
}

void putOuterRingsFirst(FeatureCollection& features, RingConvention convention)
{
    for (Feature& feature : features.features) {
        if (!feature.geometry) {
            continue;
        }
        forEachGeometry(*feature.geometry, [&](Geometry& geometry) {
            if (auto* polygon = std::get_if<Polygon>(&geometry.value)) {
                std::vector<Polygon> parts = reorganize(std::move(*polygon), convention);
                if (parts.size() == 1) {
                    geometry.value = std::move(parts.front());
                } else {
                    geometry.value = MultiPolygon{std::move(parts)};
                }
            } else if (auto* multi = std::get_if<MultiPolygon>(&geometry.value)) {
                std::vector<Polygon> all;
                for (Polygon& p : multi->polygons) {
                    for (Polygon& part : reorganize(std::move(p), convention)) {
                        all.push_back(std::move(part));
                    }
                }
                multi->polygons = std::move(all);
            }
        });
    }
}

} // namespace orbis::world::detail

#include "orbis/core/Tessellation.h"

#include "TessellationInternal.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace orbis {

namespace {

constexpr int kGridSteps = 6;                  // per edge: corners, midpoints, thirds and the centroid
constexpr double kFinestStep = 1.0 / 8192.0;   // compass search stops below this barycentric step

/// Greatest |height| over the triangle (a, b, c); see maxDeviationFromEllipsoid for the method.
double triangleDeviation(const Ellipsoid& ellipsoid, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c)
{
    const glm::dvec3 ab = b - a;
    const glm::dvec3 ac = c - a;
    auto distance = [&](double s, double t) { return std::abs(ellipsoid.toGeodetic3D(a + s * ab + t * ac).height); };

    double best = -1.0;
    double bestS = 0.0;
    double bestT = 0.0;
    auto consider = [&](double s, double t) {
        const double d = distance(s, t);
        if (d > best) {
            best = d;
            bestS = s;
            bestT = t;
            return true;
        }
        return false;
    };

    for (int i = 0; i <= kGridSteps; ++i) {
        for (int j = 0; i + j <= kGridSteps; ++j) {
            consider(static_cast<double>(i) / kGridSteps, static_cast<double>(j) / kGridSteps);
        }
    }

    // Scaled to a unit sphere, the deepest point of a triangle's plane is the foot of the centre.
    // Barycentric coordinates survive the scaling, so the foot's (s, t) apply to the original triangle.
    {
        const glm::dvec3 scale = ellipsoid.oneOverRadii();
        const glm::dvec3 sa = a * scale;
        const glm::dvec3 sab = ab * scale;
        const glm::dvec3 sac = ac * scale;
        const glm::dvec3 normal = glm::cross(sab, sac);
        const double normalSquared = glm::dot(normal, normal);
        if (normalSquared > 0.0) {
            const glm::dvec3 toFoot = normal * (glm::dot(sa, normal) / normalSquared) - sa;
            const double d00 = glm::dot(sab, sab);
            const double d01 = glm::dot(sab, sac);
            const double d11 = glm::dot(sac, sac);
            const double d20 = glm::dot(toFoot, sab);
            const double d21 = glm::dot(toFoot, sac);
            const double denominator = d00 * d11 - d01 * d01;
            if (denominator > 0.0) {
                const double s = (d11 * d20 - d01 * d21) / denominator;
                const double t = (d00 * d21 - d01 * d20) / denominator;
                if (s >= 0.0 && t >= 0.0 && s + t <= 1.0) {
                    consider(s, t);
                }
            }
        }
    }

    // Compass search over the six directions of the barycentric lattice, staying in the triangle.
    static constexpr double directions[6][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, -1}, {-1, 1}};
    for (double step = 0.5 / kGridSteps; step >= kFinestStep;) {
        bool moved = false;
        for (const auto& direction : directions) {
            const double s = bestS + step * direction[0];
            const double t = bestT + step * direction[1];
            if (s >= 0.0 && t >= 0.0 && s + t <= 1.0 && consider(s, t)) {
                moved = true;
            }
        }
        if (!moved) {
            step *= 0.5;
        }
    }
    return best;
}

} // namespace

double maxDeviationFromEllipsoid(const Mesh& mesh, const Ellipsoid& ellipsoid)
{
    double worst = 0.0;
    if (mesh.primitiveType != PrimitiveType::Triangles) {
        return worst;
    }
    for (std::size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
        worst = std::max(worst, triangleDeviation(ellipsoid, mesh.positions[mesh.indices[i]],
                                                  mesh.positions[mesh.indices[i + 1]],
                                                  mesh.positions[mesh.indices[i + 2]]));
    }
    return worst;
}

namespace detail {

glm::dvec3 projectToEllipsoid(const Ellipsoid& ellipsoid, const glm::dvec3& direction,
                              EllipsoidProjection projection) noexcept
{
    if (projection == EllipsoidProjection::Geocentric) {
        return ellipsoid.scaleToGeocentricSurface(direction);
    }
    // The surface point with geodetic normal n is r^2 n / sqrt(n . r^2 n), as in toCartesian.
    const glm::dvec3 n = glm::normalize(direction);
    const glm::dvec3 k = ellipsoid.radiiSquared() * n;
    return k / std::sqrt(glm::dot(k, n));
}

void addGeodeticNormals(Mesh& mesh, const Ellipsoid& ellipsoid)
{
    mesh.normals.resize(mesh.positions.size());
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
        mesh.normals[i] = glm::vec3(ellipsoid.geodeticSurfaceNormal(mesh.positions[i]));
    }
}

void addGeographicTextureCoordinates(Mesh& mesh, const Ellipsoid& ellipsoid)
{
    constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
    const std::size_t count = mesh.positions.size();
    auto isPole = [&](std::uint32_t v) { return mesh.positions[v].x == 0.0 && mesh.positions[v].y == 0.0; };
    auto isSeam = [&](std::uint32_t v) { return mesh.positions[v].y == 0.0 && mesh.positions[v].x < 0.0; };

    mesh.textureCoordinates.resize(count);
    for (std::uint32_t v = 0; v < count; ++v) {
        const glm::dvec3 n = ellipsoid.geodeticSurfaceNormal(mesh.positions[v]);
        const double horizontal = std::hypot(n.x, n.y);
        double longitude = horizontal == 0.0 ? 0.0 : std::atan2(n.y, n.x);
        if (isSeam(v)) {
            longitude = kPi; // the eastern copy; -0.0 in y would otherwise give -pi
        }
        const double latitude = std::atan2(n.z, horizontal);
        mesh.textureCoordinates[v] =
            glm::vec2(static_cast<float>((longitude + kPi) / kTwoPi), static_cast<float>((latitude + kHalfPi) / kPi));
    }

    auto copyVertex = [&](std::uint32_t v, float u) {
        const auto copy = static_cast<std::uint32_t>(mesh.positions.size());
        mesh.positions.push_back(mesh.positions[v]);
        if (!mesh.normals.empty()) {
            mesh.normals.push_back(mesh.normals[v]);
        }
        mesh.textureCoordinates.push_back(glm::vec2(u, mesh.textureCoordinates[v].y));
        return copy;
    };

    std::vector<std::uint32_t> westernCopy(count, kNone);
    std::vector<bool> poleTaken(count, false);
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        std::uint32_t* corner = &mesh.indices[t];
        double ySum = 0.0;
        for (int k = 0; k < 3; ++k) {
            if (!isPole(corner[k]) && !isSeam(corner[k])) {
                ySum += mesh.positions[corner[k]].y;
            }
        }
        if (ySum < 0.0) {
            for (int k = 0; k < 3; ++k) {
                if (isSeam(corner[k])) {
                    if (westernCopy[corner[k]] == kNone) {
                        westernCopy[corner[k]] = copyVertex(corner[k], 0.0f);
                    }
                    corner[k] = westernCopy[corner[k]];
                }
            }
        }
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t v = corner[k];
            if (!isPole(v)) {
                continue;
            }
            const float u = 0.5f * (mesh.textureCoordinates[corner[(k + 1) % 3]].x +
                                    mesh.textureCoordinates[corner[(k + 2) % 3]].x);
            if (!poleTaken[v]) {
                poleTaken[v] = true;
                mesh.textureCoordinates[v].x = u;
            } else {
                corner[k] = copyVertex(v, u);
            }
        }
    }
}

std::optional<double> measureDeviation(const Mesh& mesh, const Ellipsoid& ellipsoid, Deviation deviation)
{
    if (deviation == Deviation::Skip) {
        return std::nullopt;
    }
    return maxDeviationFromEllipsoid(mesh, ellipsoid);
}

} // namespace detail

} // namespace orbis

#include "orbis/core/SubdivisionEllipsoidTessellator.h"

#include "orbis/core/Ellipsoid.h"

#include "TessellationInternal.h"

namespace orbis {

TessellationResult SubdivisionEllipsoidTessellator::compute(const Ellipsoid& ellipsoid, int subdivisions,
                                                            EllipsoidProjection projection,
                                                            VertexAttributes attributes, Deviation deviation)
{
    TessellationResult result{detail::subdividedOctahedron(subdivisions), std::nullopt};
    Mesh& mesh = result.mesh;
    for (glm::dvec3& p : mesh.positions) {
        p = detail::projectToEllipsoid(ellipsoid, p, projection);
    }
    if (contains(attributes, VertexAttributes::Normal)) {
        detail::addGeodeticNormals(mesh, ellipsoid);
    }
    if (contains(attributes, VertexAttributes::TextureCoordinate)) {
        detail::addGeographicTextureCoordinates(mesh, ellipsoid);
    }
    result.maxDeviationMeters = detail::measureDeviation(mesh, ellipsoid, deviation);
    return result;
}

} // namespace orbis

// A user's program of the core alone: math on the ellipsoid, no files, no GL.
#include <orbis/core/Ellipsoid.h>
#include <orbis/core/Geodesic.h>

#include <cstdio>

int main()
{
    const orbis::Ellipsoid earth = orbis::Ellipsoid::wgs84();
    const orbis::Geodetic3D centre = earth.toGeodetic3D({0.0, 0.0, 0.0});
    std::printf("centre height %.0f\n", centre.height);
    const glm::dvec3 paris = earth.toCartesian(orbis::Geodetic3D::fromDegrees(2.35, 48.86, 0.0));
    std::printf("Paris x %.0f\n", paris.x);
    return 0;
}

// A user's program built against the installed orbis package.
#include <orbis/core/Ellipsoid.h>

#include <cstdio>

int main()
{
    const orbis::Ellipsoid earth = orbis::Ellipsoid::wgs84();
    const orbis::Geodetic3D centre = earth.toGeodetic3D({0.0, 0.0, 0.0});
    std::printf("centre height %.0f\n", centre.height);
    return 0;
}

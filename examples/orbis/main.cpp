// The orbis command. For now it demonstrates the core library: a few geodetic conversions on WGS84.
#include <orbis/core/Ellipsoid.h>

#include <cstdio>
#include <cstring>

namespace {

void printConversion(const orbis::Ellipsoid& earth, const char* name, const orbis::Geodetic3D& g)
{
    const glm::dvec3 p = earth.toCartesian(g);
    const orbis::Geodetic3D back = earth.toGeodetic3D(p);
    std::printf("%-22s lon %11.6f lat %10.6f h %12.3f m -> x %15.3f y %15.3f z %15.3f m -> "
                "lon %11.6f lat %10.6f h %12.3f m\n",
                name, orbis::toDegrees(g.longitude), orbis::toDegrees(g.latitude), g.height, p.x, p.y, p.z,
                orbis::toDegrees(back.longitude), orbis::toDegrees(back.latitude), back.height);
}

int usage()
{
    std::fprintf(stderr, "usage: orbis demo\n");
    return 2;
}

} // namespace

int main(int argc, char** argv)
{
    if (argc > 2 || (argc == 2 && std::strcmp(argv[1], "demo") != 0)) {
        return usage();
    }
    const orbis::Ellipsoid earth = orbis::Ellipsoid::wgs84();
    printConversion(earth, "Greenwich, sea level", orbis::Geodetic3D::fromDegrees(0.0, 51.4778, 0.0));
    printConversion(earth, "Everest summit", orbis::Geodetic3D::fromDegrees(86.925, 27.9881, 8848.86));
    printConversion(earth, "North pole", orbis::Geodetic3D::fromDegrees(0.0, 90.0, 0.0));
    printConversion(earth, "Antimeridian, GEO", orbis::Geodetic3D::fromDegrees(180.0, 0.0, 35786000.0));
    printConversion(earth, "Mariana trench", orbis::Geodetic3D::fromDegrees(142.2, 11.35, -10994.0));
    const orbis::Geodetic3D centre = earth.toGeodetic3D({0.0, 0.0, 0.0});
    std::printf("%-22s x 0 y 0 z 0 -> lon %.1f lat %.1f h %.3f m (the closest surface point is a pole)\n",
                "Earth's centre", orbis::toDegrees(centre.longitude), orbis::toDegrees(centre.latitude),
                centre.height);
    return 0;
}

// Software virtual texturing over the globe (Mayer 4.4, course 6.1): a tile of the surface reads
// one virtual texture through the page table. The level of detail comes from the derivatives of
// the texture coordinates, anisotropic as the course's 6.1.1; it is clamped from below by the
// page table so that it never shows a level the page table cannot give there (where the page asked
// for falls back to a coarser one, that one alone), and while pages wait, by the LOD-clamp texture,
// which varies smoothly across pages (course 6.1.2), so a region waiting for its pages shows as a
// gradual blur, never as a seam; then two levels are blended (trilinear filtering with two
// translations, course 6.1.2), each read from its page's slot with corrected gradients, inside the
// page's border. One fetch of the page table (point-sampled, from the one image holding every
// level) gives both levels' entries: each entry carries its parent page's.
//
// Positions are worked out per surface tile in integers (the page under a point at any level) and
// small fractions (where in the page), so that the precision does not depend on how deep the
// virtual texture goes.
//
// VT_SPARSE is the hardware path (course chapter 5): og_texture1 is then one sparse texture the
// size of the finest level, with its mip chain, every page at its own place and only the resident
// ones backed by memory; the hardware filters across pages and levels, and the level of detail is
// clamped so that no read touches a page that is not resident (vtSparseLod).
//
// VT_FEEDBACK draws the feedback pass instead (feedback.vert.glsl: a rectangle over the globe's
// outline): each pixel casts its ray at the ellipsoid and writes the page the frame's own pixel
// there asks for and whether it was shown a coarser one (orbis::packFeedback,
// VirtualTextureLayout.h). It works from level 0's two tiles, which places a point within 2.4e-4
// of a page at the twelfth level, the deepest a feedback sample names. The functions take their
// inputs as arguments, so that a test can run them in a vertex shader against a CPU reference
// (tests/scene/VirtualTextureGlobeTests.cpp).

#ifdef OG_FRAGMENT_SHADER
#ifdef VT_FEEDBACK
in vec3 v_ray; // feedback.vert.glsl
#else
in vec2 v_tileCoordinates; // u and v within the surface tile, 0..1 west to east and south to north
in vec3 v_normal;
#endif
out vec4 fragmentColor;
#endif

uniform sampler2D og_texture0; // page table: every level in one image (VirtualTextureLayout::pageTableOrigin); RG32F, PageTable::texels
uniform sampler2D og_texture1; // physical texture: slots of S x S texels, a page and its border (VT_SPARSE: the sparse texture)
uniform sampler2D og_texture2; // LOD clamp, RG32F, a texel per page of the finest level
#if defined(VT_FEEDBACK) && defined(OG_FRAGMENT_SHADER)
ivec3 vtTileKey; // level 0's tile under the pixel: main sets it
#else
uniform ivec3 u_tileKey;       // the surface tile: level, column, row (from the south)
#define vtTileKey u_tileKey
#endif
uniform ivec4 u_layout;        // finest level N, page size P, border B, slot size S (texels)
uniform vec2 u_physicalTexelSize; // 1 / the physical texture's width and height
uniform vec2 u_tailOrigin;        // the mip tail's strip in the physical texture (texels)
uniform int u_tailLevels;         // VirtualTextureLayout::tailLevels
uniform float u_lodBias;          // levels, > 0 coarser
uniform float u_maximumAnisotropyLog2;

const int kMissing = 4; // PageTableEntry::kMissing

// 2^e for an integer e (-126..127), exact: cheaper than exp2 or a division by 1 << e on llvmpipe.
float vtPowerOfTwo(int e)
{
    return intBitsToFloat((e + 127) << 23);
}

// The page under a point of the surface tile at a level, and where in it the point is (0..1).
struct PagePosition {
    ivec2 page;
    vec2 inPage;
};

PagePosition vtPagePosition(int level, vec2 tileCoordinates)
{
    // Without a branch (llvmpipe runs both sides of one for every pixel): `up` levels finer than
    // the tile, or `down` levels coarser.
    int finer = level - vtTileKey.x;
    int up = max(finer, 0);
    int down = max(-finer, 0);
    float pages = vtPowerOfTwo(up); // pages of this level across the tile; 1 when coarser
    vec2 scaled = tileCoordinates * pages;
    // Interpolated coordinates overshoot 0 and 1 by a rounding at the tile's edges.
    vec2 whole = clamp(floor(scaled), vec2(0.0), vec2(pages - 1.0));
    ivec2 within = vtTileKey.yz - ((vtTileKey.yz >> down) << down); // the tile within the coarser page
    return PagePosition(((vtTileKey.yz << up) >> down) + ivec2(whole), (vec2(within) + scaled - whole) * vtPowerOfTwo(-down));
}

// A page-table entry: the slot, the level of the page in it (the page's own or an ancestor's), and
// whether the source has no such page.
struct PageEntry {
    vec2 slot;
    int level;
    bool missing;
};

// From slot x + 2^8 slot y + 2^16 level + 2^21 flags, an integer exact in a float.
PageEntry vtDecodeEntry(float encoded)
{
    int bits = int(encoded);
    return PageEntry(vec2(float(bits & 255), float((bits >> 8) & 255)), (bits >> 16) & 31, ((bits >> 21) & kMissing) != 0);
}

// A page's entry and its parent page's (the page one level coarser holding it): the two levels a
// trilinear lookup blends.
struct PageEntries {
    PageEntry own;
    PageEntry parent;
};

PageEntries vtPageEntries(int level, ivec2 page)
{
    // VirtualTextureLayout::pageTableOrigin
    int finest = u_layout.x;
    ivec2 origin = level == finest ? ivec2(0) : ivec2((2 << finest) - (4 << level), 1 << finest);
    vec2 texel = texelFetch(og_texture0, page + origin, 0).rg;
    return PageEntries(vtDecodeEntry(texel.r), vtDecodeEntry(texel.g));
}

// Where a point of the tile is in the physical texture, read through the entry of its page at a
// level, and how many physical texels one unit of tile coordinates spans there.
vec2 vtPhysicalPosition(PageEntry entry, int level, PagePosition wanted, vec2 tileCoordinates, out float texelsPerTile)
{
    // Where the point is in the ancestor the entry falls back to, `coarser` levels up (0: the
    // page itself), from where it is in the page asked for.
    int coarser = max(level - entry.level, 0);
    vec2 inPage = (vec2(wanted.page - ((wanted.page >> coarser) << coarser)) + wanted.inPage) * vtPowerOfTwo(-coarser);
    vec2 texel = entry.slot * float(u_layout.w) + float(u_layout.z) + inPage * float(u_layout.y);
    texelsPerTile = float(u_layout.y) * vtPowerOfTwo(entry.level - vtTileKey.x);
    return texel * u_physicalTexelSize;
}

// log2 of a positive normal float from its exponent and mantissa bits, within 9e-4: the exponent,
// plus log2(1 + f) of the mantissa f (0..1) as a cubic exact at both ends (minimax). In place of
// llvmpipe's own log2, a longer polynomial: frames 5% faster.
float vtLog2(float x)
{
    int bits = floatBitsToInt(x);
    float f = intBitsToFloat((bits & 0x7fffff) | 0x3f800000) - 1.0;
    return float((bits >> 23) - 127) + f + f * (1.0 - f) * (0.42286 - 0.15922 * f);
}

// The level of detail, in levels above the finest (0: the finest level's texels match the pixels),
// from the squared lengths of a pixel's footprint across and up, in the finest level's texels;
// within 5e-4 of a level.
float vtLevelOfDetailSquared(float across, float up)
{
    float pa = max(across, 1e-30);
    float pb = max(up, 1e-30);
    float maxLod = 0.5 * vtLog2(max(pa, pb));
#ifdef VT_ANISOTROPIC
    // The anisotropic filter covers the footprint's long axis with up to maxAnisotropy probes.
    float minLod = 0.5 * vtLog2(min(pa, pb));
    return maxLod - min(maxLod - minLod, u_maximumAnisotropyLog2) + u_lodBias;
#else
    return maxLod + u_lodBias; // the long axis alone
#endif
}

// The same from the derivatives of the tile coordinates across and up one pixel.
float vtLevelOfDetail(vec2 dx, vec2 dy)
{
    float texelsPerTile = float(u_layout.y) * vtPowerOfTwo(u_layout.x - vtTileKey.x);
    vec2 a = dx * texelsPerTile;
    vec2 b = dy * texelsPerTile;
    return vtLevelOfDetailSquared(dot(a, a), dot(b, b));
}

// The coarsest level of detail the pages there allow (course 6.1.2's LOD clamp): never finer than
// the finest page's resident levels reach (the red channel), so every level blended is resident;
// and around a page the view asks for that is not resident yet (the green channel, far below zero
// elsewhere), a ramp falling away from it, so that the coarser look of a region waiting for its
// pages blends into its resident neighbours instead of ending at a seam. The ramp falls a level
// over kRampPixels pixels (from the level of detail lod: a page of the finest level spans
// P / 2^lod pixels), so that it hides the seam without showing coarser texels far into pages that
// are resident; and at least u_layout.x or 8 levels a page, so that no page beyond the eight
// neighbours can reach in. The ramp is compiled in (VT_LOD_RAMP) only while a page waits
// anywhere: otherwise only the page's own clamp counts.
const float kRampPixels = 4.0;

// The same from the point's page of the finest level and that page's clamp texel (red, green).
float vtLodClampAt(PagePosition finest, vec2 own, float lod)
{
    float allowed = max(own.r, own.g);
#ifdef VT_LOD_RAMP
    ivec2 size = textureSize(og_texture2, 0);
    vec2 f = clamp(finest.inPage, 0.0, 1.0);
    float slope = max(float(max(8, u_layout.x)), float(u_layout.y) * exp2(-lod) / kRampPixels);
    for (int dy = -1; dy <= 1; ++dy) {
        int y = finest.page.y + dy;
        if (y < 0 || y >= size.y) {
            continue; // nothing beyond the poles
        }
        float distanceY = dy < 0 ? f.y : (dy > 0 ? 1.0 - f.y : 0.0);
        for (int dx = -1; dx <= 1; ++dx) {
            if (dx == 0 && dy == 0) {
                continue;
            }
            int x = (finest.page.x + dx + size.x) % size.x; // the antimeridian wraps
            float distanceX = dx < 0 ? f.x : (dx > 0 ? 1.0 - f.x : 0.0);
            float waiting = texelFetch(og_texture2, ivec2(x, y), 0).g;
            allowed = max(allowed, waiting - slope * max(distanceX, distanceY));
        }
    }
#endif
    return allowed;
}

float vtLodClamp(vec2 tileCoordinates, float lod)
{
    PagePosition finest = vtPagePosition(u_layout.x, tileCoordinates);
    return vtLodClampAt(finest, texelFetch(og_texture2, finest.page, 0).rg, lod);
}

#ifdef VT_SPARSE
// The level of detail a point of the sparse texture may be read at: the one asked for, clamped
// by the LOD clamp (vtLodClamp), then raised until every bilinear tap of the two levels blended
// lies on a resident page. The taps reach at most a texel of the coarser level from the point: a
// square smaller than a page (the CPU makes sure), so it lies on the point's page of the finest
// level and those of its eight neighbours it reaches into. The clamp's texel of the point's page
// carries the finest level resident on each of them (red: its own; blue and alpha: its
// neighbours', 4 bits each: packResidencyNeighbours, PageTable.h), so no other texel is read.
// Residency is closed under ancestors (a page is put in after its parent, and no page with a
// resident child is evicted), so a page resident at level m is resident at every coarser one.
// Level 0 and the mipmap levels below it are always resident.
float vtSparseLod(vec2 tileCoordinates, float lod)
{
    PagePosition at = vtPagePosition(u_layout.x, tileCoordinates);
    vec4 own = texelFetch(og_texture2, at.page, 0);
    int sides = int(own.b);   // east, west, north, south, north-east, north-west, from bit 0
    int corners = int(own.a); // south-east, south-west
    float shown = max(lod, vtLodClampAt(at, own.rg, lod));
    for (int pass = 0; pass < u_layout.x; ++pass) {
        float level = max(floor(shown), 0.0);
        if (level >= float(u_layout.x)) {
            break;
        }
        float reach = vtPowerOfTwo(int(level) + 1) / float(u_layout.y); // in pages of the finest level
        bool east = at.inPage.x + reach >= 1.0;
        bool west = at.inPage.x - reach < 0.0;
        bool north = at.inPage.y + reach >= 1.0;
        bool south = at.inPage.y - reach < 0.0;
        float resident = own.r;
        resident = max(resident, east ? float(sides & 15) : 0.0);
        resident = max(resident, west ? float((sides >> 4) & 15) : 0.0);
        resident = max(resident, north ? float((sides >> 8) & 15) : 0.0);
        resident = max(resident, south ? float((sides >> 12) & 15) : 0.0);
        resident = max(resident, north && east ? float((sides >> 16) & 15) : 0.0);
        resident = max(resident, north && west ? float((sides >> 20) & 15) : 0.0);
        resident = max(resident, south && east ? float(corners & 15) : 0.0);
        resident = max(resident, south && west ? float((corners >> 4) & 15) : 0.0);
        if (resident <= level) {
            break;
        }
        shown = resident;
    }
    return shown;
}
#endif

// What a point shows: the finer of the two levels blended and the weight of the coarser one; and,
// for a footprint wider than a texel of level 0, how much wider (the mip tail's levels).
struct LevelChoice {
    int finer;           // level (0 coarsest .. N finest)
    float coarserWeight; // 0 when only the finer level is read
    int asked;           // the level the point's texels ask for, before the clamp
    float beyondLevel0;  // levels coarser than level 0 the point shows; > 0: the mip tail
};

LevelChoice vtChooseLevels(float lod, vec2 tileCoordinates)
{
    float finest = float(u_layout.x);
#if defined(VT_SPARSE)
    // A clamp only where it raised the level: the nearest level of an unclamped lod is its own.
    float clamped = vtSparseLod(tileCoordinates, lod);
    float allowed = clamped > lod ? clamped : 0.0;
#elif defined(VT_LOD_RAMP)
    float allowed = vtLodClamp(tileCoordinates, lod);
#else
    // No page waits: the page table's entry alone keeps the levels shown resident (see main),
    // without a read of the clamp.
    float allowed = 0.0;
#endif
#ifdef VT_TRILINEAR
    float asked = clamp(floor(lod), 0.0, finest);
    float shown = clamp(max(lod, allowed), 0.0, finest);
    float finer = floor(shown);
    float weight = shown - finer;
#else
    float asked = clamp(floor(lod + 0.5), 0.0, finest);
    float finer = clamp(max(asked, ceil(allowed - 1e-3)), 0.0, finest);
    float weight = 0.0;
#endif
    return LevelChoice(u_layout.x - int(finer), finer < finest ? weight : 0.0, u_layout.x - int(asked),
                       max(lod, allowed) - finest);
}

#ifdef OG_FRAGMENT_SHADER

// Where a point of the tile is on the whole globe: u and v, 0..1 from 180 degrees west and from the
// south pole.
vec2 vtGlobePosition(vec2 tileCoordinates)
{
    vec2 tiles = vec2(float(2 << vtTileKey.x), float(1 << vtTileKey.x));
    return (vec2(vtTileKey.yz) + tileCoordinates) / tiles;
}

// Where a point of the tile is in tail level t (Mayer 4.1: no page is smaller than a page, so the
// levels coarser than level 0 are its two pages halved t times, 1 .. VirtualTextureLayout::
// tailLevels), kept side by side in a strip of the physical texture (VirtualTextureLayout::
// tailOffset), and how many texels one unit of tile coordinates spans there.
vec2 vtTailPosition(int t, vec2 tileCoordinates, out float texelsPerTile)
{
    int twoPages = 2 * u_layout.y;
    int border = u_layout.z;
    vec2 size = vec2(float(max(twoPages >> t, 1)), float(max(u_layout.y >> t, 1)));
    float offset = float(twoPages - (twoPages >> (t - 1)) + 2 * border * (t - 1) + border);
    texelsPerTile = size.x / float(2 << vtTileKey.x);
    return (u_tailOrigin + vec2(offset, float(border)) + vtGlobePosition(tileCoordinates) * size) * u_physicalTexelSize;
}

// The physical texture's texels at a position, for a footprint (dx, dy in tile coordinates) at
// texelsPerTile.
vec4 vtRead(vec2 physical, float texelsPerTile, vec2 dx, vec2 dy)
{
#ifdef VT_ANISOTROPIC
    vec2 scale = texelsPerTile * u_physicalTexelSize;
    return textureGrad(og_texture1, physical, dx * scale, dy * scale);
#else
    // The physical texture has no mipmaps: without anisotropy the footprint does not matter.
    return textureLod(og_texture1, physical, 0.0);
#endif
}

#ifdef VT_FEEDBACK

uniform vec3 u_oneOverRadii;
uniform float u_polarOverEquatorialSquared; // (b / a)^2
uniform float u_texelsPerMetre; // the finest level's texels a metre along the equator
// How the ray changes from one of the frame's pixels to the next, across and up: the level of
// detail is the frame's pixels' own.
uniform vec3 u_pixelRight;
uniform vec3 u_pixelUp;

// The squared lengths of the frame's pixel's footprint across and up where its ray d meets the
// ellipsoid (t along it, normal n, facing = n . d < 0), in the finest level's texels: how far the
// point moves along the tangent plane as the ray moves by u_pixelRight or u_pixelUp, in longitude
// (over the radius of curvature across the meridian times cos(latitude)) and in latitude (over the
// one along it). Squared, so that neither radius needs a root: N = a / sqrt(q) and
// M = a (b/a)^2 / q^1.5, q = cos^2 + (b/a)^2 sin^2 of the latitude.
vec2 vtSquaredFootprints(vec3 d, float t, vec3 n, float facing)
{
    float cosSquared = max(dot(n.xy, n.xy), 1e-14);
    // Both of length cos(latitude); at a pole itself east is any way: there the longitude changes
    // fastest.
    vec3 east = dot(n.xy, n.xy) > 1e-14 ? vec3(-n.y, n.x, 0.0) : vec3(0.0, 1e-7, 0.0);
    vec3 north = vec3(-n.z * n.x, -n.z * n.y, cosSquared);
    float q = cosSquared + u_polarOverEquatorialSquared * n.z * n.z;
    float scale = t * u_texelsPerMetre;
    float alongLatitude = scale * scale * q / (cosSquared * cosSquared);
    float alongMeridian = alongLatitude * q * q * cosSquared / (u_polarOverEquatorialSquared * u_polarOverEquatorialSquared);
    // The point moves by p - d (n . p) / facing, times t.
    float eastD = dot(east, d) / facing;
    float northD = dot(north, d) / facing;
    float eastRight = dot(east, u_pixelRight) - eastD * dot(n, u_pixelRight);
    float northRight = dot(north, u_pixelRight) - northD * dot(n, u_pixelRight);
    float eastUp = dot(east, u_pixelUp) - eastD * dot(n, u_pixelUp);
    float northUp = dot(north, u_pixelUp) - northD * dot(n, u_pixelUp);
    return vec2(alongLatitude * eastRight * eastRight + alongMeridian * northRight * northRight,
                alongLatitude * eastUp * eastUp + alongMeridian * northUp * northUp);
}

// atan(y, x) within 1e-8 radians before float's rounding (a minimax polynomial in the square of
// the smaller argument over the larger): drivers' own atan and asin may be 1e-4 off (llvmpipe's
// asin put pixels 120 m from where they are), which names the wrong page near its edges at the
// deep levels.
float vtAtan2(float y, float x)
{
    vec2 a = abs(vec2(x, y));
    float r = min(a.x, a.y) / max(max(a.x, a.y), 1e-30); // 0..1
    float s = r * r;
    float angle = r * (0.999999982 + s * (-0.333330367 + s * (0.19991872 + s * (-0.141977978 + s * (0.106183706 +
                  s * (-0.0745685483 + s * (0.0421376236 + s * (-0.0157312491 + s * 0.0027662835))))))));
    angle = a.y > a.x ? 1.5707963 - angle : angle;
    angle = x < 0.0 ? 3.1415927 - angle : angle;
    return y < 0.0 ? -angle : angle;
}

void main()
{
    // The ray through the pixel meets the ellipsoid (ray_cast_ellipsoid.glsl, put before this
    // source), or the pixel packs to 0 (nothing asked for).
    vec3 d = v_ray;
    vec3 scaled = d * u_oneOverRadii;
    float t = rayCastEllipsoid(scaled);
    if (t < 0.0) {
        fragmentColor = vec4(0.0);
        return;
    }
    vec3 n = normalize((u_cameraScaled + t * scaled) * u_oneOverRadii); // the geodetic normal
    // At the limb the footprint grows without bound: a grazing cosine of 1e-4 (d is at least a
    // unit long, the view's axis plus offsets across it) already asks for the coarsest level.
    float facing = min(dot(n, d), -1e-4);
    vec2 footprints = vtSquaredFootprints(d, t, n, facing);
    // Level 0's two tiles are pi wide: the western from -pi, the eastern from 0.
    float longitude = vtAtan2(n.y, n.x);
    int east = longitude < 0.0 ? 0 : 1;
    vtTileKey = ivec3(0, east, 0);
    vec2 tc = vec2(longitude * og_oneOverPi + float(1 - east), vtAtan2(n.z, length(n.xy)) * og_oneOverPi + 0.5);

    LevelChoice choice = vtChooseLevels(vtLevelOfDetailSquared(footprints.x, footprints.y), tc);
    PagePosition asked = vtPagePosition(choice.asked, tc);
    PageEntry askedEntry = vtPageEntries(choice.asked, asked.page).own;
    // A coarser level than asked for is shown where the clamp chose one (then whatever its page)
    // or the page asked for falls back; unless the source has no such page.
    bool fallback = (choice.finer < choice.asked || askedEntry.level < choice.asked) && !askedEntry.missing;
    uint bits = uint(asked.page.x) | (uint(asked.page.y) << 13) | (uint(choice.asked) << 26) |
                (fallback ? (1u << 30) : 0u) | (1u << 31);
    fragmentColor = vec4(float(bits & 255u), float((bits >> 8) & 255u), float((bits >> 16) & 255u),
                         float(bits >> 24)) / 255.0;
}

#else

uniform vec4 u_baseColor;
uniform vec4 u_textureAdjustment; // alpha, brightness, contrast, 1 / gamma
#ifdef LIGHTING
uniform vec3 og_sunDirection;
#endif

void main()
{
    og_depthFragment();
    vec2 tc = v_tileCoordinates;
    vec2 dx = dFdx(tc);
    vec2 dy = dFdy(tc);
    float lod = vtLevelOfDetail(dx, dy);
#ifdef VT_SPARSE
    // The sampler blends the levels (or takes the nearest, without VT_TRILINEAR) at the level the
    // resident pages allow.
    vec4 texel = textureLod(og_texture1, vtGlobePosition(tc), vtSparseLod(tc, lod));
#else
    LevelChoice choice = vtChooseLevels(lod, tc);
    PagePosition wanted = vtPagePosition(choice.finer, tc);
    PageEntries entries = vtPageEntries(choice.finer, wanted.page);
    float finerTexels, coarserTexels;
    vec2 finer = vtPhysicalPosition(entries.own, choice.finer, wanted, tc, finerTexels);
    // The parent's entry falls back from the same page position as the page's own.
    vec2 coarser = vtPhysicalPosition(entries.parent, choice.finer, wanted, tc, coarserTexels);
    // Where the page falls back to a coarser one, that one alone, as the LOD clamp would have it.
    float coarserWeight = entries.own.level < choice.finer ? 0.0 : choice.coarserWeight;
#ifdef VT_MIP_TAIL
    // Compiled in only for tiles that may have pixels coarser than level 0 (the CPU's
    // mayAskForMipTail). There the two levels blended are level 0's pages and the tail's first
    // level, or two levels of the tail: read as the pages are, with no texture call more.
    if (choice.beyondLevel0 > 0.0) {
        int t = int(floor(choice.beyondLevel0)); // 0: level 0's pages, as chosen above
        if (t > 0) {
            finer = vtTailPosition(min(t, u_tailLevels), tc, finerTexels);
        }
        coarser = vtTailPosition(min(t + 1, u_tailLevels), tc, coarserTexels);
        coarserWeight = t < u_tailLevels ? fract(choice.beyondLevel0) : 0.0;
    }
#endif
    vec4 texel = vtRead(finer, finerTexels, dx, dy);
    if (coarserWeight > 0.0) {
        texel = mix(texel, vtRead(coarser, coarserTexels, dx, dy), coarserWeight);
    }
#endif
    // The adjustment compiled in only for a style that adjusts the colours (imagery_over.glsl, put
    // before this source).
    vec3 color = imageryOver(u_baseColor.rgb, texel, u_textureAdjustment);
#ifdef LIGHTING
    // In linear space, as models are lit: the imagery and colours are sRGB-encoded.
    color = og_linearToSrgb(og_srgbToLinear(color) * (0.2 + 0.8 * max(dot(normalize(v_normal), og_sunDirection), 0.0)));
#endif
    fragmentColor = vec4(color, 1.0);
}

#endif // VT_FEEDBACK
#endif // OG_FRAGMENT_SHADER

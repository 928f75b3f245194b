#include "TerrainMesh.h"

#include <orbis/core/Math.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace orbis::world::detail {

namespace {

/// Keeps the samples of a profile that a polyline within `tolerance` of every sample needs: the
/// ends, then recursively the sample farthest from the chord while it is farther than tolerance.
void keepAlongEdge(std::span<const float> profile, double tolerance, std::vector<bool>& keep)
{
    keep.assign(profile.size(), false);
    keep.front() = true;
    keep.back() = true;
    std::vector<std::pair<std::size_t, std::size_t>> spans = {{0, profile.size() - 1}};
    while (!spans.empty()) {
        const auto [a, b] = spans.back();
        spans.pop_back();
        double worst = -1.0;
        std::size_t at = a;
        for (std::size_t i = a + 1; i < b; ++i) {
            const double t = static_cast<double>(i - a) / static_cast<double>(b - a);
            const double chord = static_cast<double>(profile[a]) + t * static_cast<double>(profile[b] - profile[a]);
            const double deviation = std::abs(static_cast<double>(profile[i]) - chord);
            if (deviation > worst) {
                worst = deviation;
                at = i;
            }
        }
        if (worst > tolerance) {
            keep[at] = true;
            spans.push_back({a, at});
            spans.push_back({at, b});
        }
    }
}

/// A triangulation of the grid's lattice refined by greedy insertion (Garland and Heckbert, "Fast
/// polygonal approximation of terrains and height fields", 1995): starting from the tile's kept
/// edge samples, the sample farthest (vertically) from the triangle holding it is inserted, and
/// the triangulation kept Delaunay by edge flips, until no sample is farther than the
/// tolerance. Edges on the tile's boundary are never flipped nor split by interior samples, so
/// the boundary is exactly the kept edge samples. Coordinates are lattice points (column, row from
/// the south), so every orientation and circle test is exact in 64-bit integers.
class GreedyTin {
public:
    GreedyTin(std::span<const float> heights, int size) : _heights(heights), _size(size), _last(size - 1) {}

    /// Inserts the boundary's kept samples, then interior samples until within tolerance.
    void build(const std::vector<bool>& keptOnBoundary, double tolerance)
    {
        const int a = addPoint(0, 0);
        const int b = addPoint(_last, 0);
        const int c = addPoint(_last, _last);
        const int d = addPoint(0, _last);
        const int first = addTriangle(a, b, c, -1, -1, -1);
        const int second = addTriangle(a, c, d, -1, -1, -1);
        link(3 * first + 2, 3 * second);
        // The boundary's samples, each splitting the boundary edge it lies on.
        for (int i = 1; i < _last; ++i) {
            for (const auto& [x, y] : {std::pair(i, 0), std::pair(_last, i), std::pair(i, _last), std::pair(0, i)}) {
                if (keptOnBoundary[static_cast<std::size_t>(sampleOf(x, y))]) {
                    insertOnBoundary(x, y);
                }
            }
        }
        for (std::size_t t = 0; t < _triangles.size() / 3; ++t) {
            refresh(static_cast<int>(t));
        }
        while (!_heap.empty() && _error[static_cast<std::size_t>(_heap.front())] > tolerance) {
            const int t = _heap.front();
            insertInterior(t, _candidateX[static_cast<std::size_t>(t)], _candidateY[static_cast<std::size_t>(t)]);
        }
    }

    /// Sample index (row from the north * size + column) of each point, and the triangles.
    std::vector<int> samples() const
    {
        std::vector<int> result;
        for (std::size_t i = 0; i < _x.size(); ++i) {
            result.push_back(sampleOf(_x[i], _y[i]));
        }
        return result;
    }
    const std::vector<int>& triangles() const noexcept { return _triangles; }

private:
    int sampleOf(int x, int y) const noexcept { return (_last - y) * _size + x; }
    double heightAt(int x, int y) const noexcept { return static_cast<double>(_heights[static_cast<std::size_t>(sampleOf(x, y))]); }

    static std::int64_t orient(std::int64_t ax, std::int64_t ay, std::int64_t bx, std::int64_t by, std::int64_t cx,
                               std::int64_t cy) noexcept
    {
        return (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
    }

    int addPoint(int x, int y)
    {
        _x.push_back(x);
        _y.push_back(y);
        return static_cast<int>(_x.size()) - 1;
    }

    /// A counter-clockwise triangle; its half-edges a->b, b->c, c->a get the twins given.
    int addTriangle(int a, int b, int c, int twinAB, int twinBC, int twinCA)
    {
        const int t = static_cast<int>(_triangles.size() / 3);
        _triangles.insert(_triangles.end(), {a, b, c});
        _twins.insert(_twins.end(), {-1, -1, -1});
        _error.push_back(-1.0);
        _candidateX.push_back(0);
        _candidateY.push_back(0);
        _heapIndex.push_back(-1);
        link(3 * t, twinAB);
        link(3 * t + 1, twinBC);
        link(3 * t + 2, twinCA);
        return t;
    }

    /// Rewrites triangle t in place.
    void setTriangle(int t, int a, int b, int c, int twinAB, int twinBC, int twinCA)
    {
        const auto base = static_cast<std::size_t>(3 * t);
        _triangles[base] = a;
        _triangles[base + 1] = b;
        _triangles[base + 2] = c;
        link(3 * t, twinAB);
        link(3 * t + 1, twinBC);
        link(3 * t + 2, twinCA);
    }

    void link(int edge, int twin)
    {
        _twins[static_cast<std::size_t>(edge)] = twin;
        if (twin >= 0) {
            _twins[static_cast<std::size_t>(twin)] = edge;
        }
    }

    static int next(int edge) noexcept { return edge % 3 == 2 ? edge - 2 : edge + 1; }
    static int previous(int edge) noexcept { return edge % 3 == 0 ? edge + 2 : edge - 1; }
    int start(int edge) const noexcept { return _triangles[static_cast<std::size_t>(edge)]; }
    int twin(int edge) const noexcept { return _twins[static_cast<std::size_t>(edge)]; }

    /// A boundary sample: splits the boundary edge that holds it into two.
    void insertOnBoundary(int x, int y)
    {
        for (std::size_t e = 0; e < _triangles.size(); ++e) {
            const int edge = static_cast<int>(e);
            if (twin(edge) >= 0) {
                continue;
            }
            const int p0 = start(edge);
            const int p1 = start(next(edge));
            if (orient(_x[p0], _y[p0], _x[p1], _y[p1], x, y) != 0) {
                continue;
            }
            const bool between = std::min(_x[p0], _x[p1]) <= x && x <= std::max(_x[p0], _x[p1]) &&
                                 std::min(_y[p0], _y[p1]) <= y && y <= std::max(_y[p0], _y[p1]) &&
                                 !(x == _x[p0] && y == _y[p0]) && !(x == _x[p1] && y == _y[p1]);
            if (!between) {
                continue;
            }
            const int p2 = start(previous(edge));
            const int t = edge / 3;
            const int outer12 = twin(next(edge));
            const int outer20 = twin(previous(edge));
            const int p = addPoint(x, y);
            setTriangle(t, p0, p, p2, -1, -1, outer20);
            const int other = addTriangle(p, p1, p2, -1, outer12, 3 * t + 1);
            legalize(3 * t + 2);
            legalize(3 * other + 1);
            return;
        }
    }

    /// An interior sample of triangle t: inside it (three triangles) or on one of its edges,
    /// which is then an inner edge (four triangles).
    void insertInterior(int t, int x, int y)
    {
        const int e0 = 3 * t;
        for (int k = 0; k < 3; ++k) {
            const int edge = e0 + k;
            const int a = start(edge);
            const int b = start(next(edge));
            if (orient(_x[a], _y[a], _x[b], _y[b], x, y) == 0) {
                splitEdge(edge, x, y);
                return;
            }
        }
        const int a = start(e0);
        const int b = start(e0 + 1);
        const int c = start(e0 + 2);
        const int twinAB = twin(e0);
        const int twinBC = twin(e0 + 1);
        const int twinCA = twin(e0 + 2);
        const int p = addPoint(x, y);
        setTriangle(t, a, b, p, twinAB, -1, -1);
        const int second = addTriangle(b, c, p, twinBC, -1, 3 * t + 1);
        const int third = addTriangle(c, a, p, twinCA, 3 * t + 2, 3 * second + 1);
        _changed = {t, second, third};
        legalize(3 * t);
        legalize(3 * second);
        legalize(3 * third);
        refreshChanged();
    }

    /// Splits the inner edge `edge` (a -> b, in triangle a b c; its twin b -> a in b a d) at x, y.
    void splitEdge(int edge, int x, int y)
    {
        const int other = twin(edge);
        const int t = edge / 3;
        const int a = start(edge);
        const int b = start(next(edge));
        const int c = start(previous(edge));
        const int twinBC = twin(next(edge));
        const int twinCA = twin(previous(edge));
        const int p = addPoint(x, y);
        if (other < 0) {
            // Not reached for interior samples (they never lie on the boundary); kept total.
            setTriangle(t, a, p, c, -1, -1, twinCA);
            const int second = addTriangle(p, b, c, -1, twinBC, 3 * t + 1);
            _changed = {t, second};
            legalize(3 * t + 2);
            legalize(3 * second + 1);
            refreshChanged();
            return;
        }
        const int u = other / 3;
        const int d = start(previous(other));
        const int twinAD = twin(next(other));
        const int twinDB = twin(previous(other));
        // a p c, p b c on this side; b p d, p a d on the other.
        setTriangle(t, a, p, c, -1, -1, twinCA);
        const int second = addTriangle(p, b, c, -1, twinBC, 3 * t + 1);
        setTriangle(u, b, p, d, 3 * second, -1, twinDB);
        const int fourth = addTriangle(p, a, d, 3 * t, twinAD, 3 * u + 1);
        _changed = {t, second, u, fourth};
        legalize(3 * t + 2);
        legalize(3 * second + 1);
        legalize(3 * u + 2);
        legalize(3 * fourth + 1);
        refreshChanged();
    }

    /// Restores the Delaunay condition across `edge` (whose triangle holds the new point
    /// opposite it), flipping and recursing; boundary edges have no twin and stay.
    void legalize(int edge)
    {
        std::vector<int> pending = {edge};
        while (!pending.empty()) {
            const int e = pending.back();
            pending.pop_back();
            const int opposite = twin(e);
            if (opposite < 0) {
                continue;
            }
            // Triangle of e: a -> b (e), b -> p, p -> a; across: b -> a (opposite), a -> q, q -> b.
            const int a = start(e);
            const int b = start(next(e));
            const int p = start(previous(e));
            const int q = start(previous(opposite));
            if (!inCircle(a, b, p, q)) {
                continue;
            }
            const int t = e / 3;
            const int u = opposite / 3;
            const int twinBP = twin(next(e));
            const int twinPA = twin(previous(e));
            const int twinAQ = twin(next(opposite));
            const int twinQB = twin(previous(opposite));
            // Flipped: p -> a -> q and p -> q -> b.
            setTriangle(t, p, a, q, twinPA, twinAQ, -1);
            setTriangle(u, p, q, b, 3 * t + 2, twinQB, twinBP);
            if (std::find(_changed.begin(), _changed.end(), u) == _changed.end()) {
                _changed.push_back(u);
            }
            if (std::find(_changed.begin(), _changed.end(), t) == _changed.end()) {
                _changed.push_back(t);
            }
            pending.push_back(3 * t + 1); // a -> q, opposite p
            pending.push_back(3 * u + 1); // q -> b, opposite p
        }
    }

    /// q inside the circle through the counter-clockwise a, b, p.
    bool inCircle(int a, int b, int p, int q) const noexcept
    {
        const std::int64_t ax = _x[a] - _x[q], ay = _y[a] - _y[q];
        const std::int64_t bx = _x[b] - _x[q], by = _y[b] - _y[q];
        const std::int64_t px = _x[p] - _x[q], py = _y[p] - _y[q];
        const std::int64_t determinant = (ax * ax + ay * ay) * (bx * py - px * by) - (bx * bx + by * by) * (ax * py - px * ay) +
                                         (px * px + py * py) * (ax * by - bx * ay);
        return determinant > 0;
    }

    void refreshChanged()
    {
        for (const int t : _changed) {
            refresh(t);
        }
        _changed.clear();
    }

    /// The triangle's farthest interior sample and its distance, into the heap.
    void refresh(int t)
    {
        const auto base = static_cast<std::size_t>(3 * t);
        const int a = _triangles[base];
        const int b = _triangles[base + 1];
        const int c = _triangles[base + 2];
        const std::int64_t ax = _x[a], ay = _y[a], bx = _x[b], by = _y[b], cx = _x[c], cy = _y[c];
        const std::int64_t area = orient(ax, ay, bx, by, cx, cy);
        const double ha = heightAt(_x[a], _y[a]);
        const double hb = heightAt(_x[b], _y[b]);
        const double hc = heightAt(_x[c], _y[c]);
        double worst = -1.0;
        int worstX = 0;
        int worstY = 0;
        const auto x0 = static_cast<int>(std::max<std::int64_t>(1, std::min({ax, bx, cx})));
        const auto x1 = static_cast<int>(std::min<std::int64_t>(_last - 1, std::max({ax, bx, cx})));
        const auto y0 = static_cast<int>(std::max<std::int64_t>(1, std::min({ay, by, cy})));
        const auto y1 = static_cast<int>(std::min<std::int64_t>(_last - 1, std::max({ay, by, cy})));
        for (int y = y0; y <= y1; ++y) {
            for (int x = x0; x <= x1; ++x) {
                const std::int64_t wa = orient(bx, by, cx, cy, x, y);
                const std::int64_t wb = orient(cx, cy, ax, ay, x, y);
                const std::int64_t wc = area - wa - wb;
                if (wa < 0 || wb < 0 || wc < 0) {
                    continue;
                }
                const double h = (static_cast<double>(wa) * ha + static_cast<double>(wb) * hb + static_cast<double>(wc) * hc) /
                                 static_cast<double>(area);
                const double error = std::abs(heightAt(x, y) - h);
                if (error > worst) {
                    worst = error;
                    worstX = x;
                    worstY = y;
                }
            }
        }
        _error[static_cast<std::size_t>(t)] = worst;
        _candidateX[static_cast<std::size_t>(t)] = worstX;
        _candidateY[static_cast<std::size_t>(t)] = worstY;
        heapUpdate(t);
    }

    // A max-heap of triangles by their error; triangles without an interior sample stay out.
    bool higher(int i, int j) const noexcept
    {
        const double a = _error[static_cast<std::size_t>(_heap[static_cast<std::size_t>(i)])];
        const double b = _error[static_cast<std::size_t>(_heap[static_cast<std::size_t>(j)])];
        // Ties broken by triangle number, so the result does not depend on the heap's history.
        return a > b || (a == b && _heap[static_cast<std::size_t>(i)] < _heap[static_cast<std::size_t>(j)]);
    }
    void swapHeap(int i, int j)
    {
        std::swap(_heap[static_cast<std::size_t>(i)], _heap[static_cast<std::size_t>(j)]);
        _heapIndex[static_cast<std::size_t>(_heap[static_cast<std::size_t>(i)])] = i;
        _heapIndex[static_cast<std::size_t>(_heap[static_cast<std::size_t>(j)])] = j;
    }
    void siftUp(int i)
    {
        while (i > 0 && higher(i, (i - 1) / 2)) {
            swapHeap(i, (i - 1) / 2);
            i = (i - 1) / 2;
        }
    }
    void siftDown(int i)
    {
        const int count = static_cast<int>(_heap.size());
        for (;;) {
            int best = i;
            for (const int child : {2 * i + 1, 2 * i + 2}) {
                if (child < count && higher(child, best)) {
                    best = child;
                }
            }
            if (best == i) {
                return;
            }
            swapHeap(i, best);
            i = best;
        }
    }
    void heapUpdate(int t)
    {
        int& index = _heapIndex[static_cast<std::size_t>(t)];
        if (index >= 0) {
            // Out, then in again where it now belongs.
            const int at = index;
            const int lastIndex = static_cast<int>(_heap.size()) - 1;
            swapHeap(at, lastIndex);
            _heap.pop_back();
            _heapIndex[static_cast<std::size_t>(t)] = -1;
            if (at < lastIndex) {
                siftUp(at);
                siftDown(at);
            }
        }
        if (_error[static_cast<std::size_t>(t)] < 0.0) {
            return;
        }
        _heap.push_back(t);
        _heapIndex[static_cast<std::size_t>(t)] = static_cast<int>(_heap.size()) - 1;
        siftUp(static_cast<int>(_heap.size()) - 1);
    }

    std::span<const float> _heights;
    int _size;
    int _last;
    std::vector<int> _x, _y;         ///< points
    std::vector<int> _triangles;     ///< 3 points per triangle, counter-clockwise
    std::vector<int> _twins;         ///< per half-edge: the opposite half-edge, or -1 on the boundary
    std::vector<double> _error;      ///< per triangle: its farthest interior sample's distance (-1: none)
    std::vector<int> _candidateX, _candidateY;
    std::vector<int> _heap;
    std::vector<int> _heapIndex;
    std::vector<int> _changed;       ///< triangles made or flipped by the insertion under way
};

} // namespace

SimplifiedMesh simplifyGrid(std::span<const float> heights, int size, double tolerance)
{
    const int last = size - 1;
    // The edges' samples reduced on their own, each edge read west to east or south to north.
    std::vector<bool> kept(static_cast<std::size_t>(size) * static_cast<std::size_t>(size), false);
    std::vector<float> profile(static_cast<std::size_t>(size));
    std::vector<bool> keep;
    auto reduce = [&](auto sampleAt) {
        for (int i = 0; i < size; ++i) {
            profile[static_cast<std::size_t>(i)] = heights[static_cast<std::size_t>(sampleAt(i))];
        }
        keepAlongEdge(profile, tolerance, keep);
        for (int i = 0; i < size; ++i) {
            if (keep[static_cast<std::size_t>(i)]) {
                kept[static_cast<std::size_t>(sampleAt(i))] = true;
            }
        }
    };
    reduce([&](int i) { return last * size + i; });          // south
    reduce([&](int i) { return i; });                        // north
    reduce([&](int i) { return (last - i) * size; });        // west
    reduce([&](int i) { return (last - i) * size + last; }); // east

    GreedyTin tin(heights, size);
    tin.build(kept, tolerance);
    SimplifiedMesh mesh;
    mesh.gridIndex = tin.samples();
    for (const int sample : mesh.gridIndex) {
        const int column = sample % size;
        const int rowFromSouth = last - sample / size;
        mesh.vertices.emplace_back(static_cast<float>(column) / static_cast<float>(last),
                                   static_cast<float>(rowFromSouth) / static_cast<float>(last),
                                   heights[static_cast<std::size_t>(sample)]);
    }
    for (const int index : tin.triangles()) {
        mesh.indices.push_back(static_cast<std::uint32_t>(index));
    }
    return mesh;
}

std::vector<Geodetic2D> gridPositionsWithMargin(const TileKey& key, int size)
{
    const int stride = size + 2;
    std::vector<Geodetic2D> positions(static_cast<std::size_t>(stride) * static_cast<std::size_t>(stride));
    for (int row = -1; row <= size; ++row) {
        for (int column = -1; column <= size; ++column) {
            Geodetic2D g = terrainGridPosition(key, size, column, row);
            g.latitude = std::clamp(g.latitude, -kHalfPi, kHalfPi);
            // Across the antimeridian the margin is the other side's first samples.
            if (g.longitude < -kPi) {
                g.longitude += kTwoPi;
            } else if (g.longitude > kPi) {
                g.longitude -= kTwoPi;
            }
            positions[static_cast<std::size_t>((row + 1) * stride + column + 1)] = g;
        }
    }
    return positions;
}

std::vector<float> withoutMargin(std::span<const float> heightsWithMargin, int size)
{
    const std::size_t stride = static_cast<std::size_t>(size) + 2;
    std::vector<float> grid(static_cast<std::size_t>(size) * static_cast<std::size_t>(size));
    for (std::size_t row = 0; row < static_cast<std::size_t>(size); ++row) {
        std::copy_n(&heightsWithMargin[(row + 1) * stride + 1], size, &grid[row * static_cast<std::size_t>(size)]);
    }
    return grid;
}

std::vector<glm::vec3> gridNormals(const TileKey& key, int size, std::span<const float> heightsWithMargin,
                                   const Ellipsoid& ellipsoid)
{
    const int stride = size + 2;
    const GeodeticExtent extent = TilingScheme::geographic().tileExtent(key);
    const double step = (extent.east - extent.west) / (size - 1); // radians, the same both ways
    const double a = ellipsoid.radii().x;
    const double b = ellipsoid.radii().z;
    const double e2 = 1.0 - (b * b) / (a * a);
    std::vector<glm::vec3> normals(static_cast<std::size_t>(size) * static_cast<std::size_t>(size));
    for (int row = 0; row < size; ++row) {
        for (int column = 0; column < size; ++column) {
            const Geodetic2D g = terrainGridPosition(key, size, column, row);
            auto h = [&](int r, int c) {
                return static_cast<double>(heightsWithMargin[static_cast<std::size_t>((r + 1) * stride + c + 1)]);
            };
            const double sinLatitude = std::sin(g.latitude);
            const double cosLatitude = std::cos(g.latitude);
            const double w = std::sqrt(1.0 - e2 * sinLatitude * sinLatitude);
            const double east = step * a / w * cosLatitude;                   // metres between columns
            const double north = step * a * (1.0 - e2) / (w * w * w);         // metres between rows
            const double dEast = east > 1e-6 * north ? (h(row, column + 1) - h(row, column - 1)) / (2.0 * east) : 0.0;
            const double dNorth = (h(row - 1, column) - h(row + 1, column)) / (2.0 * north);
            const glm::dvec3 local = glm::normalize(glm::dvec3(-dEast, -dNorth, 1.0));
            const double sinLongitude = std::sin(g.longitude);
            const double cosLongitude = std::cos(g.longitude);
            const glm::dvec3 eastAxis(-sinLongitude, cosLongitude, 0.0);
            const glm::dvec3 northAxis(-sinLatitude * cosLongitude, -sinLatitude * sinLongitude, cosLatitude);
            const glm::dvec3 upAxis(cosLatitude * cosLongitude, cosLatitude * sinLongitude, sinLatitude);
            normals[static_cast<std::size_t>(row * size + column)] =
                glm::vec3(glm::normalize(local.x * eastAxis + local.y * northAxis + local.z * upAxis));
        }
    }
    return normals;
}

double gridDeviation(std::span<const float> heights, int size, double u, double v, double h) noexcept
{
    const double last = size - 1;
    const double x = std::clamp(u, 0.0, 1.0) * last;
    const double y = (1.0 - std::clamp(v, 0.0, 1.0)) * last; // rows from the north
    const int column = std::clamp(static_cast<int>(x), 0, size - 2);
    const int row = std::clamp(static_cast<int>(y), 0, size - 2);
    const double fx = x - column;
    const double fy = y - row;
    auto at = [&](int r, int c) { return static_cast<double>(heights[static_cast<std::size_t>(r * size + c)]); };
    const double nw = at(row, column);
    const double ne = at(row, column + 1);
    const double sw = at(row + 1, column);
    const double se = at(row + 1, column + 1);
    // Cut north-west to south-east, and north-east to south-west.
    const double first = fx >= fy ? nw + fx * (ne - nw) + fy * (se - ne) : nw + fy * (sw - nw) + fx * (se - sw);
    const double second = fx + fy <= 1.0 ? nw + fx * (ne - nw) + fy * (sw - nw)
                                         : se + (1.0 - fx) * (sw - se) + (1.0 - fy) * (ne - se);
    return std::max(std::abs(h - first), std::abs(h - second));
}

} // namespace orbis::world::detail

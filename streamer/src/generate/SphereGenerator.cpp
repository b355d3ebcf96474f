// Geodesic icosphere: each icosahedron face is split into f*f triangles on a barycentric
// lattice, then every lattice point is projected onto the unit sphere.
//
// Vertex numbering (no table, so memory stays O(1) for any f):
//   [0, 12)                      the 12 icosahedron corners
//   [12, 12 + 30(f-1))           edge interiors, f-1 per edge, ordered from the edge's lower
//                                corner index to the higher one (so both faces agree)
//   then 20 blocks of (f-1)(f-2)/2 face interiors
// giving V = 10 f^2 + 2 and F = 20 f^2 (V - E + F = 2).
#include <array>
#include <cmath>

#include "generate/Generators.h"

namespace vastray::gen {
namespace {

struct DVec3 {
    double x, y, z;
};

constexpr double kPhi = 1.6180339887498948482;

// Corners and CCW-from-outside faces of the icosahedron.
constexpr std::array<DVec3, 12> kCorners = {{
    {-1, kPhi, 0},
    {1, kPhi, 0},
    {-1, -kPhi, 0},
    {1, -kPhi, 0},
    {0, -1, kPhi},
    {0, 1, kPhi},
    {0, -1, -kPhi},
    {0, 1, -kPhi},
    {kPhi, 0, -1},
    {kPhi, 0, 1},
    {-kPhi, 0, -1},
    {-kPhi, 0, 1},
}};
constexpr std::array<std::array<uint32_t, 3>, 20> kFaces = {{
    {0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
    {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
    {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1},
}};

struct Edge {
    uint32_t a, b;  // a < b
};

// The 30 edges in first-seen order over kFaces, and a corner-pair -> edge id table.
struct Topology {
    std::array<Edge, 30> edges{};
    std::array<std::array<uint8_t, 12>, 12> edgeId{};

    constexpr Topology() {
        uint32_t count = 0;
        for (auto& row : edgeId) row.fill(0xFF);
        for (const auto& face : kFaces) {
            for (int k = 0; k < 3; ++k) {
                uint32_t u = face[k], v = face[(k + 1) % 3];
                if (edgeId[u][v] != 0xFF) continue;
                edges[count] = {u < v ? u : v, u < v ? v : u};
                edgeId[u][v] = edgeId[v][u] = static_cast<uint8_t>(count++);
            }
        }
    }
};
constexpr Topology kTopology;
static_assert(kTopology.edges[29].b != 0, "the icosahedron has exactly 30 edges");

uint64_t subdivisions(uint64_t triangles) {
    uint64_t f = static_cast<uint64_t>(std::llround(std::sqrt(static_cast<double>(triangles) / 20.0)));
    return f < 1 ? 1 : f;
}

// Lattice point (A (f-i-j) + B i + C j) / f projected to the unit sphere; double until the end.
Vec3f latticePoint(const DVec3& a, const DVec3& b, const DVec3& c, uint64_t i, uint64_t j, uint64_t f) {
    double wa = static_cast<double>(f - i - j), wb = static_cast<double>(i), wc = static_cast<double>(j);
    double x = a.x * wa + b.x * wb + c.x * wc;
    double y = a.y * wa + b.y * wb + c.y * wc;
    double z = a.z * wa + b.z * wb + c.z * wc;
    double inv = 1.0 / std::sqrt(x * x + y * y + z * z);
    return {static_cast<float>(x * inv), static_cast<float>(y * inv), static_cast<float>(z * inv)};
}

// Maps lattice coordinates (i along A->B, j along A->C) of face `face` to a vertex index.
class FaceIndexer {
public:
    FaceIndexer(uint32_t face, uint64_t f) : f_(f), corners_(kFaces[face]) {
        uint64_t interiorPerFace = f < 2 ? 0 : (f - 1) * (f - 2) / 2;
        interiorBase_ = 12 + 30 * (f - 1) + face * interiorPerFace;
    }

    uint32_t operator()(uint64_t i, uint64_t j) const {
        if (j == 0) return edgePoint(corners_[0], corners_[1], i);
        if (i == 0) return edgePoint(corners_[0], corners_[2], j);
        if (i + j == f_) return edgePoint(corners_[1], corners_[2], j);
        // Row j (1 <= j <= f-2) holds interior points i = 1 .. f-1-j.
        uint64_t rowStart = (j - 1) * (f_ - 1) - (j - 1) * j / 2;
        return static_cast<uint32_t>(interiorBase_ + rowStart + (i - 1));
    }

private:
    // Point k steps (0..f) from corner u towards corner v.
    uint32_t edgePoint(uint32_t u, uint32_t v, uint64_t k) const {
        if (k == 0) return u;
        if (k == f_) return v;
        uint64_t fromLower = u < v ? k : f_ - k;
        uint64_t edge = kTopology.edgeId[u][v];
        return static_cast<uint32_t>(12 + edge * (f_ - 1) + (fromLower - 1));
    }

    uint64_t f_;
    std::array<uint32_t, 3> corners_;
    uint64_t interiorBase_ = 0;
};

Status emitVertices(uint64_t f, MeshSink& sink) {
    for (const DVec3& corner : kCorners) {
        VASTRAY_TRY(sink.vertex(latticePoint(corner, corner, corner, 0, 0, f)));
    }
    for (const Edge& edge : kTopology.edges) {
        const DVec3 &a = kCorners[edge.a], &b = kCorners[edge.b];
        for (uint64_t k = 1; k < f; ++k) VASTRAY_TRY(sink.vertex(latticePoint(a, b, b, k, 0, f)));
    }
    for (const auto& face : kFaces) {
        const DVec3 &a = kCorners[face[0]], &b = kCorners[face[1]], &c = kCorners[face[2]];
        for (uint64_t j = 1; j + 1 < f; ++j) {
            for (uint64_t i = 1; i + j < f; ++i) VASTRAY_TRY(sink.vertex(latticePoint(a, b, c, i, j, f)));
        }
    }
    return Status::ok();
}

// Lattice triangles keep the orientation of their face, hence CCW from outside.
Status emitFaces(uint64_t f, MeshSink& sink) {
    for (uint32_t face = 0; face < 20; ++face) {
        FaceIndexer index(face, f);
        for (uint64_t j = 0; j < f; ++j) {
            for (uint64_t i = 0; i + j < f; ++i) {
                VASTRAY_TRY(sink.face(index(i, j), index(i + 1, j), index(i, j + 1)));
                if (i + j + 1 < f) {
                    VASTRAY_TRY(sink.face(index(i + 1, j), index(i + 1, j + 1), index(i, j + 1)));
                }
            }
        }
    }
    return Status::ok();
}

}  // namespace

GeneratedCounts sphereCounts(uint64_t triangles) {
    uint64_t f = subdivisions(triangles);
    return {10 * f * f + 2, 20 * f * f};
}

Status generateSphere(const GenerateOptions& options, MeshSink& sink) {
    uint64_t f = subdivisions(options.triangles);
    GeneratedCounts counts = sphereCounts(options.triangles);
    VASTRAY_TRY(sink.begin(counts.vertices, counts.triangles));
    VASTRAY_TRY(emitVertices(f, sink));
    VASTRAY_TRY(emitFaces(f, sink));
    return sink.end();
}

}  // namespace vastray::gen

// City: a ground quad (y = 0) over [-1, 1]^2 and a g * g grid of boxes standing on it, each
// with its own 8 vertices and 10 outward-wound triangles (4 walls + roof; the floor is
// never seen). Box b's footprint and height come from its own stream hash(seed, b), so
// nothing is stored between the vertex and face passes.
#include <algorithm>
#include <array>
#include <cmath>

#include "generate/Generators.h"
#include "generate/Random.h"

namespace vastray::gen {
namespace {

constexpr uint64_t kGroundVertices = 4, kGroundTriangles = 2;
constexpr uint64_t kBoxVertices = 8, kBoxTriangles = 10;

uint64_t gridSide(uint64_t triangles) {
    double boxes = static_cast<double>(triangles - kGroundTriangles) / kBoxTriangles;
    auto side = static_cast<uint64_t>(std::llround(std::sqrt(boxes)));
    return std::max<uint64_t>(side, 1);
}

struct Box {
    float x0, x1, z0, z1, height;
};

// Footprint: 40-85% of its cell, placed anywhere inside it (streets stay open). Height:
// cubic in a uniform draw, so most buildings are low and a few are towers.
Box boxAt(uint64_t seed, uint64_t side, uint64_t row, uint64_t column) {
    Rng rng(hashCombine(seed, row * side + column));
    float cell = static_cast<float>(2.0 / static_cast<double>(side));
    float cellX = -1.0f + cell * static_cast<float>(column), cellZ = -1.0f + cell * static_cast<float>(row);
    float width = cell * rng.uniform(0.4f, 0.85f), depth = cell * rng.uniform(0.4f, 0.85f);
    float x0 = cellX + (cell - width) * rng.uniform01(), z0 = cellZ + (cell - depth) * rng.uniform01();
    float u = rng.uniform01();
    return {x0, x0 + width, z0, z0 + depth, 0.02f + 0.6f * u * u * u};
}

// Bottom ring 0-3 (y = 0) then top ring 4-7 (y = height), each in the order
// (x0,z0), (x1,z0), (x1,z1), (x0,z1).
Status emitBoxVertices(const Box& b, MeshSink& sink) {
    const std::array<float, 4> xs = {b.x0, b.x1, b.x1, b.x0}, zs = {b.z0, b.z0, b.z1, b.z1};
    for (float y : {0.0f, b.height}) {
        for (int k = 0; k < 4; ++k) VASTRAY_TRY(sink.vertex({xs[k], y, zs[k]}));
    }
    return Status::ok();
}

Status emitBoxFaces(uint32_t base, MeshSink& sink) {
    for (uint32_t k = 0; k < 4; ++k) {
        uint32_t a = base + k, b = base + (k + 1) % 4;
        VASTRAY_TRY(sink.face(a, b + 4, b));
        VASTRAY_TRY(sink.face(a, a + 4, b + 4));
    }
    VASTRAY_TRY(sink.face(base + 4, base + 7, base + 5));
    return sink.face(base + 5, base + 7, base + 6);
}

Status emitGround(MeshSink& sink) {
    for (Vec3f p : {Vec3f{-1, 0, -1}, Vec3f{1, 0, -1}, Vec3f{1, 0, 1}, Vec3f{-1, 0, 1}}) {
        VASTRAY_TRY(sink.vertex(p));
    }
    return Status::ok();
}

}  // namespace

GeneratedCounts cityCounts(uint64_t triangles) {
    uint64_t boxes = gridSide(triangles) * gridSide(triangles);
    return {kGroundVertices + kBoxVertices * boxes, kGroundTriangles + kBoxTriangles * boxes};
}

Status generateCity(const GenerateOptions& options, MeshSink& sink) {
    const uint64_t side = gridSide(options.triangles);
    GeneratedCounts counts = cityCounts(options.triangles);
    VASTRAY_TRY(sink.begin(counts.vertices, counts.triangles));
    VASTRAY_TRY(emitGround(sink));
    for (uint64_t row = 0; row < side; ++row) {
        for (uint64_t column = 0; column < side; ++column) {
            VASTRAY_TRY(emitBoxVertices(boxAt(options.seed, side, row, column), sink));
        }
    }
    // Ground quad wound like the roofs: normal +y.
    VASTRAY_TRY(sink.face(0, 3, 1));
    VASTRAY_TRY(sink.face(1, 3, 2));
    for (uint64_t box = 0; box < side * side; ++box) {
        VASTRAY_TRY(emitBoxFaces(static_cast<uint32_t>(kGroundVertices + kBoxVertices * box), sink));
    }
    return sink.end();
}

}  // namespace vastray::gen

#pragma once
// Test sinks: one keeps the whole stream (small meshes only), one only counts.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "vastray/streamer/Generate.h"

namespace vastray::test {

struct RecordingSink : MeshSink {
    uint64_t announcedVertices = 0, announcedFaces = 0;
    std::vector<Vec3f> vertices;
    std::vector<std::array<uint32_t, 3>> faces;
    int beginCalls = 0, endCalls = 0;
    bool faceBeforeLastVertex = false;

    Status begin(uint64_t vertexCount, uint64_t faceCount) override {
        ++beginCalls;
        announcedVertices = vertexCount;
        announcedFaces = faceCount;
        return Status::ok();
    }
    Status vertex(Vec3f p) override {
        if (!faces.empty()) faceBeforeLastVertex = true;
        vertices.push_back(p);
        return Status::ok();
    }
    Status face(uint32_t a, uint32_t b, uint32_t c) override {
        faces.push_back({a, b, c});
        return Status::ok();
    }
    Status end() override {
        ++endCalls;
        return Status::ok();
    }
};

struct CountingSink : MeshSink {
    uint64_t announcedVertices = 0, announcedFaces = 0, vertices = 0, faces = 0, maxIndex = 0;
    Status begin(uint64_t v, uint64_t f) override {
        announcedVertices = v;
        announcedFaces = f;
        return Status::ok();
    }
    Status vertex(Vec3f) override {
        ++vertices;
        return Status::ok();
    }
    Status face(uint32_t a, uint32_t b, uint32_t c) override {
        ++faces;
        maxIndex = std::max<uint64_t>({maxIndex, a, b, c});
        return Status::ok();
    }
    Status end() override { return Status::ok(); }
};

struct DVec {
    double x, y, z;
};
inline DVec toDouble(Vec3f p) { return {p.x, p.y, p.z}; }
inline DVec sub(DVec a, DVec b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline DVec cross(DVec a, DVec b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double dot(DVec a, DVec b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

// Unnormalized normal (twice the area) of a face, in double from the float positions.
inline DVec faceNormal(const RecordingSink& mesh, const std::array<uint32_t, 3>& f) {
    DVec a = toDouble(mesh.vertices[f[0]]), b = toDouble(mesh.vertices[f[1]]),
         c = toDouble(mesh.vertices[f[2]]);
    return cross(sub(b, a), sub(c, a));
}
inline DVec faceCentroid(const RecordingSink& mesh, const std::array<uint32_t, 3>& f) {
    DVec a = toDouble(mesh.vertices[f[0]]), b = toDouble(mesh.vertices[f[1]]),
         c = toDouble(mesh.vertices[f[2]]);
    return {(a.x + b.x + c.x) / 3, (a.y + b.y + c.y) / 3, (a.z + b.z + c.z) / 3};
}

inline RecordingSink record(GeneratorKind kind, uint64_t triangles, uint64_t seed = 1) {
    RecordingSink sink;
    Status status = generate({kind, triangles, seed}, sink);
    if (!status) ADD_FAILURE() << status.message();
    return sink;
}

}  // namespace vastray::test

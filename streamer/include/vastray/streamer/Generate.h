#pragma once
// Procedural scenes for tests and benchmarks, deterministic per seed, produced as a stream
// (vertices first, then faces) so that 100M triangles never sit in memory at once.
#include <cstdint>
#include <string>
#include <string_view>

#include "vastray/core/Mesh.h"
#include "vastray/core/Result.h"
#include "vastray/core/Vec3.h"

namespace vastray {

// Receives a generated mesh in order: begin(), every vertex, every face, end().
// Counts given to begin() are exact.
class MeshSink {
public:
    virtual ~MeshSink() = default;
    virtual Status begin(uint64_t vertexCount, uint64_t faceCount) = 0;
    virtual Status vertex(Vec3f position) = 0;
    virtual Status face(uint32_t a, uint32_t b, uint32_t c) = 0;
    virtual Status end() = 0;
};

enum class GeneratorKind { Sphere, Terrain, Soup, City };

struct GenerateOptions {
    GeneratorKind kind = GeneratorKind::Sphere;
    uint64_t triangles = 20000;  // target; the actual count is as close as the shape allows
    uint64_t seed = 1;
};

Result<GeneratorKind> parseGeneratorKind(std::string_view name);
const char* generatorKindName(GeneratorKind kind);

// Exact counts the generator will emit for these options (no generation work).
struct GeneratedCounts {
    uint64_t vertices = 0;
    uint64_t triangles = 0;
};
Result<GeneratedCounts> generatedCounts(const GenerateOptions& options);

Status generate(const GenerateOptions& options, MeshSink& sink);

// The generated scene as an in-core mesh with one default material (tests, benchmarks: it
// holds every triangle in memory, unlike generateToPly). With `alsoPly`, the same pass writes it
// to that PLY file too, as generateToPly does.
Result<TriangleMesh> generateMesh(const GenerateOptions& options, const std::string& alsoPly = {});

// Writes a binary little-endian PLY (vertex x,y,z float; face vertex_indices uchar/uint),
// streaming, to a temporary name renamed on success. With `also`, every vertex and face goes
// to that sink too, in the same order.
Status generateToPly(const GenerateOptions& options, const std::string& path, MeshSink* also = nullptr);

}  // namespace vastray

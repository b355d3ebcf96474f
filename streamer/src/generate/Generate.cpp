// Public entry points: kind names, option validation and dispatch to the per-kind generators.
#include <array>
#include <limits>

#include "generate/Generators.h"

namespace vastray {
namespace {

struct KindInfo {
    GeneratorKind kind;
    const char* name;
    uint64_t minTriangles;
    const char* whyMinimum;
    GeneratedCounts (*counts)(uint64_t triangles);
    Status (*generate)(const GenerateOptions& options, MeshSink& sink);
};

constexpr std::array<KindInfo, 4> kKinds = {{
    {GeneratorKind::Sphere, "sphere", 20, "one per icosahedron face", gen::sphereCounts, gen::generateSphere},
    {GeneratorKind::Terrain, "terrain", 2, "one grid cell", gen::terrainCounts, gen::generateTerrain},
    {GeneratorKind::Soup, "soup", 1, "one triangle", gen::soupCounts, gen::generateSoup},
    {GeneratorKind::City, "city", 12, "a ground quad and one box", gen::cityCounts, gen::generateCity},
}};

// Above this the index type is not the only problem: nobody should stream such a file by accident.
constexpr uint64_t kMaxTriangles = 4'000'000'000ull;
constexpr uint64_t kMaxVertices = std::numeric_limits<uint32_t>::max();  // PLY indices are uint32

const KindInfo& infoOf(GeneratorKind kind) {
    for (const KindInfo& info : kKinds) {
        if (info.kind == kind) return info;
    }
    return kKinds[0];  // unreachable for a valid enum value
}

Status validate(const GenerateOptions& options) {
    const KindInfo& info = infoOf(options.kind);
    const std::string kind = info.name, asked = std::to_string(options.triangles);
    if (options.triangles < info.minTriangles) {
        return Status::error(kind + " needs at least " + std::to_string(info.minTriangles) + " triangles (" +
                             info.whyMinimum + "), got " + asked);
    }
    if (options.triangles > kMaxTriangles) {
        return Status::error(kind + ": at most " + std::to_string(kMaxTriangles) + " triangles, got " +
                             asked);
    }
    GeneratedCounts counts = info.counts(options.triangles);
    if (counts.vertices > kMaxVertices) {
        return Status::error(kind + ": " + asked + " triangles need " + std::to_string(counts.vertices) +
                             " vertices, more than the " + std::to_string(kMaxVertices) +
                             " a uint32 vertex index can address");
    }
    return Status::ok();
}

}  // namespace

Result<GeneratorKind> parseGeneratorKind(std::string_view name) {
    std::string valid;
    for (const KindInfo& info : kKinds) {
        if (name == info.name) return info.kind;
        valid += valid.empty() ? info.name : std::string(", ") + info.name;
    }
    return Status::error("unknown generator kind '" + std::string(name) + "' (valid kinds: " + valid + ")");
}

const char* generatorKindName(GeneratorKind kind) { return infoOf(kind).name; }

Result<GeneratedCounts> generatedCounts(const GenerateOptions& options) {
    if (Status status = validate(options); !status) return status;
    return infoOf(options.kind).counts(options.triangles);
}

Status generate(const GenerateOptions& options, MeshSink& sink) {
    VASTRAY_TRY(validate(options));
    return infoOf(options.kind).generate(options, sink);
}

namespace {

class MeshCollector final : public MeshSink {
public:
    TriangleMesh mesh;
    Status begin(uint64_t vertices, uint64_t faces) override {
        mesh.positions.reserve(vertices);
        mesh.indices.reserve(3 * faces);
        return Status::ok();
    }
    Status vertex(Vec3f p) override {
        mesh.positions.push_back(p);
        return Status::ok();
    }
    Status face(uint32_t a, uint32_t b, uint32_t c) override {
        mesh.indices.insert(mesh.indices.end(), {a, b, c});
        return Status::ok();
    }
    Status end() override {
        mesh.materials.push_back(Material{"default"});
        return Status::ok();
    }
};

}  // namespace

Result<TriangleMesh> generateMesh(const GenerateOptions& options, const std::string& alsoPly) {
    MeshCollector collector;
    if (alsoPly.empty())
        VASTRAY_TRY(generate(options, collector));
    else
        VASTRAY_TRY(generateToPly(options, alsoPly, &collector));
    return std::move(collector.mesh);
}

}  // namespace vastray

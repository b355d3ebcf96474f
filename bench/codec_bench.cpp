// Chunk geometry codecs compared on one core, both through the package's own chunk codec
// (streamer/src/package/ChunkCodec.*): Draco edgebreaker at several encoder speeds against
// meshoptimizer's index and vertex codecs (`import --codec meshopt`), at several quantization bits.
//
// Each mesh is snapped to the package's scene-wide grid (QuantizationGrid::forBounds), the
// triangles that snapping collapses are dropped (the package's rule), and the rest is cut
// into chunk-sized pieces by recursive median splits of triangle centroids. Each piece is a
// ChunkGeometry (grid words, local vertices in first-use order), encoded on its own.
// Figures: bytes (codec prefixes included), bits per triangle, encode and decode M tri/s
// (medians over runs). Decoding ends where the package's ends: grid words plus indices, not
// yet dequantized floats. Every decoded piece is checked to hold exactly its input triangles
// (any corner rotation and face order allowed, winding kept); a mismatch aborts the run.
//
//   codec_bench OUT.md [--bunny PATH] [--triangles N] [--chunk-triangles N]
//                      [--encode-runs N] [--decode-runs N]
#include <meshoptimizer.h>  // MESHOPTIMIZER_VERSION for the report

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "../streamer/src/package/ByteIo.h"
#include "../streamer/src/package/ChunkCodec.h"
#include "BenchFlags.h"
#include "vastray/streamer/Generate.h"
#include "vastray/streamer/Import.h"
#include "vastray/streamer/PackageBuilder.h"
#include "vastray/streamer/ScenePackage.h"

namespace vastray {
namespace {

struct BenchOptions {
    std::string outPath;              // the Markdown table is written here (and to stdout)
    std::string bunnyPath;            // empty or missing: the bunny is skipped with a note
    uint64_t triangles = 1000000;     // sphere, terrain and city; soup gets a quarter
    uint32_t chunkTriangles = 65536;  // largest piece encoded on its own
    int encodeRuns = 3;
    int decodeRuns = 7;
};

const std::vector<uint32_t> kBits = {14, 16, 20};
const std::vector<int> kDracoSpeeds = {0, 5, 7, 10};
constexpr int kMeshopt = -1;       // CodecSetting::speed of meshoptimizer's codec
const int kDefaultSpeed = PackageBuildOptions{}.dracoSpeed;  // the package's, the reference of the ratios

struct CodecSetting {
    int speed;  // Draco encoder speed 0..10, or kMeshopt
    uint32_t bits;
};

struct BenchMesh {
    std::string name;
    std::vector<Vec3f> positions;
    std::vector<uint32_t> indices;
};

struct Row {
    std::string mesh;
    CodecSetting setting;
    uint64_t triangles = 0, chunks = 0, bytes = 0;
    double encodeSeconds = 0, decodeSeconds = 0;  // medians, all chunks of the mesh
};

// ---- input meshes -------------------------------------------------------------------------

Result<BenchMesh> generatedMesh(GeneratorKind kind, uint64_t triangles) {
    auto generated = generateMesh(GenerateOptions{kind, triangles, 1});
    if (!generated) return generated.status();
    BenchMesh mesh;
    mesh.name = generatorKindName(kind);
    mesh.positions = std::move(generated->positions);
    mesh.indices = std::move(generated->indices);
    return mesh;
}

Result<BenchMesh> importedMesh(const std::string& path) {
    auto imported = importMesh(path);
    if (!imported) return imported.status();
    BenchMesh mesh;
    mesh.name = std::filesystem::path(path).stem().string();
    mesh.positions = std::move(imported->mesh.positions);
    mesh.indices = std::move(imported->mesh.indices);
    return mesh;
}

// ---- quantization and chunking (what the package does before its codec) ------------------

// The package's collapse rule (PackageBuilder.cpp): coincident corners or zero area in double.
bool isCollapsed(Vec3f a, Vec3f b, Vec3f c) {
    if (a == b || b == c || a == c) return true;
    const double ux = double(b.x) - a.x, uy = double(b.y) - a.y, uz = double(b.z) - a.z;
    const double vx = double(c.x) - a.x, vy = double(c.y) - a.y, vz = double(c.z) - a.z;
    return uy * vz - uz * vy == 0 && uz * vx - ux * vz == 0 && ux * vy - uy * vx == 0;
}

struct QuantizedMesh {
    std::vector<int32_t> words;       // 3 grid coordinates per vertex
    std::vector<uint32_t> triangles;  // ids of the triangles that survive snapping
};

QuantizedMesh quantize(const BenchMesh& mesh, uint32_t bits) {
    Aabb bounds;
    for (const Vec3f& p : mesh.positions) bounds.extend(p);
    const QuantizationGrid grid = QuantizationGrid::forBounds(bounds, bits);
    QuantizedMesh q;
    q.words.resize(mesh.positions.size() * 3);
    std::vector<Vec3f> snapped(mesh.positions.size());
    for (size_t v = 0; v < mesh.positions.size(); ++v) {
        for (int axis = 0; axis < 3; ++axis) q.words[3 * v + axis] = grid.quantize(mesh.positions[v][axis], axis);
        snapped[v] = grid.position(&q.words[3 * v]);
    }
    for (size_t t = 0; t < mesh.indices.size() / 3; ++t) {
        const uint32_t* i = &mesh.indices[3 * t];
        if (!isCollapsed(snapped[i[0]], snapped[i[1]], snapped[i[2]])) q.triangles.push_back(uint32_t(t));
    }
    return q;
}

// Splits `ids` into ranges of at most `limit` triangles: median of centroids on the axis of
// largest centroid extent, recursively (spatially coherent pieces, like the package's cells).
std::vector<std::pair<size_t, size_t>> medianSplit(std::vector<uint32_t>& ids, const std::vector<std::array<int64_t, 3>>& centroid,
                                                   uint32_t limit) {
    std::vector<std::pair<size_t, size_t>> leaves, stack{{0, ids.size()}};
    while (!stack.empty()) {
        const auto [begin, end] = stack.back();
        stack.pop_back();
        if (end - begin <= limit) {
            leaves.push_back({begin, end});
            continue;
        }
        std::array<int64_t, 3> lo = centroid[ids[begin]], hi = lo;
        for (size_t k = begin; k < end; ++k)
            for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], centroid[ids[k]][a]), hi[a] = std::max(hi[a], centroid[ids[k]][a]);
        int axis = 0;
        for (int a = 1; a < 3; ++a)
            if (hi[a] - lo[a] > hi[axis] - lo[axis]) axis = a;
        const size_t mid = begin + (end - begin) / 2;
        std::nth_element(ids.begin() + begin, ids.begin() + mid, ids.begin() + end,
                         [&](uint32_t x, uint32_t y) { return centroid[x][axis] < centroid[y][axis]; });
        stack.push_back({mid, end});
        stack.push_back({begin, mid});
    }
    return leaves;
}

// One piece with its own vertex table in first-use order (as ChunkBuilder gathers a cell).
ChunkGeometry gatherPiece(const BenchMesh& mesh, const QuantizedMesh& q, const uint32_t* ids, size_t count,
                          std::vector<uint32_t>& localOf) {
    ChunkGeometry piece;
    piece.indices.reserve(count * 3);
    std::vector<uint32_t> touched;
    for (size_t k = 0; k < count; ++k)
        for (int c = 0; c < 3; ++c) {
            const uint32_t global = mesh.indices[3 * size_t(ids[k]) + c];
            if (localOf[global] == UINT32_MAX) {
                localOf[global] = uint32_t(touched.size());
                touched.push_back(global);
                piece.vertexWords.insert(piece.vertexWords.end(), &q.words[3 * size_t(global)], &q.words[3 * size_t(global)] + 3);
            }
            piece.indices.push_back(localOf[global]);
        }
    for (uint32_t global : touched) localOf[global] = UINT32_MAX;
    return piece;
}

std::vector<ChunkGeometry> makeChunks(const BenchMesh& mesh, uint32_t bits, uint32_t chunkTriangles) {
    QuantizedMesh q = quantize(mesh, bits);
    std::vector<std::array<int64_t, 3>> centroid(mesh.indices.size() / 3);
    for (uint32_t t : q.triangles)
        for (int a = 0; a < 3; ++a)
            for (int c = 0; c < 3; ++c) centroid[t][a] += q.words[3 * size_t(mesh.indices[3 * size_t(t) + c]) + a];
    std::vector<uint32_t> localOf(mesh.positions.size(), UINT32_MAX);
    std::vector<ChunkGeometry> chunks;
    for (const auto& [begin, end] : medianSplit(q.triangles, centroid, chunkTriangles))
        chunks.push_back(gatherPiece(mesh, q, q.triangles.data() + begin, end - begin, localOf));
    return chunks;
}

// ---- measurement --------------------------------------------------------------------------

GeometryCodec codecOf(const CodecSetting& setting) {
    return setting.speed == kMeshopt ? GeometryCodec::Meshopt : GeometryCodec::Draco;
}

Result<std::vector<uint8_t>> encodeWith(const CodecSetting& setting, const ChunkGeometry& geometry) {
    return encodeChunkGeometry(geometry, false, codecOf(setting), setting.speed);
}

Result<ChunkGeometry> decodeWith(const CodecSetting& setting, const std::vector<uint8_t>& data) {
    return decodeChunkGeometry(data.data(), data.size(), false, codecOf(setting));
}

// Triangles as corner words, each rotated so its smallest corner comes first, sorted.
std::vector<std::array<int32_t, 9>> canonicalTriangles(const ChunkGeometry& g) {
    std::vector<std::array<int32_t, 9>> triangles(g.indices.size() / 3);
    for (size_t t = 0; t < triangles.size(); ++t) {
        std::array<std::array<int32_t, 3>, 3> c;
        for (int k = 0; k < 3; ++k) std::memcpy(c[k].data(), &g.vertexWords[3 * size_t(g.indices[3 * t + k])], 12);
        const int first = int(std::min_element(c.begin(), c.end()) - c.begin());
        for (int k = 0; k < 3; ++k) std::memcpy(&triangles[t][3 * k], c[(first + k) % 3].data(), 12);
    }
    std::sort(triangles.begin(), triangles.end());
    return triangles;
}

Status checkRoundTrip(const ChunkGeometry& input, const ChunkGeometry& decoded) {
    for (uint32_t i : decoded.indices)
        if (size_t(i) * 3 >= decoded.vertexWords.size()) return Status::error("decoded index out of range");
    const auto before = canonicalTriangles(input), after = canonicalTriangles(decoded);
    if (before.size() != after.size())
        return Status::error(std::to_string(after.size()) + " triangles decoded for " + std::to_string(before.size()));
    const auto differ = std::mismatch(before.begin(), before.end(), after.begin());
    if (differ.first != before.end())
        return Status::error("decoded triangles differ from the input (sorted position " +
                             std::to_string(differ.first - before.begin()) + ")");
    return Status::ok();
}

// A codec error or a failed round trip ends the run: figures for a codec that loses or
// changes triangles would mean nothing.
[[noreturn]] void fail(const std::string& where, const Status& status) {
    std::cerr << "codec_bench: FAILED: " << where << ": " << status.message() << "\n";
    std::exit(1);
}

std::string settingName(const CodecSetting& s) {
    return s.speed == kMeshopt ? "meshopt" : "Draco speed " + std::to_string(s.speed);
}

template <typename Work>  // one pass over every chunk
double medianSeconds(int runs, Work&& work) {
    std::vector<double> seconds;
    for (int r = 0; r < runs; ++r) {
        const auto start = std::chrono::steady_clock::now();
        work();
        seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
    std::sort(seconds.begin(), seconds.end());
    return seconds[seconds.size() / 2];
}

Row measure(const std::string& meshName, const std::vector<ChunkGeometry>& chunks, const CodecSetting& setting,
            const BenchOptions& options) {
    Row row{meshName, setting};
    row.chunks = chunks.size();
    for (const ChunkGeometry& c : chunks) row.triangles += c.indices.size() / 3;
    const std::string where = meshName + ", " + settingName(setting) + ", " + std::to_string(setting.bits) + " bits, chunk ";
    std::vector<std::vector<uint8_t>> encoded(chunks.size());
    row.encodeSeconds = medianSeconds(options.encodeRuns, [&] {
        for (size_t c = 0; c < chunks.size(); ++c) {
            auto bytes = encodeWith(setting, chunks[c]);
            if (!bytes) fail(where + std::to_string(c), bytes.status());
            encoded[c] = std::move(bytes).value();
        }
    });
    for (size_t c = 0; c < chunks.size(); ++c) {
        row.bytes += encoded[c].size();
        auto decoded = decodeWith(setting, encoded[c]);
        if (!decoded) fail(where + std::to_string(c), decoded.status());
        if (Status check = checkRoundTrip(chunks[c], *decoded); !check) fail(where + std::to_string(c), check);
    }
    size_t decodedIndices = 0;  // keeps the decoded output observable
    row.decodeSeconds = medianSeconds(options.decodeRuns, [&] {
        for (size_t c = 0; c < chunks.size(); ++c) {
            auto decoded = decodeWith(setting, encoded[c]);
            if (!decoded) fail(where + std::to_string(c), decoded.status());
            decodedIndices += decoded->indices.size();
        }
    });
    if (decodedIndices != row.triangles * 3 * size_t(options.decodeRuns)) fail(where, Status::error("decoded count drifted"));
    return row;
}

void benchMesh(const BenchMesh& mesh, const BenchOptions& options, std::vector<Row>& rows) {
    for (uint32_t bits : kBits) {
        const std::vector<ChunkGeometry> chunks = makeChunks(mesh, bits, options.chunkTriangles);
        std::vector<CodecSetting> settings;
        for (int speed : kDracoSpeeds) settings.push_back({speed, bits});
        settings.push_back({kMeshopt, bits});
        for (const CodecSetting& setting : settings) {
            rows.push_back(measure(mesh.name, chunks, setting, options));
            std::cerr << mesh.name << " " << bits << " bits " << settingName(setting) << ": "
                      << double(rows.back().bytes) * 8 / double(rows.back().triangles) << " bits/tri\n";
        }
    }
}

// ---- report -------------------------------------------------------------------------------

std::string fixed(double value, int digits) {
    char text[32];
    std::snprintf(text, sizeof text, "%.*f", digits, value);
    return text;
}

std::string grouped(uint64_t value) {
    std::string digits = std::to_string(value), out;
    for (size_t i = 0; i < digits.size(); ++i) {
        if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
        out += digits[i];
    }
    return out;
}

// Pools rows (one mesh, or all meshes) of one setting: bytes and seconds add up.
struct Pooled {
    uint64_t meshes = 0, triangles = 0, bytes = 0;
    double encodeSeconds = 0, decodeSeconds = 0;
    double bitsPerTriangle() const { return double(bytes) * 8 / double(triangles); }
    double encodeRate() const { return double(triangles) / encodeSeconds * 1e-6; }
    double decodeRate() const { return double(triangles) / decodeSeconds * 1e-6; }
};

Pooled pool(const std::vector<Row>& rows, const std::string& mesh, int speed, uint32_t bits) {
    Pooled p;
    for (const Row& r : rows)
        if ((mesh.empty() || r.mesh == mesh) && r.setting.speed == speed && r.setting.bits == bits) {
            ++p.meshes, p.triangles += r.triangles, p.bytes += r.bytes;
            p.encodeSeconds += r.encodeSeconds, p.decodeSeconds += r.decodeSeconds;
        }
    return p;
}

// One table line: the figures of `p` and their ratios to Draco at the package's speed.
std::string figures(const Pooled& p, const Pooled& draco) {
    return grouped(p.bytes) + " | " + fixed(p.bitsPerTriangle(), 2) + " | " + fixed(double(p.bytes) / double(draco.bytes), 2) +
           "× | " + fixed(p.encodeRate(), 2) + " | " + fixed(p.decodeRate(), 1) + " | " +
           fixed(p.decodeRate() / draco.decodeRate(), 1) + "× |";
}

std::string report(const std::vector<Row>& rows, const std::vector<std::string>& notes, const BenchOptions& o) {
    std::ostringstream out;
    out << "Chunk codec comparison on one thread: size and codec throughput only. **Render time end to end is not\n"
           "yet included** (the renderer is being rewritten).\n\n"
        << "Meshes are snapped to the package's scene-wide grid at the given bits (triangles that collapse are\n"
           "dropped, as the package does; *triangles* counts what is encoded) and cut into spatial pieces of at\n"
           "most " << grouped(o.chunkTriangles) << " triangles (recursive median splits), each encoded on its own. *Draco*: the package's\n"
           "ChunkCodec (edgebreaker on chunk-relative integer grid coordinates, bits above 18 in a second\n"
           "attribute) at the given encoder speed; the package uses speed " << kDefaultSpeed << ".\n*meshopt*: meshoptimizer "
        << MESHOPTIMIZER_VERSION / 1000 << "." << MESHOPTIMIZER_VERSION % 1000 / 10
        << ", optimizeVertexCache + optimizeVertexFetch, encodeIndexBuffer (v1) +\n"
           "encodeVertexBuffer on chunk-relative grid coordinates (4 × uint16 when they fit 16 bits, else\n"
           "3 × uint32), no general-purpose compressor after it. Bytes include each codec's\n"
           "per-chunk prefix. Encode and decode: median of " << o.encodeRuns << " and " << o.decodeRuns
        << " passes over all pieces; decoding ends at grid\n"
           "integers and indices (as ChunkCodec's decode does), before dequantization. Ratios (×) are against\n"
           "Draco speed " << kDefaultSpeed << " at the same bits. Every decoded piece was checked to hold exactly its input triangles.\n";
    for (const std::string& note : notes) out << "\n" << note << "\n";
    out << "\n### All meshes pooled (sum of bytes and of seconds)\n\n"
        << "| codec | bits | bytes | bits/tri | size vs Draco " << kDefaultSpeed << " | encode M tri/s | decode M tri/s | decode vs Draco "
        << kDefaultSpeed << " |\n|---|---|---|---|---|---|---|---|\n";
    std::vector<int> speeds = kDracoSpeeds;
    speeds.push_back(kMeshopt);
    for (uint32_t bits : kBits)
        for (int speed : speeds)
            out << "| " << settingName({speed, bits}) << " | " << bits << " | "
                << figures(pool(rows, "", speed, bits), pool(rows, "", kDefaultSpeed, bits)) << "\n";
    out << "\n### Per mesh\n\n| mesh | triangles | chunks | codec | bits | bytes | bits/tri | size vs Draco " << kDefaultSpeed
        << " | encode M tri/s | decode M tri/s | decode vs Draco " << kDefaultSpeed << " |\n|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const Row& r : rows)
        out << "| " << r.mesh << " | " << grouped(r.triangles) << " | " << r.chunks << " | " << settingName(r.setting) << " | "
            << r.setting.bits << " | "
            << figures(pool(rows, r.mesh, r.setting.speed, r.setting.bits), pool(rows, r.mesh, kDefaultSpeed, r.setting.bits))
            << "\n";
    return out.str();
}

// ---- command line -------------------------------------------------------------------------

Result<BenchOptions> parseArgs(int argc, char** argv) {
    BenchOptions o;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        if (arg.rfind("--", 0) != 0) {
            if (!o.outPath.empty()) return Status::error("more than one output path: " + o.outPath + ", " + arg);
            o.outPath = arg;
            continue;
        }
        if (i + 1 >= argc) return Status::error(arg + " needs a value");
        const std::string value = argv[++i];
        if (arg == "--bunny") {
            o.bunnyPath = value;
            continue;
        }
        const bool runs = arg == "--encode-runs" || arg == "--decode-runs";
        const uint64_t most = runs ? 101 : (arg == "--triangles" ? 1ull << 31 : 1ull << 24);
        auto n = bench::parseFlagNumber<uint64_t>(arg, value, 1, most);
        if (!n) return n.status();
        if (arg == "--triangles") o.triangles = *n;
        else if (arg == "--chunk-triangles") o.chunkTriangles = uint32_t(*n);
        else if (arg == "--encode-runs") o.encodeRuns = int(*n);
        else if (arg == "--decode-runs") o.decodeRuns = int(*n);
        else return Status::error("unknown option " + arg);
    }
    if (o.outPath.empty())
        return Status::error("usage: codec_bench OUT.md [--bunny PATH] [--triangles N] [--chunk-triangles N] "
                             "[--encode-runs N] [--decode-runs N]");
    return o;
}

void runMesh(Result<BenchMesh> mesh, const BenchOptions& options, std::vector<Row>& rows) {
    if (!mesh) fail("loading a mesh", mesh.status());
    std::cerr << mesh->name << ": " << mesh->indices.size() / 3 << " triangles\n";
    benchMesh(*mesh, options, rows);
}

}  // namespace
}  // namespace vastray

int main(int argc, char** argv) {
    using namespace vastray;
    auto options = parseArgs(argc, argv);
    if (!options) {
        std::cerr << "codec_bench: " << options.message() << "\n";
        return 2;
    }
    std::vector<Row> rows;
    std::vector<std::string> notes;
    for (GeneratorKind kind : {GeneratorKind::Sphere, GeneratorKind::Terrain, GeneratorKind::City})
        runMesh(generatedMesh(kind, options->triangles), *options, rows);
    runMesh(generatedMesh(GeneratorKind::Soup, options->triangles / 4), *options, rows);
    if (options->bunnyPath.empty()) {
        notes.push_back("Stanford bunny skipped: no --bunny path given.");
    } else if (!std::filesystem::exists(options->bunnyPath)) {
        notes.push_back("Stanford bunny skipped: " + options->bunnyPath + " not found.");
    } else {
        runMesh(importedMesh(options->bunnyPath), *options, rows);
    }
    for (const std::string& note : notes) std::cerr << note << "\n";
    const std::string table = report(rows, notes, *options);
    std::cout << table;
    std::ofstream file(options->outPath);
    file << table;
    if (!file) {
        std::cerr << "codec_bench: cannot write " << options->outPath << "\n";
        return 1;
    }
    return 0;
}

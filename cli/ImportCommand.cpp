#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "Commands.h"
#include "OutputPath.h"
#include "vastray/core/ByteSize.h"
#include "vastray/streamer/Import.h"
#include "vastray/streamer/PackageBuilder.h"

namespace vastray::cli {
namespace {

// The same bound as render's --threads: more workers than this only cost memory.
constexpr uint32_t kMaxThreads = 4096;

struct ImportArgs {
    std::string input, output, chunkSize = "16MiB";
    uint32_t quantizeBits = 20;
    uint32_t threads = 0;
    int dracoSpeed = 7;
    double residentBytesPerTriangle = PackageBuildOptions{}.residentBytesPerTriangle;
    std::string codec = "draco";
    bool doubleSided = false, singleSided = false;
    std::string progress = "auto";
};

Result<PackageBuildOptions> buildOptions(const ImportArgs& args) {
    PackageBuildOptions options;
    auto chunkSize = parseByteSize(args.chunkSize);
    if (!chunkSize) return Status::error("--chunk-size: " + chunkSize.message());
    options.chunkSizeBytes = *chunkSize;
    if (options.chunkSizeBytes < kMinChunkSizeBytes)
        return Status::error("--chunk-size " + args.chunkSize + " is below the minimum of " +
                             formatBytes(kMinChunkSizeBytes));
    if (args.quantizeBits > kMaxQuantizeBits)
        return Status::error("--quantize-bits must be 0 (lossless) or 1.." + std::to_string(kMaxQuantizeBits));
    options.quantizeBits = args.quantizeBits;
    if (args.threads > kMaxThreads)
        return Status::error("--threads " + std::to_string(args.threads) + " is outside [0, " +
                             std::to_string(kMaxThreads) + "] (0 = all cores)");
    options.threads = args.threads;
    if (args.dracoSpeed < 0 || args.dracoSpeed > 10) return Status::error("--draco-speed must be 0..10");
    options.dracoSpeed = args.dracoSpeed;
    if (!(args.residentBytesPerTriangle >= 0))
        return Status::error("--resident-bytes-per-triangle must be 0 (no cap) or positive");
    options.residentBytesPerTriangle = args.residentBytesPerTriangle;
    auto codec = parseGeometryCodec(args.codec);
    if (!codec) return Status::error("--codec: " + codec.message());
    options.codec = *codec;
    options.progress = args.progress == "bar"     ? Progress::Mode::Bar
                       : args.progress == "lines" ? Progress::Mode::Lines
                       : args.progress == "none"  ? Progress::Mode::None
                                                  : Progress::Mode::Auto;
    if (std::filesystem::path(args.output).extension() != ".vast")
        return Status::error("output '" + args.output + "' must end in .vast");
    std::error_code error;
    if (std::filesystem::equivalent(args.input, args.output, error))
        return Status::error("output would overwrite the input");
    VASTRAY_TRY(checkWritableOutput("--output", args.output));
    return options;
}

void printImportReport(const std::string& input, const ImportReport& report, const TriangleMesh& mesh, double seconds) {
    std::printf("read %s (%s): %llu triangles, %llu vertices, %zu materials in %.2f s", input.c_str(),
                report.format.c_str(), (unsigned long long)mesh.triangleCount(),
                (unsigned long long)mesh.positions.size(), mesh.materials.size(), seconds);
    if (report.degenerateDropped)
        std::printf("; dropped %llu degenerate triangles", (unsigned long long)report.degenerateDropped);
    std::printf("\n");
}

void printBuildReport(const std::string& output, const PackageBuildReport& r, const PackageBuildOptions& options) {
    std::printf("wrote %s: %llu triangles in %u chunks (%u empty cells), %llu duplicated references, %s file\n",
                output.c_str(), (unsigned long long)r.triangles, r.chunks, r.emptyCells,
                (unsigned long long)(r.references - r.triangles), formatBytes(r.fileBytes).c_str());
    std::printf("  largest chunk resident: %s of %s; quantization: %s", formatBytes(r.maxChunkResidentBytes).c_str(),
                formatBytes(options.chunkSizeBytes).c_str(),
                options.quantizeBits ? (std::to_string(options.quantizeBits) + " bits").c_str() : "lossless");
    if (r.collapsedDropped)
        std::printf(", %llu triangles collapsed and dropped", (unsigned long long)r.collapsedDropped);
    std::printf("\n  %.2f s total (%.1f M triangles/s): quantize %.2f s; summed over threads: partition %.2f s, "
                "%s encode %.2f s, decode %.2f s, BVHs %.2f s; write %.2f s\n",
                r.totalSeconds, double(r.triangles) / r.totalSeconds * 1e-6, r.quantizeSeconds, r.partitionSeconds,
                options.codec == GeometryCodec::Meshopt ? "meshopt" : "Draco",
                r.encodeSeconds, r.decodeSeconds, r.bvhBuildSeconds, r.writeSeconds);
}

}  // namespace

CommandRun addImportCommand(CLI::App& app) {
    auto args = std::make_shared<ImportArgs>();
    CLI::App* cmd = app.add_subcommand("import", "Import a mesh (.obj, .ply, .gltf, .glb; .stl, .off, .fbx, .dae, .3ds, .3mf, .ac, .ase, .dxf, .lwo, .ms3d, .x, .x3d through assimp) into a scene package (.vast).");
    cmd->add_option("input", args->input, "mesh file")->required()->check(CLI::ExistingFile);
    cmd->add_option("-o,--output", args->output, "scene package to write (.vast)")->required();
    cmd->add_option("--chunk-size", args->chunkSize,
                    "resident size limit of one chunk (B, KiB, MiB, GiB; minimum 16KiB)")
        ->capture_default_str();
    cmd->add_option("--quantize-bits", args->quantizeBits,
                    "position precision over the scene's extent, 1..30 bits; 0 = lossless")
        ->capture_default_str();
    auto* ds = cmd->add_flag("--double-sided", args->doubleSided, "make every material double-sided");
    auto* ss = cmd->add_flag("--single-sided", args->singleSided, "make every material single-sided");
    ds->excludes(ss);
    cmd->add_option("--codec", args->codec,
                    "chunk geometry codec: draco (smallest package) | meshopt (geometry 2-6x larger, package 6-19% larger; decodes 10-30x faster)")
        ->check(CLI::IsMember({"draco", "meshopt"}))
        ->capture_default_str();
    cmd->add_option("--draco-speed", args->dracoSpeed,
                    "Draco trade-off: 0 = smallest package, slowest import; 10 = fastest import, largest")
        ->capture_default_str();
    cmd->add_option("--resident-bytes-per-triangle", args->residentBytesPerTriangle,
                    "cap each chunk's device bytes per triangle (BVH nodes, positions, indices) by building "
                    "its BVH with larger leaves (up to 16 triangles; a chunk that does not fit with those "
                    "keeps them): less memory, more triangle tests per ray, same hits; 0 = no cap")
        ->capture_default_str();
    cmd->add_option("--threads", args->threads, "worker threads, 0..4096 (0 = all cores)")->capture_default_str();
    cmd->add_option("--progress", args->progress, "auto (bar on a terminal, lines otherwise) | bar | lines | none")
        ->check(CLI::IsMember({"auto", "bar", "lines", "none"}))
        ->capture_default_str();
    return [args]() {
        auto options = buildOptions(*args);
        if (!options) {
            std::fprintf(stderr, "vastray import: %s\n", options.message().c_str());
            return 2;
        }
        ImportOptions importOptions;
        if (args->doubleSided) importOptions.sidedness = ImportOptions::Sidedness::ForceDoubleSided;
        if (args->singleSided) importOptions.sidedness = ImportOptions::Sidedness::ForceSingleSided;
        if (options->progress != Progress::Mode::None) {
            std::error_code error;
            const uint64_t bytes = std::filesystem::file_size(args->input, error);
            std::fprintf(stderr, "reading %s (%s)...\n", args->input.c_str(), formatBytes(error ? 0 : bytes).c_str());
        }
        const auto start = std::chrono::steady_clock::now();
        auto imported = importMesh(args->input, importOptions);
        if (!imported) {
            std::fprintf(stderr, "vastray import: %s\n", imported.message().c_str());
            return 1;
        }
        printImportReport(args->input, imported->report, imported->mesh,
                          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
        for (const std::string& warning : imported->report.warnings)
            std::fprintf(stderr, "vastray import: warning: %s: %s\n", args->input.c_str(), warning.c_str());
        options->degenerateDropped = imported->report.degenerateDropped;
        options->defaultDoubleSided = !args->singleSided;
        auto report = buildPackage(std::move(imported->mesh), args->output, *options);
        if (!report) {
            std::fprintf(stderr, "vastray import: %s: %s\n", args->input.c_str(), report.message().c_str());
            return 1;
        }
        printBuildReport(args->output, *report, *options);
        return 0;
    };
}

}  // namespace vastray::cli

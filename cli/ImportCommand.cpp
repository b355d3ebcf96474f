#include <CLI/CLI.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>

#include "Commands.h"
#include "OutputPath.h"
#include "vastray/core/ByteSize.h"
#include "vastray/core/VolumeLeaf.h"
#include "vastray/streamer/Import.h"
#include "vastray/streamer/PackageBuilder.h"
#include "vastray/streamer/VolumeImport.h"

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
    // --volume FILE.vdb[:GRID], and each material option once (every volume) or once per volume.
    std::vector<std::string> volumes, volumeAlbedo, volumeEmission, volumeTemperature, volumeEmissionScale;
    std::vector<float> volumeDensity, volumeAnisotropy;
    std::vector<std::string> volumeCodec;
};

// One value per volume from an option given never (the default), once (every volume) or once
// per --volume, in their order.
template <typename T>
Result<T> perVolume(const std::vector<T>& values, size_t volume, size_t volumes, const char* flag, T fallback) {
    if (values.empty()) return fallback;
    if (values.size() == 1) return values[0];
    if (values.size() != volumes)
        return Status::error(std::string(flag) + " is given " + std::to_string(values.size()) + " times for " +
                             std::to_string(volumes) + " volumes: give it once (every volume) or once per --volume");
    return values[volume];
}

// R,G,B or one value (grey), each in [0, max].
Result<std::array<float, 3>> parseColor(const char* flag, const std::string& text, float max, const char* range) {
    std::array<float, 3> color{};
    const char* at = text.c_str();
    const std::string expected = std::string(flag) + " '" + text + "': expected R,G,B or one value, each in " + range;
    for (int c = 0; c < 3; ++c) {
        char* end = nullptr;
        color[c] = std::strtof(at, &end);
        if (end == at || !(color[c] >= 0.0f && color[c] <= max)) return Status::error(expected);
        at = end;
        if (c == 0 && *at == '\0') return std::array<float, 3>{color[0], color[0], color[0]};
        if (c < 2 && *at++ != ',') return Status::error(expected);
    }
    if (*at != '\0') return Status::error(expected);
    return color;
}

// Every --volume with its material options, as readVolumes (VolumeImport.h) takes them; it
// checks the count and the materials' ranges and reads the files (errors name the option, or
// the file and the grid).
Result<std::vector<VolumeSource>> volumeSources(const ImportArgs& args) {
    std::vector<VolumeSource> sources;
    const size_t count = args.volumes.size();
    if (count > kMaxVolumes)  // before any option is parsed, as readVolumes would say it
        return Status::error(std::to_string(count) + " volumes exceed the limit of " + std::to_string(kMaxVolumes));
    for (size_t i = 0; i < count; ++i) {
        VolumeSource source;
        source.names = {"--volume-albedo", "--volume-density", "--volume-anisotropy", "--volume-emission-scale"};
        // FILE.vdb, or FILE.vdb:GRID (the grid named GRID; without one, the file's first float grid).
        source.path = args.volumes[i];
        auto endsWithVdb = [](const std::string& s) {
            return s.size() >= 4 && (s.compare(s.size() - 4, 4, ".vdb") == 0 || s.compare(s.size() - 4, 4, ".VDB") == 0);
        };
        if (!endsWithVdb(source.path)) {
            const size_t colon = source.path.rfind(':');
            if (colon == std::string::npos || !endsWithVdb(source.path.substr(0, colon)))
                return Status::error("--volume '" + source.path + "': expected FILE.vdb or FILE.vdb:GRID");
            source.grid = source.path.substr(colon + 1);
            source.path.resize(colon);
        }
        VolumeMaterial& material = source.material;
        auto albedo = perVolume(args.volumeAlbedo, i, count, "--volume-albedo", std::string("0.8"));
        if (!albedo) return albedo.status();
        auto parsed = parseColor("--volume-albedo", *albedo, 1.0f, "[0, 1]");
        if (!parsed) return parsed.status();
        material.albedo = *parsed;
        auto emissionScale = perVolume(args.volumeEmissionScale, i, count, "--volume-emission-scale", std::string("1"));
        if (!emissionScale) return emissionScale.status();
        auto emission = parseColor("--volume-emission-scale", *emissionScale, kMaxVolumeDensity, "[0, 1e18]");
        if (!emission) return emission.status();
        material.emission = *emission;
        auto emissionGrid = perVolume(args.volumeEmission, i, count, "--volume-emission", std::string("-"));
        if (!emissionGrid) return emissionGrid.status();
        if (*emissionGrid != "-") source.emissionGrid = *emissionGrid;
        auto temperatureGrid = perVolume(args.volumeTemperature, i, count, "--volume-temperature", std::string("-"));
        if (!temperatureGrid) return temperatureGrid.status();
        if (*temperatureGrid != "-" && !source.emissionGrid.empty())
            return Status::error("--volume '" + args.volumes[i] + "': --volume-emission '" + source.emissionGrid +
                                 "' and --volume-temperature '" + *temperatureGrid +
                                 "' both name its emission; give one of them");
        if (*temperatureGrid != "-") source.emissionGrid = *temperatureGrid, material.temperature = true;
        auto density = perVolume(args.volumeDensity, i, count, "--volume-density", 1.0f);
        if (!density) return density.status();
        material.densityScale = *density;
        auto g = perVolume(args.volumeAnisotropy, i, count, "--volume-anisotropy", 0.0f);
        if (!g) return g.status();
        material.anisotropy = *g;
        auto codec = perVolume(args.volumeCodec, i, count, "--volume-codec", std::string("float"));
        if (!codec) return codec.status();
        const std::optional<VolumeCodec> parsedCodec = parseVolumeCodec(*codec);
        if (!parsedCodec)
            return Status::error("--volume-codec '" + *codec + "' is not a brick codec (expected float, fp16 or fp8)");
        source.codec = *parsedCodec;
        sources.push_back(std::move(source));
    }
    return sources;
}

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
    if (r.textures)
        std::printf("\n  textures: %u (%llu pages of 128 x 128 texels with their mip levels, %s stored; decoded and "
                    "paged during the write)",
                    r.textures, (unsigned long long)r.texturePages, formatBytes(r.textureBytes).c_str());
    if (r.emitters)
        std::printf("\n  emissive triangles: %llu, sampled as lights by next-event estimation",
                    (unsigned long long)r.emitters);
    for (const std::string& warning : r.warnings) std::printf("\n  warning: %s", warning.c_str());
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
                    "position precision over the scene's extent, 1..30 bits (a power-of-two step: one 2^-bits to "
                    "2^(1-bits) of the extent); up to 20 the device keeps a vertex in 8 bytes; 0 = lossless")
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
                    "cap each chunk's device bytes per triangle (BVH nodes; positions: 8 bytes a vertex with --quantize-bits "
                    "of 1..20, else 12; indices: 8 bytes a triangle) by building "
                    "its BVH with larger leaves (up to 16 triangles; a chunk that does not fit with those "
                    "keeps them): less memory, more triangle tests per ray, same hits; 0 = no cap")
        ->capture_default_str();
    cmd->add_option("--threads", args->threads, "worker threads, 0..4096 (0 = all cores)")->capture_default_str();
    cmd->add_option("--volume", args->volumes,
                    "FILE.vdb[:GRID]: add an OpenVDB float grid (GRID, else the file's first float grid) as a "
                    "density volume, placed by the grid's transform; repeatable (at most 64)");
    cmd->add_option("--volume-albedo", args->volumeAlbedo,
                    "R,G,B (or one value) in [0, 1]: the fraction of extinction that scatters (default 0.8); "
                    "once for every volume or once per --volume");
    cmd->add_option("--volume-density", args->volumeDensity,
                    "extinction per unit of grid density per world unit, [0, 1e18] (default 1); once or per --volume");
    cmd->add_option("--volume-anisotropy", args->volumeAnisotropy,
                    "Henyey-Greenstein g in (-1, 1): 0 isotropic, > 0 forward scattering (default 0); once or per --volume");
    cmd->add_option("--volume-emission", args->volumeEmission,
                    "GRID: a float grid of the volume's file (same transform) whose values, times "
                    "--volume-emission-scale, are the radiance the volume's absorbing part emits; '-': none "
                    "(default); once or per --volume");
    cmd->add_option("--volume-temperature", args->volumeTemperature,
                    "GRID: a float grid of the volume's file (same transform) of temperatures in kelvin, [0, 1e5]: "
                    "the volume's absorbing part glows as a blackbody (linear sRGB, luminance 1 at 6500 K), times "
                    "--volume-emission-scale; not with --volume-emission for the same volume; '-': none (default); "
                    "once or per --volume");
    cmd->add_option("--volume-emission-scale", args->volumeEmissionScale,
                    "R,G,B (or one value) in [0, 1e18]: radiance per unit of the emission grid, or the factor on a "
                    "temperature grid's blackbody radiance (default 1); once or per --volume");
    cmd->add_option("--volume-codec", args->volumeCodec,
                    "float | fp16 | fp8: how the package stores the volume's bricks and the device holds them, as "
                    "NanoVDB leaves: float exact (2,144 bytes a brick), or NanoVDB's quantized Fp16 (1,120) and Fp8 "
                    "(608), which keep each voxel within its brick's (max - min) / 131,070 or / 510 (default float); "
                    "once or per --volume");
    cmd->add_option("--progress", args->progress, "auto (bar on a terminal, lines otherwise) | bar | lines | none")
        ->check(CLI::IsMember({"auto", "bar", "lines", "none"}))
        ->capture_default_str();
    return [args]() {
        auto options = buildOptions(*args);
        if (!options) {
            std::fprintf(stderr, "vastray import: %s\n", options.message().c_str());
            return 2;
        }
        auto sources = volumeSources(*args);
        auto volumes = sources ? readVolumes(*sources) : Result<std::vector<Volume>>(sources.status());
        if (!volumes) {
            std::fprintf(stderr, "vastray import: %s\n", volumes.message().c_str());
            return 1;
        }
        for (const Volume& v : *volumes) {
            const char* glow = !v.hasEmission() ? "" : (v.material.temperature ? ", with temperature" : ", with emission");
            std::printf("read volume '%s': %u x %u x %u brick cells, %llu bricks (%s of voxels, stored as %s of NanoVDB "
                        "%s leaves)%s\n",
                        v.name.c_str(), v.brickCells[0], v.brickCells[1], v.brickCells[2],
                        (unsigned long long)v.brickCount(), formatBytes(v.brickCount() * kVolumeBrickVoxels * 4).c_str(),
                        formatBytes(v.brickCount() * volumeLeafBytes(v.codec) * (v.hasEmission() ? 2 : 1)).c_str(),
                        volumeCodecName(v.codec), glow);
        }
        options->volumes = std::move(volumes).value();
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

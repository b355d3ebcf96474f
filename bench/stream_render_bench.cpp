// Figures of the streaming renderer (issue "Streaming tracer"): a generated scene is imported
// into a package, then rendered through the Vulkan backend in core (a budget that holds every
// chunk) and out of core (the scene's resident size 4x and 16x the budget), primary-only and
// with diffuse bounces. Prints one Markdown table; every figure comes from StreamingStats and
// RenderStats of the renders it ran.
//
//   stream_render_bench [--kind city] [--triangles N] [--chunk-size 16MiB] [--resolution WxH]
//                       [--spp N] [--depth D] [--ratios 4,16] [--budgets 512MiB,128MiB] [--device I] [--package P.vast]
//                       [--codec draco|meshopt] [--repeat N] [--resident-only] [--keep] [--out FILE.md]
//                       [--resident-bytes-per-triangle B]  (import option: cap the chunks' device bytes)
//                       [--eye X,Y,Z --target X,Y,Z]  (default: frame the scene; give both to match a
//                       peer renderer's camera, e.g. ../shared/tools/mitsuba_bench.py)
//                       [--no-embree]  (skip the Embree reference row: the same frame on the host's cores)
//                       [--attributes]  (the generated mesh gets per-vertex normals and colours)
//                       [--write-ply FILE.ply]  (also write the generated mesh, its positions and faces, as
//                                                binary PLY: the same scene for mitsuba_bench.py, without the CLI)
//                       [--steady-out-of-core]  (each ratio also rendered with its scene kept open, after a
//                                                warm-up render: no decoding, as a service rendering one scene
//                                                again; compared with the resident row)
//                       [--max-paths-per-wave N]  (cap the device wave, e.g. to compare wave sizes in one call)
//                       [--no-overlap-loads]  (load chunks between paging steps, the device idle: for comparisons)
//                       [--no-partial-residency]  (every paging step waits for every chunk copy before it:
//                                                  for comparisons; StreamingOptions::partialResidency)
//                       [--no-stream-waves]  (out of core, a tile's wave at a time: for comparisons)
//                       [--window-tiles N]  (streamed waves: the most tiles open at once; default: all that fit)
//                       [--no-restart-in-shade]  (streamed waves: a generate kernel after each shading restarts
//                        the groups it ended, instead of the shading itself; for comparisons)
//                       [--wave-share F]  (out of core, the wave's part of the budget; default 0.5)
//                       [--path-state auto|device|host] [--host-state-paths N]  (gpu::PathStateMemory)
//                       [--device-wave-cap N]  (out of core, state in the budget: the wave's cap in paths,
//                                               gpu::kMaxOutOfCoreBatchRays by default; for comparisons)
//                       [--no-prefetch-scene]  (out of core, decode chunks only when rays reach them: for comparisons)
//                       [--upload auto|mapped|dma]  (how chunks reach the slots: gpu::ChunkUploadMode)
//                       [--staging-bytes 4GiB]  (--upload dma: the pinned staging area's size; default:
//                                                a sixteenth of the machine's memory, within 1-16 GiB)
//                       [--dma-batch 0]  (--upload dma: bytes of chunk copies per transfer submission; 0: per chunk)
//                       [--no-stage-on-decode]  (--upload dma: the render thread writes each chunk into staging at its
//                                                first load, not the thread that decoded it: for comparisons)
//                       [--float-positions]  (3 floats a vertex on the device even where the package's grid packs
//                                             them in 8 bytes: ChunkAttributes::packedPositions, for comparisons)
// --ratios sets out-of-core budgets as the scene's resident bytes over each ratio (so a smaller scene
// gets a smaller budget); --budgets adds rows at budgets in bytes (the same memory for any package).
//   stream_render_bench --kernel-stats [--device I]  (only: the driver's registers and sizes of the wavefront's
//                                                     kernels, gpu/KernelStatistics.h; no scene)
// --repeat N renders every row N times and keeps the run of median render time (the device
// machine's host-side timings vary by tens of percent between single runs).
// Exit status: 2 for a bad command line (the flag and the limit named), 1 when a run fails.
#include <algorithm>
#include <climits>
#include <cmath>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <optional>
#include <vector>

#include "BenchFlags.h"
#include "vastray/core/ByteSize.h"
#include "vastray/core/RenderOptions.h"
#include "vastray/core/VertexAttributes.h"
#include "vastray/cpu/EmbreeRenderer.h"
#include "vastray/cpu/RenderScene.h"
#include "vastray/gpu/KernelStatistics.h"
#include "vastray/gpu/VulkanChunkBackend.h"
#include "vastray/gpu/VulkanDevice.h"
#include "vastray/streamer/Generate.h"
#include "vastray/streamer/PackageBuilder.h"
#include "vastray/streamer/ScenePackage.h"
#include "vastray/streamer/StreamingRenderer.h"

namespace {

using namespace vastray;

struct Args {
    std::string kind = "city", package, out;
    GeometryCodec codec = GeometryCodec::Draco;
    uint64_t triangles = 10000000, chunkSize = 16ull << 20;
    uint32_t width = 1920, height = 1080, spp = 1, depth = 2;
    std::vector<double> ratios{4, 16};
    std::vector<uint64_t> budgets;  // --budgets: out-of-core rows at these budgets in bytes
    bool floatPositions = false;    // --float-positions
    int device = -1;
    int repeat = 1;
    bool keep = false;
    bool residentOnly = false;  // only the resident rows (for profiling the host side)
    bool steadyOutOfCore = false;  // --steady-out-of-core: also each ratio with its scene kept open
    bool camera = false;        // --eye and --target given
    bool embree = true;         // also render the frame with the Embree reference on the host's cores
    bool attributes = false;    // --attributes: the generated mesh gets per-vertex normals and colours
    std::string writePly;       // --write-ply: the generated mesh as binary PLY too
    bool kernelStats = false;   // --kernel-stats: print the kernels' driver statistics and stop
    Vec3f eye, target;
    std::optional<PixelBounds> region;  // --region X0,Y0,X1,Y1: one tile of the frame (bench/tiles_shared_gpu.sh)
    double residentBytesPerTriangle = PackageBuildOptions{}.residentBytesPerTriangle;  // import option
    StreamingOptions streaming;  // --max-paths-per-wave, --no-overlap-loads, --no-partial-residency, --no-stream-waves, --no-prefetch-scene
    double waveShare = gpu::kWaveShareOutOfCore;  // --wave-share: the wave's part of an out-of-core budget
    gpu::PathStateOptions pathState;              // --path-state, --host-state-paths, --device-wave-cap
    gpu::ChunkUploadOptions upload;               // --upload, --staging-bytes
};

[[noreturn]] void fail(const std::string& message, int status = 1) {
    std::fprintf(stderr, "stream_render_bench: %s\n", message.c_str());
    std::exit(status);
}
// A bad command line: status 2, as every benchmark (bench/BenchFlags.h); 1 is for a run that failed.
[[noreturn]] void usage(const std::string& message) { fail(message, 2); }

Args parseArgs(int argc, char** argv) {
    Args a;
    const bench::FlagNumbers number("stream_render_bench", 2);  // 2: usage()'s status
    for (int i = 1; i < argc; ++i) {
        const std::string flag = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) usage(flag + " needs a value");
            return argv[++i];
        };
        if (flag == "--kind") a.kind = value();
        else if (flag == "--triangles") a.triangles = number.get<uint64_t>(flag, value());
        else if (flag == "--chunk-size") {
            auto size = parseByteSize(value());
            if (!size) usage(size.message());
            a.chunkSize = *size;
        } else if (flag == "--resolution") {
            const auto size = number.list<uint32_t>(flag, value(), 'x', 1, kMaxImageSide, 2);
            a.width = size[0], a.height = size[1];
        } else if (flag == "--region") {
            const auto v = number.list<uint32_t>(flag, value(), ',', 0, kMaxImageSide, 4);
            const PixelBounds r{v[0], v[1], v[2], v[3]};
            if (r.x1 <= r.x0 || r.y1 <= r.y0) usage("--region X0,Y0,X1,Y1 (X1 > X0, Y1 > Y0)");
            a.region = r;
        } else if (flag == "--spp") a.spp = number.get<uint32_t>(flag, value(), 1, kMaxSamplesPerPixel);
        else if (flag == "--depth") a.depth = number.get<uint32_t>(flag, value(), 0, kMaxDepthLimit);
        else if (flag == "--ratios") {
            // At least 1: a budget at most the scene's resident bytes (and its cast to bytes defined).
            a.ratios = number.list<double>(flag, value(), ',', 1.0, std::numeric_limits<double>::max());
        } else if (flag == "--budgets") {
            std::stringstream list(value());
            for (std::string item; std::getline(list, item, ',');) {
                auto size = parseByteSize(item);
                if (!size) usage("--budgets: " + size.message());
                a.budgets.push_back(*size);
            }
        } else if (flag == "--float-positions") a.floatPositions = true;
        else if (flag == "--device") a.device = number.get<int>(flag, value(), -1);  // -1: VulkanDevice picks
        else if (flag == "--package") a.package = value();
        else if (flag == "--out") a.out = value();
        else if (flag == "--codec") {
            auto codec = parseGeometryCodec(value());
            if (!codec) usage(codec.message());
            a.codec = *codec;
        } else if (flag == "--repeat") {
            // The steady rows count their passes to repeat + 1 in an int.
            a.repeat = number.get<int>(flag, value(), 1, INT_MAX - 1);
        } else if (flag == "--keep") a.keep = true;
        else if (flag == "--resident-only") a.residentOnly = true;
        else if (flag == "--steady-out-of-core") a.steadyOutOfCore = true;
        else if (flag == "--kernel-stats") a.kernelStats = true;
        else if (flag == "--resident-bytes-per-triangle")  // [0, 1e6]: buildPackage's limit
            a.residentBytesPerTriangle = number.get<double>(flag, value(), 0, 1e6);
        else if (flag == "--no-embree") a.embree = false;
        else if (flag == "--attributes") a.attributes = true;
        else if (flag == "--write-ply") a.writePly = value();
        else if (flag == "--no-overlap-loads") a.streaming.overlapLoads = false;
        else if (flag == "--no-partial-residency") a.streaming.partialResidency = false;
        else if (flag == "--no-stream-waves") a.streaming.streamWaves = false;
        else if (flag == "--window-tiles") a.streaming.windowTiles = number.get<uint32_t>(flag, value());
        else if (flag == "--no-restart-in-shade") a.streaming.restartInShade = false;
        else if (flag == "--no-prefetch-scene") a.streaming.prefetchScene = false;
        else if (flag == "--upload") {
            const std::string v = value();
            if (v == "auto") a.upload.mode = gpu::ChunkUploadMode::Auto;
            else if (v == "mapped") a.upload.mode = gpu::ChunkUploadMode::Mapped;
            else if (v == "dma") a.upload.mode = gpu::ChunkUploadMode::Dma;
            else usage("--upload auto|mapped|dma");
        } else if (flag == "--staging-bytes") {
            auto size = parseByteSize(value());
            if (!size) usage(size.message());
            a.upload.stagingBytes = *size;
        } else if (flag == "--no-stage-on-decode") a.upload.stageOnDecode = false;
        else if (flag == "--dma-batch") {
            auto size = parseByteSize(value());
            if (!size) usage(size.message());
            a.upload.submitBytes = *size;
        }
        else if (flag == "--path-state") {
            auto memory = gpu::parsePathStateMemory(value());
            if (!memory) usage(memory.message());
            a.pathState.memory = *memory;
        } else if (flag == "--host-state-paths") {
            a.pathState.hostPaths = number.get<uint32_t>(flag, value(), 1);
        } else if (flag == "--device-wave-cap") {
            a.pathState.deviceWaveCap =
                number.get<uint32_t>(flag, value(), gpu::kMinBatchRays, gpu::kMaxBatchRays);
        }
        else if (flag == "--wave-share") {
            a.waveShare = number.get<double>(flag, value(), 0, 1);
            if (a.waveShare == 0 || a.waveShare == 1) usage("--wave-share must be in (0, 1)");
        } else if (flag == "--max-paths-per-wave") {
            a.streaming.maxPathsPerWave = number.get<uint32_t>(flag, value(), 1);
        }
        else if (flag == "--eye" || flag == "--target") {
            const auto v = number.list<float>(flag, value(), ',', std::numeric_limits<float>::lowest(),
                                              std::numeric_limits<float>::max(), 3);
            (flag == "--eye" ? a.eye : a.target) = Vec3f{v[0], v[1], v[2]};
            a.camera = true;
        } else usage("unknown flag " + flag);
    }
    if (!a.writePly.empty() && !a.package.empty()) usage("--write-ply writes the generated scene; with --package there is none");
    return a;
}

std::string makePackage(const Args& a, double* importSeconds) {
    const std::string path = (std::filesystem::temp_directory_path() /
                              ("stream-bench-" + a.kind + "-" + std::to_string(a.triangles) + "-" +
                               geometryCodecName(a.codec) + "-chunk" + std::to_string(a.chunkSize) +
                               "-cap" + std::to_string(int(a.residentBytesPerTriangle)) +
                               (a.attributes ? "-attributes" : "") + ".vast"))
                                 .string();
    GenerateOptions g;
    auto kind = parseGeneratorKind(a.kind);
    if (!kind) fail(kind.message());
    g.kind = *kind;
    g.triangles = a.triangles;
    // With --write-ply the same pass writes the PLY: the same positions and faces as the package's.
    auto mesh = generateMesh(g, a.writePly);
    if (!mesh) fail((a.writePly.empty() ? std::string() : "--write-ply " + a.writePly + ": ") + mesh.message());
    if (a.attributes) {
        // What a scan with normals and colours costs: a normal leaning from each vertex towards
        // +Y (radial from below the scene), a colour from its position.
        const Aabb box = mesh->bounds();
        const Vec3f centre = (box.lo + box.hi) * 0.5f, size = box.hi - box.lo;
        for (const Vec3f& p : mesh->positions) {
            mesh->normals.push_back(encodeOctahedral(p - centre + Vec3f{0, 2.0f * size.y, 0}));
            auto byte = [](float v) { return uint8_t(int(v * 251.0f) & 255); };
            mesh->colors.push_back(packSrgb8(byte((p.x - box.lo.x) / size.x), 200, byte((p.z - box.lo.z) / size.z)));
        }
    }
    PackageBuildOptions options;
    options.chunkSizeBytes = a.chunkSize;
    options.codec = a.codec;
    options.residentBytesPerTriangle = a.residentBytesPerTriangle;
    options.progress = Progress::Mode::None;
    const auto start = std::chrono::steady_clock::now();
    auto report = buildPackage(std::move(mesh).value(), path, options);
    if (!report) fail(report.message());
    *importSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return path;
}

struct Row {
    std::string label;
    uint64_t budget = 0;
    RenderStats render;
    StreamingStats streaming;
    gpu::ChunkUploadFigures upload;  // the render's backend's
    std::string imageCheck;          // at --depth: its image against the resident render's (sameImage)
};

// Whether two renders of one frame are the same bit for bit (the beauty and its alpha): "equal",
// or how many values differ and by how much at most.
std::string sameImage(const RenderImage& a, const RenderImage& b) {
    if (a.rgb.size() != b.rgb.size() || a.alpha.size() != b.alpha.size()) return "different sizes";
    uint64_t differ = 0;
    double most = 0;
    auto compare = [&](const std::vector<float>& x, const std::vector<float>& y) {
        for (size_t i = 0; i < x.size(); ++i)
            if (std::memcmp(&x[i], &y[i], sizeof(float)) != 0)
                ++differ, most = std::max(most, std::abs(double(x[i]) - double(y[i])));
    };
    compare(a.rgb, b.rgb);
    compare(a.alpha, b.alpha);
    if (differ == 0) return "equal";
    char text[128];
    std::snprintf(text, sizeof text, "%llu of %zu values differ (at most %.3g)", (unsigned long long)differ,
                  a.rgb.size() + a.alpha.size(), most);
    return text;
}

}  // namespace

int main(int argc, char** argv) {
    const Args args = parseArgs(argc, argv);
    if (args.kernelStats) {
        gpu::VulkanDeviceOptions options;
        options.deviceIndex = args.device, options.kernelStatistics = true;
        auto device = gpu::VulkanDevice::create(options);
        if (!device) fail(device.message());
        auto text = gpu::describeKernels(**device);
        if (!text) fail(text.message());
        std::fputs(text->c_str(), stdout);
        return 0;
    }
    double importSeconds = 0;
    const std::string path = args.package.empty() ? makePackage(args, &importSeconds) : args.package;
    auto reader = PackageReader::open(path);
    if (!reader) fail(reader.message());
    const PackageInfo& info = (*reader)->info();

    gpu::VulkanDeviceOptions deviceOptions;
    deviceOptions.deviceIndex = args.device;
    auto device = gpu::VulkanDevice::create(deviceOptions);
    if (!device) fail(device.message());

    // What a render's backend is created with: as asked for, but 3 floats a vertex with --float-positions.
    auto asked = [&](ChunkAttributes a) {
        if (args.floatPositions) a.packedPositions = false;
        return a;
    };
    const ChunkAttributes attributes = asked(requiredAttributes(info, RenderOptions{}));
    const uint64_t residentBytes = gpu::residentChunkBytes(info, attributes);
    auto fitPlan = gpu::planPool(info, attributes, 1ull << 40);
    if (!fitPlan) fail(fitPlan.message());
    // In core: every chunk gets a slot and the largest ray batch.
    const uint64_t fitBudget = fitPlan->totalBytes;

    std::vector<Row> rows;
    RenderImage residentImage;  // the resident path render: Embree's and every row's image at --depth are compared with it
    // The run of median render time among `runs`.
    auto median = [](std::vector<Row> runs) {
        std::sort(runs.begin(), runs.end(),
                  [](const Row& a, const Row& b) { return a.render.renderSeconds < b.render.renderSeconds; });
        return runs[runs.size() / 2];
    };
    // A row's image check (Row::imageCheck) after one more run's image: "equal" while every run so
    // far was, else what the last run that differed found. Only at --depth, once the resident
    // image exists.
    auto checkImage = [&](std::string& check, uint32_t depth, const RenderImage& image) {
        if (depth != args.depth || residentImage.rgb.empty()) return;
        const std::string found = sameImage(image, residentImage);
        if (check.empty() || found != "equal") check = found;
    };
    auto setCamera = [&](RenderOptions& o) {
        if (!args.camera) return;
        o.frameScene = false;
        o.camera.eye = args.eye, o.camera.target = args.target;
    };
    auto render = [&](const std::string& label, uint64_t budget, IntegratorKind integrator, uint32_t depth) {
        RenderOptions o;
        setCamera(o);
        o.width = args.width, o.height = args.height, o.samplesPerPixel = args.spp;
        o.integrator = integrator, o.maxDepth = depth;
        o.region = args.region;
        std::vector<Row> runs;
        std::string imageCheck;
        for (int run = 0; run < args.repeat; ++run) {
            Row row;
            row.label = label, row.budget = budget;
            row.streaming.memoryBudgetBytes = budget;
            gpu::ChunkUploadOptions upload = args.upload;
            upload.figures = &row.upload;
            auto image = renderStreaming(
                **reader, o, args.streaming,
                [&](const PackageInfo& p, const ChunkAttributes& a) {
                    return gpu::createVulkanChunkBackend(**device, p, asked(a), budget, args.waveShare, upload, 0,
                                                         args.pathState);
                },
                &row.render, &row.streaming);
            if (!image) fail(label + ": " + image.message());
            std::fprintf(stderr, "%s: %.3f s\n", label.c_str(), row.render.renderSeconds);
            runs.push_back(row);
            checkImage(imageCheck, depth, *image);
        }
        rows.push_back(median(runs));
        rows.back().imageCheck = imageCheck;
    };
    render("warm-up (in core, primary)", fitBudget, IntegratorKind::Path, 0);
    rows.clear();
    // Steady state: the scene stays open, so a second render of each kind decodes nothing (the
    // host cache holds the decoded scene) and, in core, uploads nothing: what a service rendering
    // one scene again sees. The first render of each kind only warms it up.
    auto steady = [&](const std::string& prefix, uint64_t budget, std::initializer_list<uint32_t> depths) {
        auto scene = StreamingScene::open(**reader, attributes, args.streaming,
                                          [&](const PackageInfo& p, const ChunkAttributes& a) {
                                              return gpu::createVulkanChunkBackend(**device, p, asked(a), budget,
                                                                                   args.waveShare, args.upload, 0,
                                                                                   args.pathState);
                                          });
        if (!scene) fail(scene.message());
        for (uint32_t depth : depths) {
            RenderOptions o;
            setCamera(o);
            o.width = args.width, o.height = args.height, o.samplesPerPixel = args.spp, o.maxDepth = depth;
            o.region = args.region;
            std::vector<Row> runs;
            std::string imageCheck;
            for (int pass = 0; pass <= args.repeat; ++pass) {
                Row row;
                row.label = prefix + (depth == 0 ? ", primary" : ", path depth " + std::to_string(depth));
                row.budget = budget;
                row.streaming.memoryBudgetBytes = budget;
                auto image = (*scene)->render(o, &row.render, &row.streaming);
                if (!image) fail(row.label + ": " + image.message());
                if (pass > 0) runs.push_back(row);  // pass 0 warmed the scene up
                if (budget == fitBudget && depth == args.depth)
                    residentImage = std::move(image).value();
                else
                    checkImage(imageCheck, depth, *image);
            }
            rows.push_back(median(runs));
            rows.back().imageCheck = imageCheck;
        }
    };
    steady("resident", fitBudget, {0u, args.depth});
    if (!args.residentOnly) {
        render("in core, primary", fitBudget, IntegratorKind::Path, 0);
        render("in core, path depth " + std::to_string(args.depth), fitBudget, IntegratorKind::Path, args.depth);
    }
    // Out-of-core rows: by ratio, then by budget in bytes.
    std::vector<std::pair<std::string, uint64_t>> outOfCore;
    for (double ratio : args.residentOnly ? std::vector<double>{} : args.ratios) {
        char label[64];
        std::snprintf(label, sizeof label, "%gx over budget", ratio);
        outOfCore.emplace_back(label, uint64_t(double(residentBytes) / ratio));
    }
    for (uint64_t budget : args.residentOnly ? std::vector<uint64_t>{} : args.budgets) {
        char label[96];
        std::snprintf(label, sizeof label, "%s budget (%.2fx over)", formatBytes(budget).c_str(),
                      double(residentBytes) / double(budget));
        outOfCore.emplace_back(label, budget);
    }
    for (const auto& [name, budget] : outOfCore) {
        render(name + ", primary", budget, IntegratorKind::Path, 0);
        render(name + ", path depth " + std::to_string(args.depth), budget, IntegratorKind::Path, args.depth);
        if (args.steadyOutOfCore) steady("steady " + name, budget, {args.depth});
    }
    // The Embree row last: while it keeps the host's cores busy for seconds the GPU idles, and the
    // GPU rows right after it ran up to 3x slower on the device machine (sessions 42-43: the in-core
    // rows after it walked 0.308 s where other runs walked 0.105 s; the GPU's clocks, presumably).
    std::string embreeNote;
    if (args.embree) {
        auto scene = loadRenderScene(path);
        if (!scene) fail(scene.message());
        RenderOptions o;
        setCamera(o);
        o.width = args.width, o.height = args.height, o.samplesPerPixel = args.spp, o.maxDepth = args.depth;
        Row row;
        row.label = "embree on the host's cores, path depth " + std::to_string(args.depth);
        auto image = renderWithEmbree(*scene, o, &row.render);
        if (!image) fail(row.label + ": " + image.message());
        rows.push_back(row);
        double se = 0, energy = 0;
        for (size_t i = 0; i < image->rgb.size() && i < residentImage.rgb.size(); ++i) {
            const double d = double(image->rgb[i]) - double(residentImage.rgb[i]);
            se += d * d, energy += double(image->rgb[i]) * image->rgb[i];
        }
        char note[256];
        std::snprintf(note, sizeof note,
                      " Embree (BVH build %.3f s, not in its render time) against the resident path render: "
                      "relative RMSE %.2e.",
                      row.render.buildSeconds, std::sqrt(se / std::max(energy, 1e-30)));
        embreeNote = note;
    }

    std::ostringstream md;
    md << "Scene: " << args.kind << ", " << info.triangleCount << " triangles, " << info.chunks.size()
       << " chunks (chunk size " << formatBytes(info.chunkSizeBytes) << "), resident "
       << formatBytes(residentBytes) << " = " << double(residentBytes) / double(info.triangleCount)
       << " bytes/triangle (positions " << (attributes.packedPositions ? "packed, 8" : "12")
       << " bytes a vertex); package " << formatBytes(info.fileBytes) << " (" << geometryCodecName(info.codec)
       << " chunks)";
    if (importSeconds > 0) md << ", imported in " << importSeconds << " s";
    md << ". Device: " << (*device)->info().name << ". Image " << args.width << "x" << args.height << ", "
       << args.spp << " spp";
    if (args.camera)
        md << ", eye " << args.eye.x << "," << args.eye.y << "," << args.eye.z << " target " << args.target.x << ","
           << args.target.y << "," << args.target.z;
    if (args.region)
        md << ", region " << args.region->x0 << "," << args.region->y0 << "," << args.region->x1 << ","
           << args.region->y1;
    md << ". Each row: the run of median render time of " << args.repeat << "." << embreeNote;
    const gpu::ChunkUploadMode mode = gpu::resolveUploadMode(**device, args.upload.mode);
    md << " Chunk uploads: " << (mode == gpu::ChunkUploadMode::Dma ? "DMA from pinned staging" : "mapped (host writes)");
    if (mode == gpu::ChunkUploadMode::Dma)
        md << " (transfer queue " << ((*device)->separateTransferQueue() ? "of its own family" : "= the compute queue")
           << ", device-only slots " << ((*device)->hasSeparateMemory() ? "yes" : "no") << ")";
    md << ".\n\n";
    md << "| render | budget | slots / wave paths (host: state in host memory) | render s | rays | rays/s (render) | device s | kernels s: walk / shade / other | "
          "submits | walk passes | "
          "host→device B | device→host B | decode s (waited) | upload s | touched | loads | loads/touched | "
          "per-wave loads/touched | time vs in core | steps loading with the device idle | late chunks | host gap s | device idle s |\n";
    md << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const Row& r : rows) {
        const StreamingStats& s = r.streaming;
        double reference = 0;
        // Against the in-core render of the same kind; a steady out-of-core row against the
        // resident one (both with the scene open and decoded).
        const bool steadyRow = r.label.rfind("steady", 0) == 0;
        for (const Row& q : rows)
            if (q.label.rfind(steadyRow ? "resident" : "in core", 0) == 0 && r.label.rfind("resident", 0) != 0 &&
                q.label.substr(q.label.rfind(',')) == r.label.substr(r.label.rfind(',')))
                reference = q.render.renderSeconds;
        auto ratio = [&](double ref) {
            char text[32] = "-";
            if (ref > 0) std::snprintf(text, sizeof text, "%.2fx", r.render.renderSeconds / ref);
            return std::string(text);
        };
        char line[1024];
        std::snprintf(line, sizeof line,
                      "| %s | %s | %u / %u%s | %.3f | %llu | %.1f M | %.3f | %.3f / %.3f / %.3f | %llu | %llu | %llu | %llu | %.3f (%.3f) | %.3f "
                      "| %llu | %llu | %.2f | %.3f | %s | %llu | %llu | %.3f | %.3f |\n",
                      r.label.c_str(), formatBytes(r.budget).c_str(), s.slots, s.wavePaths,
                      s.pathStateHostBytes > 0 ? " host" : "", r.render.renderSeconds,
                      (unsigned long long)r.render.rays, r.render.raysPerSecond() / 1e6, s.deviceSeconds,
                      s.kernelSeconds[StreamingStats::kKernelWalk], s.kernelSeconds[StreamingStats::kKernelShade],
                      s.kernelSeconds[StreamingStats::kKernelGenerate] + s.kernelSeconds[StreamingStats::kKernelAccumulate] +
                          s.kernelSeconds[StreamingStats::kKernelAov], (unsigned long long)s.submits, (unsigned long long)s.walkPasses,
                      (unsigned long long)s.hostToDeviceBytes, (unsigned long long)s.deviceToHostBytes,
                      s.decodeSeconds, s.decodeWaitSeconds, s.uploadSeconds,
                      (unsigned long long)s.chunksTouched, (unsigned long long)s.chunkLoads,
                      s.chunksTouched ? double(s.chunkLoads) / double(s.chunksTouched) : 0.0,
                      s.streamChunksTouched ? double(s.streamChunksTouched + s.streamReloads) / double(s.streamChunksTouched) : 0.0,
                      ratio(reference).c_str(), (unsigned long long)s.idleLoadSteps,
                      (unsigned long long)s.lateChunks, s.hostGapSeconds, s.deviceIdleSeconds);
        md << line;
    }
    md << "\nUploads per row: host copy s (into slots or staging) / DMA s (transfer queue, timestamps) / "
          "staging wait s / DMA GB / transfer submissions / copies of chunks still staged (no host copy) / "
          "chunks staged as decoded (worker s) / staging area:\n\n";
    for (const Row& r : rows) {
        const gpu::ChunkUploadFigures& u = r.upload;
        if (u.hostCopySeconds == 0 && u.dmaCopies == 0) continue;
        char dma[32] = "-", line[512];
        if (u.dmaCopies > 0) std::snprintf(dma, sizeof dma, u.dmaTimed ? "%.3f" : "untimed", u.dmaSeconds);
        std::snprintf(line, sizeof line, "- %s: %.3f / %s / %.3f / %.2f / %llu / %llu / %llu (%.3f) / %s\n",
                      r.label.c_str(), u.hostCopySeconds, dma, u.stagingWaitSeconds, double(u.dmaBytes) / 1e9,
                      (unsigned long long)u.dmaSubmits, (unsigned long long)u.stagingHits,
                      (unsigned long long)u.stagedOnDecode, u.stageSeconds,
                      u.stagingBytes ? formatBytes(u.stagingBytes).c_str() : "-");
        md << line;
    }
    // Out of core a render equals the in-core one bit for bit (docs/RENDERING.md): each row at
    // --depth, every run of it, against the resident render on the same device.
    bool checked = false;
    for (const Row& r : rows) {
        if (r.imageCheck.empty()) continue;
        if (!checked)
            md << "\nImages at path depth " << args.depth
               << " against the resident render (beauty and alpha, bit for bit, every run):\n\n";
        checked = true;
        md << "- " << r.label << ": " << r.imageCheck << "\n";
    }
    std::fputs(md.str().c_str(), stdout);
    if (!args.out.empty()) std::ofstream(args.out) << md.str();
    if (args.package.empty() && !args.keep) std::filesystem::remove(path);
    return 0;
}

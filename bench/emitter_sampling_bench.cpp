// Time against error of emissive-triangle sampling (docs/RENDERING.md, "Emissive triangles"):
// a closed box lit only by emissive triangles on its ceiling (one square lamp, or --lamps N
// small ones over a grid), rendered with next-event estimation sampling the emitters and with
// the emitters found by chance only, on the device (Vulkan, the scene in core) and the Embree
// reference, each at several sample counts, against one high-sample reference image. --mapped
// gives the lamps an emissive map (512^2, sRGB: bright bands over a dark ground, across each
// lamp), which sampled points read at their UVs.
//
//   emitter_sampling_bench [--resolution 128x128] [--depth 5] [--spp 1,4,16] [--reference-spp 1024]
//                          [--lamps 1] [--mapped] [--device I] [--no-embree] [--out FILE.md]
//                          [--write-package FILE.vast]  (build the box's package there, nothing else)
//                          [--package FILE.vast]  (render that package, built before with the same
//                          --lamps and --mapped: a machine without OpenImageIO cannot encode the map)
//                          [--reference-out FILE.pfm]  (the reference image, for bench/mitsuba_emitters.py)
//                          [--reference-only]  (render and write the reference, nothing else)
//
// Prints a Markdown table: backend, emitters sampled or not, spp, render seconds (the render
// alone: the scene is open and its pipelines built), relative RMSE against the reference, and
// RMSE x sqrt(seconds) (lower is better at equal time). The reference is the Embree reference
// sampling the emitters at --reference-spp (an independent seed). Exit status: 2 for a bad
// command line, 1 when a run fails.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "BenchFlags.h"
#include "vastray/core/Emitters.h"
#include "vastray/core/ImageFile.h"
#include "vastray/core/RenderOptions.h"
#include "vastray/cpu/EmbreeRenderer.h"
#include "vastray/cpu/RenderScene.h"
#include "vastray/gpu/VulkanChunkBackend.h"
#include "vastray/gpu/VulkanDevice.h"
#include "vastray/streamer/PackageBuilder.h"
#include "vastray/streamer/ScenePackage.h"
#include "vastray/streamer/StreamingRenderer.h"

using namespace vastray;

namespace {

[[noreturn]] void fail(const std::string& message, int status = 1) {
    std::fprintf(stderr, "emitter_sampling_bench: %s\n", message.c_str());
    std::exit(status);
}
// A bad command line: status 2, as every benchmark (bench/BenchFlags.h); 1 is for a run that failed.
[[noreturn]] void usage(const std::string& message) { fail(message, 2); }

// --lamps N at most kMaxLampSide^2: the grid, ceil(sqrt(N)) lamps a side and two emissive
// triangles a lamp, then stays within kMaxEmitters; a package with more samples none of them.
constexpr uint32_t kMaxLampSide = 1448;
static_assert(2 * kMaxLampSide * kMaxLampSide <= kMaxEmitters &&
              2 * (kMaxLampSide + 1) * (kMaxLampSide + 1) > kMaxEmitters);

struct Args {
    uint32_t width = 128, height = 128, depth = 5, referenceSpp = 1024, lamps = 1;
    std::vector<uint32_t> spp{1, 4, 16};
    int device = -1;
    bool embree = true;
    std::string out, referenceOut;
    bool referenceOnly = false;
    bool mapped = false;
    std::string writePackage, package;
};

Args parseArgs(int argc, char** argv) {
    Args a;
    const bench::FlagNumbers number("emitter_sampling_bench", 2);  // 2: usage()'s status
    for (int i = 1; i < argc; ++i) {
        const std::string flag = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) usage(flag + " needs a value");
            return argv[++i];
        };
        if (flag == "--resolution") {
            const auto size = number.list<uint32_t>(flag, value(), 'x', 1, kMaxImageSide, 2);
            a.width = size[0], a.height = size[1];
        } else if (flag == "--depth") a.depth = number.get<uint32_t>(flag, value(), 0, kMaxDepthLimit);
        else if (flag == "--reference-spp")
            a.referenceSpp = number.get<uint32_t>(flag, value(), 1, kMaxSamplesPerPixel);
        else if (flag == "--lamps")  // 0 is taken as 1
            a.lamps = std::max(1u, number.get<uint32_t>(flag, value(), 0, kMaxLampSide * kMaxLampSide));
        else if (flag == "--spp") a.spp = number.list<uint32_t>(flag, value(), ',', 1, kMaxSamplesPerPixel);
        else if (flag == "--device") a.device = number.get<int>(flag, value(), -1);  // -1: VulkanDevice picks
        else if (flag == "--no-embree") a.embree = false;
        else if (flag == "--out") a.out = value();
        else if (flag == "--reference-out") a.referenceOut = value();
        else if (flag == "--reference-only") a.referenceOnly = true;
        else if (flag == "--mapped") a.mapped = true;
        else if (flag == "--write-package") a.writePackage = value();
        else if (flag == "--package") a.package = value();
        else usage("unknown flag " + flag + " (see the comment at the top of bench/emitter_sampling_bench.cpp)");
    }
    return a;
}

// The box [-1, 1]^3, open nowhere, its walls Lambertian (the left red, the right green, the
// rest white), seen from inside; the ceiling's lamps: one square of side 0.5 under the ceiling,
// or `lamps` squares (rounded to a square grid) sharing that square's area, facing down.
TriangleMesh boxWithLamps(uint32_t lamps, bool mapped) {
    TriangleMesh mesh;
    Material white{"white"}, red{"red"}, green{"green"}, lamp{"lamp"};
    white.baseColor = {0.7f, 0.7f, 0.7f, 1};
    red.baseColor = {0.6f, 0.1f, 0.1f, 1};
    green.baseColor = {0.1f, 0.6f, 0.1f, 1};
    lamp.baseColor = {0, 0, 0, 1};
    lamp.emissive = {12, 10, 8};
    lamp.doubleSided = false;
    mesh.materials = {white, red, green, lamp};
    auto quad = [&](Vec3f a, Vec3f b, Vec3f c, Vec3f d, uint32_t material) {  // counter-clockwise from the front
        const auto base = uint32_t(mesh.positions.size());
        mesh.positions.insert(mesh.positions.end(), {a, b, c, d});
        mesh.uvs.insert(mesh.uvs.end(), {{0, 1}, {1, 1}, {1, 0}, {0, 0}});
        mesh.indices.insert(mesh.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
        mesh.materialIds.insert(mesh.materialIds.end(), {material, material});
    };
    quad({-1, -1, -1}, {-1, -1, 1}, {1, -1, 1}, {1, -1, -1}, 0);  // floor, facing +y
    quad({-1, 1, -1}, {1, 1, -1}, {1, 1, 1}, {-1, 1, 1}, 0);      // ceiling, facing -y
    quad({-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1}, 0);  // back wall, facing +z
    quad({-1, -1, 1}, {-1, 1, 1}, {1, 1, 1}, {1, -1, 1}, 0);      // front wall, facing -z
    quad({-1, -1, -1}, {-1, 1, -1}, {-1, 1, 1}, {-1, -1, 1}, 1);  // left, facing +x
    quad({1, -1, -1}, {1, -1, 1}, {1, 1, 1}, {1, 1, -1}, 2);      // right, facing -x
    const auto side = uint32_t(std::ceil(std::sqrt(double(lamps))));
    const float cell = 0.5f / float(side), y = 0.999f;
    for (uint32_t j = 0; j < side; ++j)
        for (uint32_t i = 0; i < side; ++i) {
            const float x0 = -0.25f + cell * float(i), z0 = -0.25f + cell * float(j);
            const float s = side == 1 ? cell : 0.8f * cell;  // a grid of lamps keeps gaps between them
            quad({x0, y, z0}, {x0 + s, y, z0}, {x0 + s, y, z0 + s}, {x0, y, z0 + s}, 3);  // facing -y
        }
    if (!mapped) {
        mesh.uvs.clear();
        return mesh;
    }
    // Eight bright bands (white) over a dark ground (1/16), 512^2 texels.
    const uint32_t n = 512;
    std::vector<uint8_t> texels(4 * n * n);
    for (uint32_t t = 0; t < n; ++t)
        for (uint32_t s = 0; s < n; ++s) {
            const uint8_t v = (s * 16 / n) % 2 == 0 ? 255 : 70;  // sRGB 70: about 1/16 linear
            uint8_t* p = &texels[4 * (t * n + s)];
            p[0] = p[1] = p[2] = v, p[3] = 255;
        }
    const std::filesystem::path png = std::filesystem::temp_directory_path() / "vastray-emitter-bench-bands.png";
    if (!writeRgba8Png(png.string(), n, n, texels)) fail("cannot write " + png.string());
    std::ifstream in(png, std::ios::binary);
    mesh.textures.push_back({"bands.png", ".png", {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()},
                             TextureWrap::Clamp, TextureWrap::Clamp, TextureEncoding::Srgb});
    mesh.materials[3].textures.slots[uint32_t(TextureSlot::Emissive)].texture = 0;
    return mesh;
}

RenderOptions view(const Args& a, uint32_t spp, uint32_t seed) {
    RenderOptions o;
    o.width = a.width, o.height = a.height, o.samplesPerPixel = spp, o.maxDepth = a.depth, o.seed = seed;
    o.frameScene = false;
    o.camera = {{0, 0, 0.95f}, {0, 0, -1}, {0, 1, 0}, 75.0f};
    o.environment.zenith = o.environment.horizon = o.environment.ground = {0, 0, 0};
    o.environment.sunIrradiance = {0, 0, 0};
    return o;
}

double relativeRmse(const std::vector<float>& a, const std::vector<float>& b) {
    double se = 0, energy = 0;
    for (size_t i = 0; i < b.size(); ++i) {
        const double d = double(a[i]) - double(b[i]);
        se += d * d, energy += double(b[i]) * b[i];
    }
    return std::sqrt(se / std::max(energy, 1e-30));
}

}  // namespace

int main(int argc, char** argv) {
    const Args args = parseArgs(argc, argv);
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / "vastray-emitter-bench";
    std::filesystem::create_directories(dir);
    const std::string path =
        !args.package.empty() ? args.package : !args.writePackage.empty() ? args.writePackage : (dir / "box.vast").string();
    if (args.package.empty()) {
        PackageBuildOptions build;
        build.progress = Progress::Mode::None;
        auto report = buildPackage(boxWithLamps(args.lamps, args.mapped), path, build);
        if (!report) fail(report.message());
        if (!args.writePackage.empty()) return 0;
    }
    auto reader = PackageReader::open(path);
    if (!reader) fail(reader.message());
    const PackageInfo& info = (*reader)->info();
    auto scene = loadRenderScene(path);
    if (!scene) fail(scene.message());

    auto withEmitters = [&](RenderOptions o, bool sampled) {
        if (sampled) applySceneEmitters(info.emitters, info.materials, o);
        return o;
    };
    std::fprintf(stderr, "reference: Embree, %u spp, emitters sampled...\n", args.referenceSpp);
    auto reference = renderWithEmbree(*scene, withEmitters(view(args, args.referenceSpp, 1000), true));
    if (!reference) fail(reference.message());
    if (!args.referenceOut.empty())
        if (Status s = writeImageFile(args.referenceOut, *reference); !s) fail(s.message());
    if (args.referenceOnly) return 0;

    gpu::VulkanDeviceOptions deviceOptions;
    deviceOptions.deviceIndex = args.device;
    auto device = gpu::VulkanDevice::create(deviceOptions);
    if (!device) fail(device.message());
    const ChunkAttributes attributes = requiredAttributes(info, RenderOptions{});
    auto plan = gpu::planPool(info, attributes, 1ull << 40);
    if (!plan) fail(plan.message());
    const uint64_t budget = plan->totalBytes;
    auto open = StreamingScene::open(**reader, attributes, StreamingOptions{},
                                     [&](const PackageInfo& p, const ChunkAttributes& a) {
                                         return gpu::createVulkanChunkBackend(**device, p, a, budget);
                                     });
    if (!open) fail(open.message());

    std::ostringstream table;
    table << "| backend | emitters | spp | render s | relative RMSE | RMSE x sqrt(s) |\n|---|---|---|---|---|---|\n";
    for (bool sampled : {true, false})
        for (uint32_t spp : args.spp) {
            const RenderOptions o = withEmitters(view(args, spp, 7), sampled);
            (void)(*open)->render(o);  // the pipeline variant and the scene's upload, once
            RenderStats stats;
            auto image = (*open)->render(o, &stats);
            if (!image) fail(image.message());
            const double error = relativeRmse(image->rgb, reference->rgb);
            char row[256];
            std::snprintf(row, sizeof row, "| device | %s | %u | %.4f | %.4f | %.4f |\n", sampled ? "sampled" : "by chance",
                          spp, stats.renderSeconds, error, error * std::sqrt(stats.renderSeconds));
            table << row;
            std::fprintf(stderr, "%s", row);
            if (!args.embree) continue;
            RenderStats embreeStats;
            auto embree = renderWithEmbree(*scene, o, &embreeStats);
            if (!embree) fail(embree.message());
            const double embreeError = relativeRmse(embree->rgb, reference->rgb);
            std::snprintf(row, sizeof row, "| embree | %s | %u | %.4f | %.4f | %.4f |\n", sampled ? "sampled" : "by chance",
                          spp, embreeStats.renderSeconds, embreeError, embreeError * std::sqrt(embreeStats.renderSeconds));
            table << row;
            std::fprintf(stderr, "%s", row);
        }
    char head[512];
    std::snprintf(head, sizeof head,
                  "Box lit by %zu sampled emissive triangles (%u lamp squares), %ux%u, path depth %u; reference: "
                  "Embree, %u spp, emitters sampled, seed 1000. Device: %s.\n\n",
                  info.emitters.size(), args.lamps, args.width, args.height, args.depth, args.referenceSpp,
                  (*device)->info().name.c_str());
    std::printf("%s%s", head, table.str().c_str());
    if (!args.out.empty()) std::ofstream(args.out) << head << table.str();
    return 0;
}

// The streaming renderer end to end: the Vulkan backend's device wavefront (lavapipe in CI)
// against itself at ample and tight budgets and wave sizes (bit for bit, and it really
// streamed), and against the independent Embree reference (the same hits; floats within
// rounding: the device's sqrt, division and cosine round differently).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <memory>
#include <sstream>
#include <thread>

#include "StreamTestSupport.h"
#include "shared/StreamTypes.h"
#include "shared/WavefrontTypes.h"
#include "TestTmp.h"
#include "VolumePackageForge.h"
#include "BowlMesh.h"
#include "vastray/core/ByteSize.h"
#include "vastray/cpu/EmbreeRenderer.h"
#include "vastray/cpu/RenderScene.h"
#include "vastray/gpu/VulkanChunkBackend.h"
#include "vastray/gpu/VulkanDevice.h"
#include "vastray/streamer/Generate.h"
#include "vastray/streamer/Import.h"
#include "vastray/streamer/PackageBuilder.h"
#include "vastray/streamer/ScenePackage.h"
#include "vastray/streamer/StreamingRenderer.h"

namespace vastray {
namespace {

std::string tmpPath(const std::string& name) {
    const std::filesystem::path dir = test::testTmpDir("stream");
    std::filesystem::create_directories(dir);
    return (dir / name).string();
}

using test::budgetForSlots;
using test::renderEmbree;
using test::renderVulkan;
gpu::VulkanDevice& device() { return test::sharedVulkanDevice(); }

std::string packageFromMesh(const std::string& name, TriangleMesh mesh, uint64_t chunkBytes,
                            GeometryCodec codec = GeometryCodec::Draco) {
    const std::string path = tmpPath(name + ".vast");
    if (std::filesystem::exists(path)) return path;
    PackageBuildOptions options;
    options.codec = codec;
    options.chunkSizeBytes = chunkBytes;
    options.progress = Progress::Mode::None;
    auto report = buildPackage(std::move(mesh), path, options);
    EXPECT_TRUE(report) << report.message();
    return path;
}

std::string packageFromFile(const std::string& name, const std::string& meshPath, uint64_t chunkBytes) {
    auto imported = importMesh(meshPath);
    EXPECT_TRUE(imported) << imported.message();
    if (!imported) return {};
    return packageFromMesh(name, std::move(imported->mesh), chunkBytes);
}

std::string generatedPackage(GeneratorKind kind, uint64_t triangles, uint64_t chunkBytes) {
    const std::string name = std::string(generatorKindName(kind)) + "-" + std::to_string(triangles) + "-" +
                             std::to_string(chunkBytes);
    const std::string ply = tmpPath(name + ".ply");
    if (!std::filesystem::exists(ply)) {
        GenerateOptions options;
        options.kind = kind;
        options.triangles = triangles;
        EXPECT_TRUE(generateToPly(options, ply));
    }
    return packageFromFile(name, ply, chunkBytes);
}

RenderOptions smallRender(uint32_t aovs = kAovDepth | kAovNormal | kAovPrimId) {
    RenderOptions o;
    o.width = 40, o.height = 32;
    o.samplesPerPixel = 2;
    o.maxDepth = 3;
    o.aovs = aovs;
    return o;
}

template <typename T>
bool sameBits(const std::vector<T>& a, const std::vector<T>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

// cost counts the work done, which depends on the schedule (out of core, cells are traced out of
// order and fewer are pruned): compared only where the schedule is the same.
void expectIdentical(const RenderImage& a, const RenderImage& b, bool compareCost = true) {
    EXPECT_TRUE(sameBits(a.rgb, b.rgb)) << "beauty differs";
    EXPECT_TRUE(sameBits(a.alpha, b.alpha)) << "alpha differs";
    EXPECT_TRUE(sameBits(a.depth, b.depth)) << "depth differs";
    EXPECT_TRUE(sameBits(a.normal, b.normal)) << "normal differs";
    EXPECT_TRUE(sameBits(a.albedo, b.albedo)) << "albedo differs";
    EXPECT_TRUE(sameBits(a.primId, b.primId)) << "primid differs";
    EXPECT_TRUE(sameBits(a.chunkId, b.chunkId)) << "chunkid differs";
    if (compareCost) {
        EXPECT_TRUE(sameBits(a.cost, b.cost)) << "cost differs";
    }
}

double primIdAgreement(const RenderImage& a, const RenderImage& b) {
    uint64_t same = 0;
    for (size_t i = 0; i < a.primId.size(); ++i) same += a.primId[i] == b.primId[i];
    return double(same) / double(a.primId.size());
}

constexpr uint32_t kAllAovs = kAovDepth | kAovNormal | kAovAlbedo | kAovPrimId | kAovChunkId | kAovCost;

// The device wavefront against the Embree reference (an independent implementation of the same
// sampling specification, docs/RENDERING.md) on every AOV both have: the same triangles hit,
// floats that differ by rounding. Camera directions and normals are normalized on the device
// (its inverse square root is not correctly rounded) and Embree's t is its own, so depth and
// normals differ in the last bits; a path whose Russian-roulette draw falls within that rounding
// of its survival probability takes another turn, hence a beauty tolerance well below the noise
// of these renders (relative RMSE 1e-3; measured 4e-8 on lavapipe).
void expectAgrees(const RenderImage& device, const RenderImage& reference) {
    ASSERT_EQ(device.rgb.size(), reference.rgb.size());
    double se = 0, energy = 0, alpha = 0;
    for (size_t i = 0; i < reference.rgb.size(); ++i) {
        const double d = double(device.rgb[i]) - double(reference.rgb[i]);
        se += d * d, energy += double(reference.rgb[i]) * reference.rgb[i];
    }
    for (size_t i = 0; i < reference.alpha.size(); ++i) alpha += std::fabs(device.alpha[i] - reference.alpha[i]);
    const double beauty = std::sqrt(se / std::max(energy, 1e-30));
    EXPECT_LE(beauty, 1e-3) << "beauty relative RMSE";
    EXPECT_LE(alpha / double(reference.alpha.size()), 1e-3) << "alpha, mean difference";
    // A pixel-centre ray through an edge shared by two triangles may be given to either by the
    // two watertight tests (1 pixel of this 40x32 terrain): there the normal differs too.
    ASSERT_FALSE(reference.primId.empty());
    EXPECT_GE(primIdAgreement(device, reference), 0.998);
    double depthError = 0, normalError = 0;
    for (size_t i = 0; i < reference.depth.size(); ++i)
        if (std::isfinite(reference.depth[i]) || std::isfinite(device.depth[i]))
            depthError = std::max(depthError, std::fabs(double(device.depth[i]) - reference.depth[i]) / reference.depth[i]);
    for (size_t i = 0; i < reference.normal.size(); ++i)
        if (device.primId[i / 3] == reference.primId[i / 3])
            normalError = std::max(normalError, std::fabs(double(device.normal[i]) - reference.normal[i]));
    EXPECT_LE(depthError, 1e-4) << "depth, largest relative error";
    EXPECT_LE(normalError, 1e-4) << "normal, largest error";
    EXPECT_TRUE(sameBits(device.albedo, reference.albedo)) << "albedo differs";
    std::printf("device wavefront vs Embree: beauty relative RMSE %.2e, primid agreement %.6f, depth %.2e, normal "
                "%.2e\n", beauty, primIdAgreement(device, reference), depthError, normalError);
}

TEST(StreamingRender, VulkanAgreesWithEmbreeOnEveryAov) {
    const std::string path = generatedPackage(GeneratorKind::Terrain, 20000, 64 << 10);
    for (IntegratorKind integrator : {IntegratorKind::Path, IntegratorKind::AmbientOcclusion}) {
        RenderOptions o = smallRender(kAllAovs);
        o.integrator = integrator;
        StreamingStats gs;
        auto gpuImage = renderVulkan(path, o, 64ull << 20, &gs);
        ASSERT_TRUE(gpuImage) << gpuImage.message();
        auto reference = renderEmbree(path, o);
        ASSERT_TRUE(reference) << reference.message();
        expectAgrees(*gpuImage, *reference);
        EXPECT_GT(gs.chunksTotal, 4u) << "the scene should span several chunks";
        EXPECT_LE(gs.peakDeviceBytes, gs.memoryBudgetBytes);
    }
}

TEST(StreamingRender, TightBudgetEqualsAmpleBudgetAndReallyStreams) {
    const std::string path = generatedPackage(GeneratorKind::Terrain, 20000, 64 << 10);
    const RenderOptions o = smallRender(kAllAovs);
    const uint64_t tight = budgetForSlots(path, 2, o.aovs);
    ASSERT_GT(tight, 0u);
    StreamingStats ample, small;
    auto a = renderVulkan(path, o, 256ull << 20, &ample);
    ASSERT_TRUE(a) << a.message();
    auto b = renderVulkan(path, o, tight, &small);
    ASSERT_TRUE(b) << b.message();
    expectIdentical(*a, *b, false);
    // Loading between the paging steps (the device idle) instead of while it walks: other
    // schedules, the same image.
    StreamingStats between;
    auto c = renderVulkan(path, o, tight, &between, 1u << 21, false);
    ASSERT_TRUE(c) << c.message();
    expectIdentical(*a, *c, false);
    EXPECT_GT(between.chunkLoads, between.chunksTouched);
    EXPECT_GT(between.idleLoadSteps, 0u) << "without overlap every paging step loads with the device idle";
    EXPECT_LE(between.idleLoadSteps, between.chunkLoads) << "a step that loads loads a chunk at least";
    EXPECT_LE(ample.idleLoadSteps, 1u) << "in core only the first step waits, for the chunks its rays start in";
    EXPECT_GT(small.hostGapSeconds, 0.0) << "the host reads and plans between paging steps";
    EXPECT_GT(small.deviceIdleSeconds, 0.0) << "the device waits for the host between paging steps";
    EXPECT_EQ(small.lateChunks, 0u) << "mapped uploads are done before a step is submitted";
    // Decoding chunks only when rays reach them (no scene prefetch): the same image too.
    StreamingStats onDemand;
    auto d = renderVulkan(path, o, tight, &onDemand, 1u << 21, true, false);
    ASSERT_TRUE(d) << d.message();
    expectIdentical(*a, *d, false);
    EXPECT_EQ(onDemand.chunksTouched, small.chunksTouched);
    EXPECT_EQ(small.slots, 2u);
    EXPECT_GT(small.chunkLoads, small.chunksTouched) << "two slots should have forced reloads";
    EXPECT_EQ(ample.chunkLoads, ample.chunksTouched) << "a scene that fits loads each chunk once";
    EXPECT_LE(small.streamReloads, small.chunkLoads) << "reloads within a wave are among the loads";
    EXPECT_LE(ample.peakDeviceBytes, ample.memoryBudgetBytes);
    EXPECT_LE(small.peakDeviceBytes, small.memoryBudgetBytes);
    std::printf("terrain: %llu chunks, touched %llu; tight budget %s: %llu loads (%llu within a wave), %llu decodes\n",
                (unsigned long long)small.chunksTotal, (unsigned long long)small.chunksTouched,
                formatBytes(tight).c_str(), (unsigned long long)small.chunkLoads,
                (unsigned long long)small.streamReloads, (unsigned long long)small.decodes);
}

// Camera rays out of core: a ray does not stop at its first missing cell but traces the resident
// cells beyond it, and every waiting ray walks again once per paging step, so a chunk serves all
// the rays of the wave that need it while it is resident and is never loaded twice for one wave
// (with shading, later bounces may need it again after its eviction). Stopping at the first
// missing cell, as the walk once did, loaded chunks again for rays that had waited elsewhere.
TEST(StreamingRender, CameraRaysLoadEachChunkOncePerWave) {
    const std::string path = generatedPackage(GeneratorKind::Terrain, 20000, 64 << 10);
    RenderOptions o = smallRender(kAovDepth | kAovPrimId);
    o.maxDepth = 0;
    o.samplesPerPixel = 4;
    StreamingStats ample, small;
    auto a = renderVulkan(path, o, 256ull << 20, &ample);
    ASSERT_TRUE(a) << a.message();
    auto b = renderVulkan(path, o, budgetForSlots(path, 2, o.aovs), &small);
    ASSERT_TRUE(b) << b.message();
    expectIdentical(*a, *b, false);
    EXPECT_EQ(small.slots, 2u);
    EXPECT_GT(small.chunkLoads, uint64_t(small.slots)) << "two slots should page chunks in and out";
    EXPECT_EQ(small.streamReloads, 0u) << small.chunkLoads << " loads for " << small.streamChunksTouched
                                       << " chunks touched over the waves";
}

// Chunks copied by the transfer queue from pinned staging memory into slots the host cannot map
// (gpu::ChunkUploadMode::Dma): the kernels wait for the copies on a timeline semaphore, so a
// render that streams with them equals the mapped render bit for bit, whether the staging area
// holds two chunks (every load is written into it and waits for the copy that last read its
// block) or every chunk (a chunk is written once; loads again are copies on the device alone).
// On lavapipe the staging area is device memory, taken from the budget. The decoding threads
// write chunks into unused staging blocks as they decode them (stageOnDecode), or not.
TEST(StreamingRender, DmaUploadsEqualMappedUploads) {
    const std::string path = generatedPackage(GeneratorKind::Terrain, 20000, 64 << 10);
    const RenderOptions o = smallRender(kAllAovs);
    const bool stagingInDevice = device().inDeviceMemory(gpu::VulkanDevice::MemoryUse::Staging);
    gpu::ChunkUploadOptions upload;
    upload.mode = gpu::ChunkUploadMode::Mapped;
    StreamingStats mapped;
    auto a = renderVulkan(path, o, budgetForSlots(path, 2, o.aovs), &mapped, 1u << 21, true, true, upload);
    ASSERT_TRUE(a) << a.message();
    auto render = [&](uint64_t stagingBytes, uint64_t submitBytes, bool overlap, StreamingStats& stats,
                      gpu::ChunkUploadFigures& figures, bool partialResidency = true) {
        upload.mode = gpu::ChunkUploadMode::Dma;
        upload.stagingBytes = stagingBytes, upload.submitBytes = submitBytes, upload.figures = &figures;
        const uint64_t budget = budgetForSlots(path, 2, o.aovs, stagingInDevice ? stagingBytes : 0);
        ASSERT_GT(budget, 0u);
        auto image = renderVulkan(path, o, budget, &stats, 1u << 21, overlap, true, upload, true, {}, 0,
                                  partialResidency);
        ASSERT_TRUE(image) << image.message();
        expectIdentical(*a, *image, false);
        EXPECT_EQ(stats.slots, 2u);
        EXPECT_GT(stats.chunkLoads, stats.chunksTotal) << "two slots should have forced reloads";
        EXPECT_LE(stats.peakDeviceBytes, stats.memoryBudgetBytes);
        // Every load went through the transfer queue: the arrays by DMA, the slot entry by map.
        EXPECT_EQ(figures.dmaCopies, stats.chunkLoads);
        EXPECT_EQ(figures.dmaBytes + stats.chunkLoads * sizeof(gpu::ChunkSlot), stats.bytesUploaded);
        // The host writes chunks into staging at their load, or as they are decoded (stageOnDecode).
        EXPECT_GT(figures.hostCopySeconds + figures.stageSeconds, 0.0);
        EXPECT_LE(figures.hostCopySeconds, stats.uploadSeconds);
    };
    StreamingStats small, between, all, batched;
    gpu::ChunkUploadFigures smallFigures, betweenFigures, allFigures, batchedFigures;
    render(1, 0, true, small, smallFigures);
    EXPECT_EQ(smallFigures.dmaSubmits, smallFigures.dmaCopies) << "a submission per chunk";
    // Loads between the steps: the next kernels wait for copies submitted just before them.
    render(1, 0, false, between, betweenFigures);
    // Every chunk kept staged: the host writes each chunk once at most.
    render(1ull << 30, 0, true, all, allFigures);
    EXPECT_GT(allFigures.stagingHits, 0u);
    EXPECT_LE(allFigures.dmaCopies - allFigures.stagingHits, all.chunksTotal);
    // Copies batched until the next compute submission (or until a block of the open batch is
    // needed again): fewer transfer submissions.
    render(1, 1ull << 30, true, batched, batchedFigures);
    EXPECT_LT(batchedFigures.dmaSubmits, batchedFigures.dmaCopies);
    // Copies seen done a query late (copiesSeenLate), as on a device whose bus is slower than
    // its walk: with partial residency a step after a load sees the chunk absent, waits for
    // fewer copies, and its rays park again until a later step; the image stays the same.
    // Without it, every step waits for every copy and sees every chunk loaded.
    upload.copiesSeenLate = true;
    StreamingStats late, waited;
    gpu::ChunkUploadFigures lateFigures, waitedFigures;
    render(1ull << 30, 0, true, late, lateFigures);
    EXPECT_GT(late.lateChunks, 0u);
    render(1ull << 30, 0, true, waited, waitedFigures, false);
    EXPECT_EQ(waited.lateChunks, 0u);
    upload.copiesSeenLate = false;
    // Chunks written into staging by the threads that decode them (stageOnDecode, the default:
    // the staging area holds every chunk, so each is staged once, by a worker or at its load) or
    // only at their loads: the same image either way.
    EXPECT_GT(allFigures.stagedOnDecode, 0u) << "no chunk was staged as it was decoded";
    EXPECT_LE(allFigures.stagedOnDecode, all.chunksTotal);
    StreamingStats atLoad;
    gpu::ChunkUploadFigures atLoadFigures;
    upload.stageOnDecode = false;
    render(1ull << 30, 0, true, atLoad, atLoadFigures);
    upload.stageOnDecode = true;
    EXPECT_EQ(atLoadFigures.stagedOnDecode, 0u);
    EXPECT_EQ(atLoadFigures.stageSeconds, 0.0);
    std::printf("dma: %llu loads; all chunks staged: %llu copies of chunks still staged, %llu chunks staged as "
                "decoded\n",
                (unsigned long long)all.chunkLoads, (unsigned long long)allFigures.stagingHits,
                (unsigned long long)allFigures.stagedOnDecode);
}

// DMA uploads whose staging lies in device memory keep it from the budget, in whole slots: two
// at least, one per chunk at most.
TEST(StreamingRender, StagingInDeviceMemoryCountsAgainstTheBudget) {
    const std::string path = generatedPackage(GeneratorKind::Terrain, 20000, 64 << 10);
    auto reader = PackageReader::open(path);
    ASSERT_TRUE(reader) << reader.message();
    const PackageInfo& info = (*reader)->info();
    const double share = gpu::kWaveShareOutOfCore;
    auto plain = gpu::planPool(info, ChunkAttributes{}, 1ull << 40);
    auto two = gpu::planPool(info, ChunkAttributes{}, 1ull << 40, true, share, 1);
    auto every = gpu::planPool(info, ChunkAttributes{}, 1ull << 40, true, share, 1ull << 40);
    ASSERT_TRUE(plain && two && every);
    const uint64_t slot = (plain->slotBytes + 65535) / 65536 * 65536;
    EXPECT_EQ(plain->stagingBytes, 0u);
    EXPECT_EQ(two->stagingBytes, 2 * slot);
    EXPECT_EQ(every->stagingBytes, info.chunks.size() * slot);
    EXPECT_EQ(two->minimumBytes, plain->minimumBytes + two->stagingBytes);
    auto refused = gpu::planPool(info, ChunkAttributes{}, plain->minimumBytes, true, share, 1);
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.message().find("staging area"), std::string::npos) << refused.message();
    const uint64_t budget = budgetForSlots(path, 3, 0, 1);
    auto three = gpu::planPool(info, ChunkAttributes{}, budget, true, share, 1);
    ASSERT_TRUE(three);
    EXPECT_EQ(three->slots, 3u);
    EXPECT_LE(three->totalBytes, budget);
}

// The same scene packaged with each chunk codec: the codecs order faces and rotate corners
// differently, so the chunk trees differ, but every hit is the same triangle and the image the
// same up to float rounding of t and of the corner order (a bounce frame that depended on the
// sign of a zero normal component once made 8 % of a city's pixels differ).
TEST(StreamingRender, MeshoptPackageRendersLikeDracoPackage) {
    const std::string ply = tmpPath("city-codecs.ply");
    GenerateOptions g;
    g.kind = GeneratorKind::City;
    g.triangles = 20000;
    ASSERT_TRUE(generateToPly(g, ply));
    auto imported = importMesh(ply);
    ASSERT_TRUE(imported) << imported.message();
    const std::string draco = packageFromMesh("city-draco", imported->mesh, 64 << 10, GeometryCodec::Draco);
    const std::string meshopt = packageFromMesh("city-meshopt", imported->mesh, 64 << 10, GeometryCodec::Meshopt);
    const RenderOptions o = smallRender(kAovPrimId | kAovChunkId);
    StreamingStats ds, ms;
    auto a = renderVulkan(draco, o, budgetForSlots(draco, 2, o.aovs), &ds);
    ASSERT_TRUE(a) << a.message();
    auto b = renderVulkan(meshopt, o, budgetForSlots(meshopt, 2, o.aovs), &ms);
    ASSERT_TRUE(b) << b.message();
    EXPECT_GT(ms.chunkLoads, ms.chunksTouched) << "the meshopt package should have streamed";
    EXPECT_GE(primIdAgreement(*a, *b), 0.9999);
    EXPECT_TRUE(sameBits(a->chunkId, b->chunkId));
    double squared = 0, reference = 0;
    for (size_t i = 0; i < a->rgb.size(); ++i) {
        squared += double(a->rgb[i] - b->rgb[i]) * (a->rgb[i] - b->rgb[i]);
        reference += double(a->rgb[i]) * a->rgb[i];
    }
    EXPECT_LE(std::sqrt(squared / reference), 1e-3) << "relative RMSE between the codecs' images";
}

TEST(StreamingRender, SmallWavesEqualOneWave) {
    const std::string path = generatedPackage(GeneratorKind::Soup, 5000, 32 << 10);
    const RenderOptions o = smallRender(kAllAovs);
    auto one = renderVulkan(path, o, 64ull << 20);
    ASSERT_TRUE(one) << one.message();
    auto many = renderVulkan(path, o, 64ull << 20, nullptr, 333);
    ASSERT_TRUE(many) << many.message();
    // Cost counts the cells each render really traced: a cold render pages chunks in during
    // its first streams, and which cells a nearer hit prunes depends on what was resident when.
    expectIdentical(*one, *many, false);
}

// Out of core, waves are streamed: a group of a pixel's samples that is done starts the next
// pixel of the window at once. With small waves the window holds several tiles and turns over
// many times; the image equals the in-core render and the tile-at-a-time schedule bit for bit,
// whether the shading restarts the groups it ends or a generate kernel after it does.
TEST(StreamingRender, StreamedWavesEqualTileWaves) {
    const std::string path = generatedPackage(GeneratorKind::Terrain, 20000, 64 << 10);
    RenderOptions o = smallRender(kAllAovs);
    o.samplesPerPixel = 5;
    const uint64_t tight = budgetForSlots(path, 2, o.aovs);
    StreamingStats ample, streamed, tiled;
    auto a = renderVulkan(path, o, 256ull << 20, &ample, 333);
    ASSERT_TRUE(a) << a.message();
    auto b = renderVulkan(path, o, tight, &streamed, 333);
    ASSERT_TRUE(b) << b.message();
    auto c = renderVulkan(path, o, tight, &tiled, 333, true, true, {}, false);
    ASSERT_TRUE(c) << c.message();
    StreamingStats narrow, wide;
    auto n = renderVulkan(path, o, tight, &narrow, 333, true, true, {}, true, {}, 5);
    ASSERT_TRUE(n) << n.message();
    auto w = renderVulkan(path, o, tight, &wide, 150);
    ASSERT_TRUE(w) << w.message();
    // Groups restarted by a generate kernel after each shading, not by the shading itself.
    StreamingStats generated;
    auto g = renderVulkan(path, o, tight, &generated, 333, true, true, {}, true, {}, 0, true, false);
    ASSERT_TRUE(g) << g.message();
    expectIdentical(*a, *b, false);
    expectIdentical(*a, *g, false);
    EXPECT_EQ(generated.walkedRays, ample.walkedRays);
    EXPECT_GE(generated.streamedTiles, 20u);
    expectIdentical(*a, *c, false);
    expectIdentical(*a, *n, false);
    expectIdentical(*a, *w, false);
    // 333 paths: groups of 5 samples, tiles of at most 66 pixels (20 tiles); the window is as
    // many tiles as the output buffer holds (it holds the plan's wave, 1,024 paths or more here),
    // or 5 when asked. 150 paths: tiles of 30 pixels, the widest window the kernels have.
    EXPECT_EQ(narrow.streamWindowTiles, 5u);
    EXPECT_GE(streamed.streamWindowTiles, 15u);
    EXPECT_EQ(wide.streamWindowTiles, gpu::kMaxWindowTiles);
    EXPECT_GE(narrow.streamedTiles, 20u);
    EXPECT_GE(wide.streamedTiles, 40u);
    EXPECT_GE(streamed.streamedTiles, 20u);
    EXPECT_EQ(tiled.streamedTiles, 0u);
    EXPECT_EQ(ample.streamedTiles, 0u) << "in core, a tile's wave at a time";
    EXPECT_GT(streamed.chunkLoads, streamed.chunksTouched);
    EXPECT_LE(streamed.peakDeviceBytes, streamed.memoryBudgetBytes);
    // The same rays (AOV, camera, bounce and shadow rays), whatever the schedule.
    EXPECT_EQ(streamed.walkedRays, ample.walkedRays);
    EXPECT_EQ(tiled.walkedRays, ample.walkedRays);

    // More samples than a wave holds: a group renders its pixel in blocks (4 samples, then 2),
    // adding each to the pixel's sum in sample order.
    o.width = 16, o.height = 8, o.samplesPerPixel = 6;
    auto d = renderVulkan(path, o, 256ull << 20, nullptr, 4);
    ASSERT_TRUE(d) << d.message();
    StreamingStats blocks;
    auto e = renderVulkan(path, o, tight, &blocks, 4);
    ASSERT_TRUE(e) << e.message();
    expectIdentical(*d, *e, false);
    EXPECT_EQ(blocks.streamedTiles, 128u) << "one pixel per tile";
}

TEST(StreamingRender, HostCacheAvoidsSecondDecodes) {
    const std::string path = generatedPackage(GeneratorKind::Terrain, 20000, 64 << 10);
    const RenderOptions o = smallRender();
    const uint64_t tight = budgetForSlots(path, 2, o.aovs);
    StreamingStats s;
    auto image = renderVulkan(path, o, tight, &s, 1u << 21, true, false);
    ASSERT_TRUE(image) << image.message();
    EXPECT_EQ(s.decodes, s.chunksTouched) << "the default host cache holds every chunk";
    // With the scene prefetch (the default), chunks no ray reaches may be decoded too, but no
    // chunk twice.
    StreamingStats p;
    auto prefetched = renderVulkan(path, o, tight, &p);
    ASSERT_TRUE(prefetched) << prefetched.message();
    EXPECT_LE(p.decodes, p.chunksTotal);
}

// A small package's chunk table repeated to at least `chunks` chunks: a large scene for planPool,
// which reads nothing else.
PackageInfo standInScene(size_t chunks) {
    const std::string path = generatedPackage(GeneratorKind::Terrain, 20000, 64 << 10);
    auto reader = PackageReader::open(path);
    EXPECT_TRUE(reader) << reader.message();
    if (!reader) return {};
    PackageInfo big = (*reader)->info();
    const std::vector<ChunkInfo> one = big.chunks;
    while (big.chunks.size() < chunks) big.chunks.insert(big.chunks.end(), one.begin(), one.end());
    return big;
}

// A large out-of-core budget: the wave stops at kMaxOutOfCoreBatchRays paths and the slots take
// the rest (PERF_NOTES 63). The stand-in scene is several GiB.
TEST(StreamingRender, OutOfCoreWaveStopsAtItsCapAndSlotsTakeTheRest) {
    const PackageInfo big = standInScene(120000);
    ASSERT_GT(big.decodedBytes(), 4ull << 30) << "the stand-in scene must exceed the budget";
    const uint64_t budget = 2ull << 30;
    auto plan = gpu::planPool(big, ChunkAttributes{}, budget, false);
    ASSERT_TRUE(plan) << plan.message();
    ASSERT_LT(plan->slots, big.chunks.size());
    EXPECT_EQ(plan->batchRays, gpu::kMaxOutOfCoreBatchRays) << "half of 2 GiB would hold ~5 M paths";
    EXPECT_LT(plan->rayBytes, budget / 8);
    EXPECT_GT(plan->totalBytes, budget * 9 / 10) << "the slots take what the wave leaves";
    EXPECT_LE(plan->totalBytes, budget);
    // Below the cap the share still decides.
    auto small = gpu::planPool(big, ChunkAttributes{}, 64ull << 20, false);
    ASSERT_TRUE(small) << small.message();
    EXPECT_LT(small->batchRays, gpu::kMaxOutOfCoreBatchRays);
    EXPECT_GT(small->rayBytes, (64ull << 20) * 2 / 5) << "about half of the budget";
    // Another cap (stream_render_bench --device-wave-cap) moves the split; one outside the
    // dispatchable range is refused by name.
    const uint32_t higher = gpu::kMaxOutOfCoreBatchRays + (128u << 10);
    auto raised = gpu::planPool(big, ChunkAttributes{}, budget, false, gpu::kWaveShareOutOfCore, 0, 0, 0, higher);
    ASSERT_TRUE(raised) << raised.message();
    EXPECT_EQ(raised->batchRays, higher);
    EXPECT_LT(raised->slots, plan->slots) << "the larger wave takes slots";
    EXPECT_LE(raised->totalBytes, budget);
    for (uint32_t cap : {gpu::kMinBatchRays - 1, gpu::kMaxBatchRays + 1}) {
        auto refused = gpu::planPool(big, ChunkAttributes{}, budget, false, gpu::kWaveShareOutOfCore, 0, 0, 0, cap);
        ASSERT_FALSE(refused);
        EXPECT_NE(refused.message().find("out-of-core wave's cap"), std::string::npos) << refused.message();
    }
}

// The output buffer (tile colours and AOVs) holds twice the wave's pixels out of core when it lies
// in host memory, off the budget (a streamed window of ~32 tiles); the wave's pixels in core, or
// where it counts against the budget.
TEST(StreamingRender, OutputBufferDoublesOutOfCoreOnlyOffTheBudget) {
    const PackageInfo big = standInScene(120000);
    const uint64_t budget = 2ull << 30;
    auto host = gpu::planPool(big, ChunkAttributes{}, budget, false);
    ASSERT_TRUE(host) << host.message();
    ASSERT_LT(host->slots, big.chunks.size());
    EXPECT_EQ(host->outputPixels, uint64_t(gpu::kOutOfCoreOutputScale) * host->batchRays);
    auto counted = gpu::planPool(big, ChunkAttributes{}, budget, true);
    ASSERT_TRUE(counted) << counted.message();
    EXPECT_EQ(counted->outputPixels, counted->batchRays) << "in the budget: the wave's pixels";
    auto inCore = gpu::planPool(big, ChunkAttributes{}, 1ull << 40, false);
    ASSERT_TRUE(inCore) << inCore.message();
    ASSERT_EQ(inCore->slots, big.chunks.size());
    EXPECT_EQ(inCore->outputPixels, inCore->batchRays) << "in core nothing is streamed";
}

// Path state in host memory (gpu::PathStateMemory::Host): off the budget where host memory is
// not the device's (but for the paths' walk bits, a byte a path), so the slots take the rest of
// it and the wave is the asked-for size; counted where
// it is (lavapipe), the wave shrinking to what the budget holds. In core nothing moves.
TEST(StreamingRender, PathStateInHostMemoryGivesTheSlotsTheBudget) {
    const std::string path = generatedPackage(GeneratorKind::Terrain, 20000, 64 << 10);
    auto reader = PackageReader::open(path);
    ASSERT_TRUE(reader) << reader.message();
    const PackageInfo big = standInScene(20000);
    const uint64_t budget = 64ull << 20;
    auto device = gpu::planPool(big, ChunkAttributes{}, budget, false);
    auto host = gpu::planPool(big, ChunkAttributes{}, budget, false, gpu::kWaveShareOutOfCore, 0, 0, gpu::kHostStatePaths);
    ASSERT_TRUE(device && host) << device.message() << host.message();
    ASSERT_LT(host->slots, big.chunks.size()) << "the test needs an out-of-core budget";
    EXPECT_FALSE(device->stateInHostMemory);
    EXPECT_TRUE(host->stateInHostMemory);
    EXPECT_EQ(host->batchRays, gpu::kHostStatePaths);
    EXPECT_EQ(host->rayBytes, uint64_t(gpu::kHostStatePaths))
        << "state outside the device's heaps is not the device's: only its walk bits, a byte a path, stay on it";
    EXPECT_GT(host->slots, device->slots * 17 / 10) << "the slots take the half the wave had";
    EXPECT_LE(host->totalBytes, budget);
    // Where host memory is the device's the state counts, and the wave is what fits.
    auto counted = gpu::planPool(big, ChunkAttributes{}, budget, true, gpu::kWaveShareOutOfCore, 0, 0, gpu::kHostStatePaths);
    ASSERT_TRUE(counted) << counted.message();
    EXPECT_TRUE(counted->stateInHostMemory);
    EXPECT_GT(counted->rayBytes, 0u);
    EXPECT_LT(counted->batchRays, gpu::kHostStatePaths) << "512 k paths' state is more than 64 MiB";
    EXPECT_LE(counted->totalBytes, budget);
    // A budget that holds every chunk: in core, the state stays in device memory.
    auto fits = gpu::planPool((*reader)->info(), ChunkAttributes{}, 256ull << 20, false, gpu::kWaveShareOutOfCore, 0, 0,
                              gpu::kHostStatePaths);
    ASSERT_TRUE(fits) << fits.message();
    EXPECT_EQ(fits->slots, (*reader)->info().chunks.size());
    EXPECT_FALSE(fits->stateInHostMemory);
}

// Auto moves the state to host memory only on a device with memory apart from the host's, for a
// scene of more than kHostStateOversubscription budgets and without volumes; Host with volumes is
// refused, naming them.
TEST(StreamingRender, AutoPathStateMemoryFollowsTheOversubscription) {
    const std::string path = generatedPackage(GeneratorKind::Terrain, 20000, 64 << 10);
    auto reader = PackageReader::open(path);
    ASSERT_TRUE(reader) << reader.message();
    PackageInfo info = (*reader)->info();
    const ChunkAttributes a{};
    const uint64_t resident = gpu::residentChunkBytes(info, a);
    ASSERT_GT(resident, 0u);
    using gpu::PathStateMemory;
    auto resolve = [&](PathStateMemory asked, bool separate, uint64_t budget) {
        auto r = gpu::resolvePathStateMemory(asked, separate, info, a, budget);
        EXPECT_TRUE(r) << r.message();
        return r ? *r : PathStateMemory::Auto;
    };
    const uint64_t deep = uint64_t(double(resident) / (gpu::kHostStateOversubscription + 1));
    const uint64_t shallow = uint64_t(double(resident) / (gpu::kHostStateOversubscription - 1));
    EXPECT_EQ(resolve(PathStateMemory::Auto, true, deep), PathStateMemory::Host);
    EXPECT_EQ(resolve(PathStateMemory::Auto, true, shallow), PathStateMemory::Device);
    EXPECT_EQ(resolve(PathStateMemory::Auto, false, deep), PathStateMemory::Device) << "one memory: nothing to gain";
    EXPECT_EQ(resolve(PathStateMemory::Host, false, shallow), PathStateMemory::Host) << "asked for";
    EXPECT_EQ(resolve(PathStateMemory::Device, true, deep), PathStateMemory::Device) << "asked for";
    info.volumes.emplace_back();  // the rule reads only whether there are volumes
    EXPECT_EQ(resolve(PathStateMemory::Auto, true, deep), PathStateMemory::Device) << "volumes keep per-path records";
    auto refused = gpu::resolvePathStateMemory(PathStateMemory::Host, true, info, a, deep);
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.message().find("volumes"), std::string::npos) << refused.message();
    const std::pair<const char*, PathStateMemory> names[] = {
        {"auto", PathStateMemory::Auto}, {"device", PathStateMemory::Device}, {"host", PathStateMemory::Host}};
    for (const auto& [name, memory] : names) {
        auto parsed = gpu::parsePathStateMemory(name);
        ASSERT_TRUE(parsed) << name;
        EXPECT_EQ(*parsed, memory) << name;
    }
    EXPECT_FALSE(gpu::parsePathStateMemory("gpu"));
}

// The kernels read and write the path state wherever it lies: an out-of-core render with the
// state in host memory (on lavapipe host-visible memory, counted against the budget) equals the
// in-core render bit for bit, and its figures say where the state was.
TEST(StreamingRender, PathStateInHostMemoryRendersTheInCoreImage) {
    const std::string path = generatedPackage(GeneratorKind::Terrain, 20000, 64 << 10);
    RenderOptions o = smallRender(kAllAovs & ~kAovCost);
    o.samplesPerPixel = 4;
    const uint64_t tight = budgetForSlots(path, 3, o.aovs);
    ASSERT_GT(tight, 0u);
    StreamingStats ample, host, device;
    auto a = renderVulkan(path, o, 256ull << 20, &ample);
    ASSERT_TRUE(a) << a.message();
    EXPECT_EQ(ample.pathStateHostBytes, 0u);
    auto b = renderVulkan(path, o, tight, &host, 1u << 21, true, true, {}, true, {gpu::PathStateMemory::Host, 2048});
    ASSERT_TRUE(b) << b.message();
    expectIdentical(*a, *b, false);
    EXPECT_LT(host.slots, host.chunksTotal);
    EXPECT_GT(host.chunkLoads, host.chunksTouched) << "out of core";
    EXPECT_GT(host.pathStateHostBytes, 0u);
    EXPECT_GT(host.wavePaths, 0u);
    EXPECT_LE(host.wavePaths, 2048u);
    EXPECT_LE(host.peakDeviceBytes, tight);
    auto c = renderVulkan(path, o, tight, &device, 1u << 21, true, true, {}, true, {gpu::PathStateMemory::Device});
    ASSERT_TRUE(c) << c.message();
    expectIdentical(*a, *c, false);
    EXPECT_EQ(device.pathStateHostBytes, 0u);
}

TEST(StreamingRender, WaveShareSplitsAnOutOfCoreBudget) {
    const std::string path = generatedPackage(GeneratorKind::Terrain, 20000, 64 << 10);
    auto reader = PackageReader::open(path);
    ASSERT_TRUE(reader) << reader.message();
    const PackageInfo& info = (*reader)->info();
    const uint64_t budget = budgetForSlots(path, 4, smallRender().aovs);
    auto half = gpu::planPool(info, ChunkAttributes{}, budget);
    auto quarter = gpu::planPool(info, ChunkAttributes{}, budget, true, 0.25);
    ASSERT_TRUE(half && quarter);
    ASSERT_LT(half->slots, info.chunks.size()) << "the test needs an out-of-core budget";
    EXPECT_GT(quarter->slots, half->slots);
    EXPECT_LT(quarter->batchRays, half->batchRays);
    EXPECT_LE(quarter->totalBytes, budget);
    for (double bad : {0.0, 1.0, -0.5, std::nan("")}) {
        auto refused = gpu::planPool(info, ChunkAttributes{}, budget, true, bad);
        ASSERT_FALSE(refused) << bad;
        EXPECT_NE(refused.message().find("share"), std::string::npos) << refused.message();
    }
}

void expectAgreesWithEmbree(const std::string& name, const std::string& path, double minAgreement = 0.9999,
                            double maxRelativeRmse = 0.02) {
    RenderOptions o = smallRender(kAovPrimId);
    o.width = 96, o.height = 80;
    o.samplesPerPixel = 4;
    auto reference = renderEmbree(path, o);
    ASSERT_TRUE(reference) << reference.message();
    StreamingStats s;
    auto streamed = renderVulkan(path, o, 64ull << 20, &s);
    ASSERT_TRUE(streamed) << streamed.message();
    const double agreement = primIdAgreement(*reference, *streamed);
    double se = 0, energy = 0;
    for (size_t i = 0; i < reference->rgb.size(); ++i) {
        const double d = double(reference->rgb[i]) - double(streamed->rgb[i]);
        se += d * d, energy += double(reference->rgb[i]) * reference->rgb[i];
    }
    const double relativeRmse = std::sqrt(se / std::max(energy, 1e-30));
    std::printf("%s: %llu chunks, primid agreement %.6f, beauty relative RMSE %.2e\n", name.c_str(),
                (unsigned long long)s.chunksTotal, agreement, relativeRmse);
    EXPECT_GE(agreement, minAgreement) << name;
    EXPECT_LE(relativeRmse, maxRelativeRmse) << name;
}

TEST(StreamingRender, AgreesWithEmbreeOnGeneratedScenes) {
    expectAgreesWithEmbree("terrain", generatedPackage(GeneratorKind::Terrain, 20000, 64 << 10));
    expectAgreesWithEmbree("soup", generatedPackage(GeneratorKind::Soup, 5000, 32 << 10));
    expectAgreesWithEmbree("sphere", generatedPackage(GeneratorKind::Sphere, 20000, 64 << 10));
    expectAgreesWithEmbree("city", generatedPackage(GeneratorKind::City, 20000, 64 << 10));
}

TEST(StreamingRender, AgreesWithEmbreeOnSharedMeshes) {
    const std::string dir = std::string(VASTRAY_SHARED_DATA) + "/meshes/";
    if (!std::filesystem::exists(dir)) {
        std::printf("note: %s is absent (a user's clone): shared-mesh agreement not checked\n", dir.c_str());
        GTEST_SKIP() << dir << " absent";
    }
    for (const char* mesh : {"stanford-bunny", "fandisk", "teapot", "spot", "suzanne"})
        expectAgreesWithEmbree(mesh, packageFromFile(mesh, dir + mesh + ".obj", 128 << 10));
}

TEST(StreamingRender, BudgetBelowMinimumIsAnErrorStatingIt) {
    const std::string path = generatedPackage(GeneratorKind::Terrain, 20000, 64 << 10);
    auto image = renderVulkan(path, smallRender(), 100 << 10);
    ASSERT_FALSE(image);
    EXPECT_NE(image.message().find("below this scene's minimum of"), std::string::npos) << image.message();
}

TEST(StreamingRender, CorruptChunkIsNamed) {
    const std::string good = generatedPackage(GeneratorKind::Terrain, 20000, 64 << 10);
    const std::string bad = tmpPath("corrupt.vast");
    std::filesystem::copy_file(good, bad, std::filesystem::copy_options::overwrite_existing);
    auto reader = PackageReader::open(bad);
    ASSERT_TRUE(reader);
    const ChunkInfo chunk = (*reader)->info().chunks[1];
    reader->reset();
    {
        std::fstream f(bad, std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(std::streamoff(chunk.offset + chunk.size / 2));
        const char junk[4] = {'\x5a', '\x5a', '\x5a', '\x5a'};
        f.write(junk, 4);
    }
    auto image = renderVulkan(bad, smallRender(), 64ull << 20);
    ASSERT_FALSE(image) << "a damaged chunk must fail the render";
    EXPECT_NE(image.message().find("chunk 1"), std::string::npos) << image.message();
}

// Two squares at z = 0, one facing +z and one facing -z, both single-sided: from either side
// exactly the one facing the camera is seen (docs/GEOMETRY.md); in every backend.
TEST(StreamingRender, CoincidentOppositeFacesPickTheOneFacingTheRay) {
    TriangleMesh mesh;
    mesh.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
    mesh.indices = {0, 1, 2, 0, 2, 3, 0, 2, 1, 0, 3, 2};  // triangles 0,1 face +z; 2,3 face -z
    Material m;
    m.doubleSided = false;
    mesh.materials = {m};
    const std::string path = packageFromMesh("coincident", mesh, 16 << 10);
    for (float side : {1.0f, -1.0f}) {
        RenderOptions o = smallRender(kAovPrimId);
        o.frameScene = false;
        o.camera.eye = {0.1f, 0.2f, 3.0f * side};
        o.camera.target = {0, 0, 0};
        auto image = renderVulkan(path, o, 64ull << 20);
        ASSERT_TRUE(image) << image.message();
        auto reference = renderEmbree(path, o);
        ASSERT_TRUE(reference) << reference.message();
        const uint32_t centre = image->primId[(o.height / 2) * o.width + o.width / 2];
        EXPECT_EQ(centre < 2, side > 0) << "side " << side << " saw primitive " << centre;
        EXPECT_EQ(primIdAgreement(*image, *reference), 1.0);
    }
}

}  // namespace
}  // namespace vastray

namespace vastray {
namespace {

// A scene kept open (the render service keeps one per package): a second render of a scene
// that fits loads and decodes nothing, and gives the same image.
TEST(StreamingRender, SecondRenderOfAnOpenSceneLoadsNothing) {
    const std::string path = generatedPackage(GeneratorKind::Terrain, 20000, 64 << 10);
    auto reader = PackageReader::open(path);
    ASSERT_TRUE(reader) << reader.message();
    const RenderOptions o = smallRender(kAovDepth | kAovPrimId);
    auto scene = StreamingScene::open(**reader, requiredAttributes((*reader)->info(), o), StreamingOptions{},
                                      [&](const PackageInfo& info, const ChunkAttributes& a) {
                                          return gpu::createVulkanChunkBackend(device(), info, a, 64ull << 20);
                                      });
    ASSERT_TRUE(scene) << scene.message();
    StreamingStats first, second;
    auto a = (*scene)->render(o, nullptr, &first);
    ASSERT_TRUE(a) << a.message();
    auto b = (*scene)->render(o, nullptr, &second);
    ASSERT_TRUE(b) << b.message();
    expectIdentical(*a, *b);
    EXPECT_GT(first.chunkLoads, 0u);
    EXPECT_EQ(second.chunkLoads, 0u);
    EXPECT_EQ(second.decodes, 0u);
    EXPECT_EQ(second.bytesRead, 0u);
    EXPECT_EQ(second.chunksTouched, first.chunksTouched);
    // A render needing an attribute the scene was opened without is refused, not wrong.
    RenderOptions more = o;
    more.aovs = kAovDepth;
    EXPECT_TRUE((*scene)->render(more));
    auto scene2 = StreamingScene::open(**reader, ChunkAttributes{}, StreamingOptions{},
                                       [&](const PackageInfo& info, const ChunkAttributes& a) {
                                           return gpu::createVulkanChunkBackend(device(), info, a, 64ull << 20);
                                       });
    ASSERT_TRUE(scene2);
    EXPECT_FALSE((*scene2)->render(o)) << "primid needs primitive ids the scene was opened without";
}

// The bytes this process has read through read()/pread() so far (/proc/self/io's rchar: the
// chunk reads of decode workers, whether the file is in the page cache or not), less what
// reading /proc/self/io itself has read (`own`, which this adds to).
uint64_t bytesReadByThisProcess(uint64_t& own) {
    std::ifstream io("/proc/self/io");
    const std::string text((std::istreambuf_iterator<char>(io)), std::istreambuf_iterator<char>());
    own += text.size();
    std::istringstream fields(text);
    std::string key;
    uint64_t value = 0;
    while (fields >> key >> value)
        if (key == "rchar:") return value - own;
    return 0;
}

// StreamingOptions::decodeOnOpen (the CLI's): the chunks are read and decoded while the backend
// factory runs (there the CLI waits for its device), the first render counts those decodes, and
// the image is the one a scene opened without it renders.
TEST(StreamingRender, DecodeOnOpenDecodesWhileTheFactoryWaits) {
    const std::string path = generatedPackage(GeneratorKind::Terrain, 20000, 64 << 10);
    auto reader = PackageReader::open(path);
    ASSERT_TRUE(reader) << reader.message();
    const PackageInfo& info = (*reader)->info();
    ASSERT_GT(info.chunks.size(), 1u);
    uint64_t chunkBytes = 0;
    for (const ChunkInfo& c : info.chunks) chunkBytes += c.size;
    const RenderOptions o = smallRender(kAovDepth | kAovPrimId);
    StreamingOptions early;
    early.decodeOnOpen = true;
    bool sawReads = false;
    uint64_t own = 0;
    const uint64_t before = bytesReadByThisProcess(own);
    auto scene = StreamingScene::open(**reader, requiredAttributes(info, o), early,
                                      [&](const PackageInfo& i, const ChunkAttributes& a) {
                                          // Wait (at most 30 s) for the workers to read every chunk.
                                          const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
                                          while (!(sawReads = bytesReadByThisProcess(own) - before >= chunkBytes) &&
                                                 std::chrono::steady_clock::now() < deadline)
                                              std::this_thread::sleep_for(std::chrono::milliseconds(2));
                                          return gpu::createVulkanChunkBackend(device(), i, a, 64ull << 20);
                                      });
    ASSERT_TRUE(scene) << scene.message();
    EXPECT_TRUE(sawReads) << "the chunks were not read while the factory waited";
    StreamingStats first, second;
    auto a = (*scene)->render(o, nullptr, &first);
    ASSERT_TRUE(a) << a.message();
    EXPECT_EQ(first.decodes, info.chunks.size()) << "the decodes done before the render are its own";
    EXPECT_EQ(first.bytesRead, chunkBytes);
    auto b = (*scene)->render(o, nullptr, &second);
    ASSERT_TRUE(b) << b.message();
    EXPECT_EQ(second.decodes, 0u);

    auto plain = StreamingScene::open(**reader, requiredAttributes(info, o), StreamingOptions{},
                                      [&](const PackageInfo& i, const ChunkAttributes& c) {
                                          return gpu::createVulkanChunkBackend(device(), i, c, 64ull << 20);
                                      });
    ASSERT_TRUE(plain) << plain.message();
    auto c = (*plain)->render(o);
    ASSERT_TRUE(c) << c.message();
    expectIdentical(*a, *c);
}

// import --resident-bytes-per-triangle (default 32): the chunk trees are cut shallower until
// each chunk's device footprint fits (or the depth floor is reached); the image is the same as
// with no cap (0), only the work per ray and the partition (more triangles fit a chunk) change.
TEST(StreamingRender, ResidentByteCapKeepsTheImage) {
    GenerateOptions generate;
    generate.kind = GeneratorKind::City;
    generate.triangles = 30000;
    const std::string ply = tmpPath("city-cap.ply");
    ASSERT_TRUE(generateToPly(generate, ply));
    auto imported = importMesh(ply);
    ASSERT_TRUE(imported) << imported.message();
    const std::string uncapped = tmpPath("city-cap-none.vast"), path = tmpPath("city-cap-25.vast");
    PackageBuildOptions options;
    options.chunkSizeBytes = 64 << 10;
    options.progress = Progress::Mode::None;
    options.residentBytesPerTriangle = 0;
    ASSERT_TRUE(buildPackage(imported->mesh, uncapped, options));
    options.residentBytesPerTriangle = 25;
    ASSERT_TRUE(buildPackage(imported->mesh, path, options));
    auto bytesPerTriangle = [](const std::string& package) {
        auto reader = PackageReader::open(package);
        EXPECT_TRUE(reader) << reader.message();
        double worst = 0;
        const bool packed = (*reader)->info().grid.packsPositions();
        for (const ChunkInfo& c : (*reader)->info().chunks)
            worst = std::max(worst, double(c.bvhNodeCount * sizeof(Bvh4Node) + devicePositionBytes(c.vertexCount, packed) +
                                           deviceIndexBytes(c.triangleCount, (c.flags & kChunkIndexDeltas16) != 0,
                                                            c.longTriangles)) /
                                        c.triangleCount);
        return worst;
    };
    EXPECT_GT(bytesPerTriangle(uncapped), 25.0) << "the city's trees must need larger leaves for this test to mean anything";
    EXPECT_LE(bytesPerTriangle(path), 25.0);
    const RenderOptions o = smallRender(kAllAovs);
    auto a = renderVulkan(uncapped, o, 64ull << 20);
    ASSERT_TRUE(a) << a.message();
    auto b = renderVulkan(path, o, 64ull << 20);
    ASSERT_TRUE(b) << b.message();
    EXPECT_TRUE(sameBits(a->rgb, b->rgb)) << "beauty differs";
    EXPECT_TRUE(sameBits(a->depth, b->depth)) << "depth differs";
    EXPECT_TRUE(sameBits(a->normal, b->normal)) << "normal differs";
    EXPECT_TRUE(sameBits(a->primId, b->primId)) << "primid differs";
}

// The same package with its indices in 8 bytes a triangle (format 16, kChunkIndexDeltas16) and
// in 12 (laid out as format 15, which has no flags): the same trees and hits, so the same image
// bit for bit, streamed through two slots each, in smaller slots with the flag.
TEST(StreamingRender, IndicesInEightBytesRenderLikeTwelve) {
    const std::string path = generatedPackage(GeneratorKind::City, 20000, 64 << 10);
    const std::string old = tmpPath("city-indices-twelve.vast");
    test::writeBytes(old, test::withoutChunkFlags(test::fileBytes(path)));
    auto compact = PackageReader::open(path);
    ASSERT_TRUE(compact) << compact.message();
    auto full = PackageReader::open(old);
    ASSERT_TRUE(full) << full.message();
    ASSERT_EQ((*full)->info().formatVersion, 15u);
    const ChunkAttributes attributes{};
    for (const ChunkInfo& c : (*compact)->info().chunks) {
        ASSERT_EQ(c.flags, kChunkIndexDeltas16) << "chunk " << c.id;
        const ChunkInfo& twelve = (*full)->info().chunks[c.id];
        EXPECT_EQ(twelve.flags, 0u);
        EXPECT_LE(chunkLayout(c, attributes).totalBytes + 4ull * c.triangleCount,
                  chunkLayout(twelve, attributes).totalBytes + 16);  // (16-byte aligned sections)
    }
    const RenderOptions o = smallRender(kAllAovs);
    StreamingStats cs, fs;
    auto a = renderVulkan(path, o, budgetForSlots(path, 2, o.aovs), &cs);
    ASSERT_TRUE(a) << a.message();
    auto b = renderVulkan(old, o, budgetForSlots(old, 2, o.aovs), &fs);
    ASSERT_TRUE(b) << b.message();
    EXPECT_GT(cs.chunkLoads, cs.chunksTouched) << "the render should have streamed";
    EXPECT_EQ(cs.chunkLoads, fs.chunkLoads);
    EXPECT_LT(cs.bytesUploaded, fs.bytesUploaded);
    expectIdentical(*a, *b);
}

// The bowl under two large triangles (tests/BowlMesh.h), whose vertex indices lie further apart
// than 16-bit offsets reach: the walk reads them as long triangles (kSlotLongTriangle), they are
// hit, and the image equals the same package's with 12-byte indices (format 15) bit for bit and
// agrees with Embree's.
TEST(StreamingRender, LongTrianglesOfEightByteIndicesAreHit) {
    const std::string path = packageFromMesh("bowl-long-triangles", test::bowlUnderLongTriangles(), 64 << 20);
    const std::string old = tmpPath("bowl-long-triangles-twelve.vast");
    test::writeBytes(old, test::withoutChunkFlags(test::fileBytes(path)));
    auto reader = PackageReader::open(path);
    ASSERT_TRUE(reader) << reader.message();
    ASSERT_EQ((*reader)->info().chunks.size(), 1u);
    EXPECT_GE((*reader)->info().chunks[0].longTriangles, 1u) << "the large triangles must be long for this test to mean anything";
    RenderOptions o = smallRender(kAllAovs);
    o.frameScene = false;
    o.camera = {{0.3f, -0.2f, 6.0f}, {0, 0, 1}, {0, 1, 0}, 45.0f};
    auto a = renderVulkan(path, o, 256ull << 20);
    ASSERT_TRUE(a) << a.message();
    auto b = renderVulkan(old, o, 256ull << 20);
    ASSERT_TRUE(b) << b.message();
    expectIdentical(*a, *b);
    uint64_t lidPixels = 0, slantPixels = 0;
    for (uint32_t id : a->primId) lidPixels += id == test::kBowlLid, slantPixels += id == test::kBowlSlant;
    EXPECT_GT(lidPixels, 100u);
    EXPECT_GT(slantPixels, 20u);
    auto reference = renderEmbree(path, o);
    ASSERT_TRUE(reference) << reference.message();
    expectAgrees(*a, *reference);
}

// A render of `path` with positions packed in 8 bytes a vertex or as 3 floats (the package's grid
// packs them: ChunkAttributes::packedPositions), at `budget`.
Result<RenderImage> renderPositions(const std::string& path, const RenderOptions& o, uint64_t budget, bool packed,
                                    StreamingStats* stats) {
    auto reader = PackageReader::open(path);
    if (!reader) return reader.status();
    stats->memoryBudgetBytes = budget;
    return renderStreaming(
        **reader, o, StreamingOptions{},
        [&](const PackageInfo& info, const ChunkAttributes& a) {
            EXPECT_TRUE(a.packedPositions) << "the import's grid packs positions";
            ChunkAttributes asked = a;
            asked.packedPositions = packed;
            return gpu::createVulkanChunkBackend(device(), info, asked, budget);
        },
        nullptr, stats);
}

// Positions in 8 bytes a vertex (the grid coordinates; the walk rebuilds the floats in fp32)
// render the image of 3 floats a vertex bit for bit, in core and streamed through two slots,
// with 4 bytes a vertex fewer uploaded; and equal to Embree's, which reads the decoded floats.
TEST(StreamingRender, PackedPositionsRenderLikeFloats) {
    const std::string path = generatedPackage(GeneratorKind::City, 20000, 64 << 10);
    auto reader = PackageReader::open(path);
    ASSERT_TRUE(reader) << reader.message();
    ASSERT_TRUE((*reader)->info().grid.packsPositions());
    uint64_t vertices = 0;
    for (const ChunkInfo& c : (*reader)->info().chunks) vertices += c.vertexCount;
    const RenderOptions o = smallRender(kAllAovs);
    StreamingStats packedIn, floatsIn, packedOut, floatsOut;
    auto a = renderPositions(path, o, 256ull << 20, true, &packedIn);
    ASSERT_TRUE(a) << a.message();
    auto b = renderPositions(path, o, 256ull << 20, false, &floatsIn);
    ASSERT_TRUE(b) << b.message();
    expectIdentical(*a, *b);
    EXPECT_EQ(packedIn.chunkLoads, floatsIn.chunkLoads);
    EXPECT_EQ(packedIn.chunkLoads, (*reader)->info().chunks.size()) << "in core: each chunk once";
    EXPECT_EQ(floatsIn.bytesUploaded - packedIn.bytesUploaded, 4 * vertices);
    const uint64_t tight = budgetForSlots(path, 2, o.aovs);
    ASSERT_GT(tight, 0u);
    auto c = renderPositions(path, o, tight, true, &packedOut);
    ASSERT_TRUE(c) << c.message();
    auto d = renderPositions(path, o, tight, false, &floatsOut);
    ASSERT_TRUE(d) << d.message();
    EXPECT_GT(packedOut.chunkLoads, packedOut.chunksTouched) << "the render should have streamed";
    expectIdentical(*c, *a, false);  // (the cost AOV counts the work done, more out of core)
    expectIdentical(*d, *a, false);
    auto reference = renderEmbree(path, o);
    ASSERT_TRUE(reference) << reference.message();
    expectAgrees(*a, *reference);
}

// A package whose grid cannot pack positions (more than 20 bits) renders with 3 floats a vertex;
// a backend asked to pack them for it refuses, saying why; a hand-made chunk with a vertex off
// the grid is refused before it reaches the device.
TEST(StreamingRender, PositionsPackOnlyOnTheirGrid) {
    auto generated = generateMesh({GeneratorKind::City, 6000, 1});
    ASSERT_TRUE(generated) << generated.message();
    const std::string path = tmpPath("city-6000-22-bits.vast");
    PackageBuildOptions options;
    options.chunkSizeBytes = 64 << 10;
    options.quantizeBits = 22;
    options.progress = Progress::Mode::None;
    ASSERT_TRUE(buildPackage(std::move(generated).value(), path, options));
    auto reader = PackageReader::open(path);
    ASSERT_TRUE(reader) << reader.message();
    const PackageInfo& info = (*reader)->info();
    EXPECT_FALSE(info.grid.packsPositions());
    const RenderOptions o = smallRender(kAovPrimId);
    EXPECT_FALSE(requiredAttributes(info, o).packedPositions);
    auto image = renderVulkan(path, o, 256ull << 20);
    ASSERT_TRUE(image) << image.message();
    auto reference = renderEmbree(path, o);
    ASSERT_TRUE(reference) << reference.message();
    expectAgrees(*image, *reference);
    ChunkAttributes packed{};
    packed.packedPositions = true;
    auto refused = gpu::createVulkanChunkBackend(device(), info, packed, 64ull << 20);
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.message().find("22 bits) does not allow them"), std::string::npos) << refused.message();

    const std::string city = generatedPackage(GeneratorKind::City, 20000, 64 << 10);
    auto cityReader = PackageReader::open(city);
    ASSERT_TRUE(cityReader) << cityReader.message();
    auto backend = gpu::createVulkanChunkBackend(device(), (*cityReader)->info(), packed, 64ull << 20);
    ASSERT_TRUE(backend) << backend.message();
    auto chunk = (*cityReader)->readChunk(1);
    ASSERT_TRUE(chunk) << chunk.message();
    DecodedChunk made = std::move(chunk).value();
    made.validated = false;
    EXPECT_TRUE((*backend)->load(0, made, {}).isOk()) << "its vertices lie on the grid";
    made.id = 3;
    made.positions[4].y = std::nextafter(made.positions[4].y, 1e30f);
    const Status offGrid = (*backend)->load(1, made, {});
    ASSERT_FALSE(offGrid.isOk());
    EXPECT_NE(offGrid.message().find("chunk 3: vertex 4 does not lie on the package's grid"), std::string::npos)
        << offGrid.message();
}

// The Vulkan backend checks a chunk the package reader did not (a hand-made one) before any
// of it reaches the device; the reader's chunks come checked and load as they are.
TEST(StreamingRender, BackendRefusesAnUncheckedChunkWithBadIndices) {
    const std::string path = generatedPackage(GeneratorKind::Terrain, 20000, 64 << 10);
    auto reader = PackageReader::open(path);
    ASSERT_TRUE(reader) << reader.message();
    const ChunkAttributes attributes{};
    auto backend = gpu::createVulkanChunkBackend(device(), (*reader)->info(), attributes, 64ull << 20);
    ASSERT_TRUE(backend) << backend.message();
    auto chunk = (*reader)->readChunk(2);
    ASSERT_TRUE(chunk) << chunk.message();
    EXPECT_TRUE(chunk->validated) << "the reader checks every index, reference and node";
    EXPECT_TRUE((*backend)->load(0, *chunk, {}).isOk());
    DecodedChunk made = std::move(chunk).value();
    made.id = 5;
    made.validated = false;
    made.indices[7] = uint32_t(made.positions.size());
    const Status refused = (*backend)->load(1, made, {});
    ASSERT_FALSE(refused.isOk());
    EXPECT_NE(refused.message().find("chunk 5: index 7"), std::string::npos) << refused.message();
}

// A lone two-triangle square of half-size 700 seen from above: nothing can occlude a point of
// it, so ambient occlusion is exactly 1 in every pixel (misses see the sky: 1 too). Before
// bounce rays refused hits within t's rounding error, 13.5 % of them re-hit their own square
// (the error of t grows with the vertices' distance from the ray origin, not with the offset).
// A scene lit by emissive triangles with the sun off: the shading kernel specialized for
// emission and no sun (Wavefront.cpp) agrees with Embree, and out of core equals in core.
TEST(StreamingRender, EmittersWithoutSunAgreeWithEmbreeAndStreamTheSame) {
    auto generated = generateMesh({GeneratorKind::City, 20000, 1});
    ASSERT_TRUE(generated) << generated.message();
    TriangleMesh mesh = std::move(generated).value();
    Material lamp{"lamp"};
    lamp.baseColor = {0.2f, 0.2f, 0.2f, 1.0f};
    lamp.emissive = {4.0f, 3.0f, 2.0f};
    mesh.materials = {Material{"stone"}, lamp};
    mesh.materialIds.resize(mesh.triangleCount());
    for (uint64_t t = 0; t < mesh.triangleCount(); ++t) mesh.materialIds[t] = t % 7 == 0 ? 1u : 0u;
    const std::string path = packageFromMesh("city-lamps", std::move(mesh), 64 << 10);
    RenderOptions o = smallRender(kAovPrimId);
    o.environment.sunIrradiance = {0, 0, 0};
    o.environment.zenith = {0, 0, 0}, o.environment.horizon = {0, 0, 0}, o.environment.ground = {0, 0, 0};
    auto reference = renderEmbree(path, o);
    ASSERT_TRUE(reference) << reference.message();
    auto ample = renderVulkan(path, o, 256ull << 20);
    ASSERT_TRUE(ample) << ample.message();
    expectAgrees(*ample, *reference);
    double energy = 0;
    for (float v : ample->rgb) energy += v;
    EXPECT_GT(energy, 0.0) << "the emitters light the image (the sky and the sun are black)";
    const uint64_t tight = budgetForSlots(path, 2, o.aovs);
    ASSERT_GT(tight, 0u);
    auto streamed = renderVulkan(path, o, tight);
    ASSERT_TRUE(streamed) << streamed.message();
    expectIdentical(*ample, *streamed, false);
}

TEST(StreamingRender, LoneLargeSquareNeverOccludesItself) {
    for (float half : {100.0f, 700.0f, 5000.0f}) {
        TriangleMesh square;
        square.positions = {{-half, 0, -half}, {half, 0, -half}, {half, 0, half}, {-half, 0, half}};
        square.indices = {0, 1, 2, 0, 2, 3};
        square.materials.push_back(Material{"ground"});
        const std::string path = packageFromMesh("square-" + std::to_string(int(half)), square, 64 << 10);
        RenderOptions o = smallRender(kAovNone);
        o.integrator = IntegratorKind::AmbientOcclusion;
        o.width = 64, o.height = 48, o.samplesPerPixel = 16;
        o.frameScene = false;
        o.camera.eye = {0.3f * half, 0.2f * half, 0.4f * half};
        o.camera.target = {0, 0, 0};
        auto image = renderVulkan(path, o, 64ull << 20);
        ASSERT_TRUE(image) << image.message();
        uint64_t dark = 0;
        for (float v : image->rgb) dark += v != 1.0f;
        EXPECT_EQ(dark, 0u) << "half-size " << half << ": pixel channels below 1 (self-occlusion)";
    }
}

// An open scene that fits: the second render finds every chunk resident, records each tile's
// kernels into one submission, loads nothing, and gives the cold render's image bit for bit;
// what comes back from the device is the image and its AOVs plus a few counters per stream.
TEST(StreamingRender, ResidentRenderEqualsColdRenderAndReadsBackOnlyTheImage) {
    for (GeneratorKind kind : {GeneratorKind::City, GeneratorKind::Terrain}) {
        const std::string path = generatedPackage(kind, 20000, 64 << 10);
        for (IntegratorKind integrator : {IntegratorKind::Path, IntegratorKind::AmbientOcclusion}) {
            RenderOptions o = smallRender(kAllAovs);
            o.integrator = integrator;
            StreamingStats cold, warm;
            RenderStats warmRender;
            auto renders = test::renderVulkanColdAndWarm(path, o, 64ull << 20, &cold, &warm, &warmRender);
            ASSERT_TRUE(renders) << renders.message();
            SCOPED_TRACE(integrator == IntegratorKind::Path ? "path" : "ao");
            expectIdentical(renders->first, renders->second, false);
            EXPECT_GT(cold.chunksTotal, 4u);
            EXPECT_EQ(warm.chunkLoads, 0u);
            EXPECT_EQ(warm.chunksTouched, cold.chunksTouched);
            EXPECT_GT(warmRender.rays, uint64_t(o.width) * o.height * o.samplesPerPixel);
            EXPECT_EQ(warm.submits, 1u) << "one tile, one submission";
            // One pass per stream in core: the AOV rays' stream, then one per bounce (ao: the
            // camera rays and the occlusion rays); out of core more, one per paging step.
            const uint64_t streams = 1 + (integrator == IntegratorKind::Path ? o.maxDepth + 1 : 2);
            EXPECT_EQ(warm.walkPasses, streams);
            EXPECT_GT(cold.walkPasses, streams) << "the cold render paged chunks in between passes";
            EXPECT_GT(cold.pipelineSeconds, 0.0) << "the cold render created its walk and shade kernels";
            EXPECT_EQ(warm.pipelineSeconds, 0.0) << "the warm render created a pipeline again";
            // rgb + alpha, depth, normal, albedo, primid, chunkid, cost: 4 + 4 + 4 + 12 + 12 + 4 + 4 + 8
            // bytes per pixel (colour comes back as RGBA), plus touched flags and the ray counter.
            const uint64_t image = uint64_t(o.width) * o.height * (16 + 4 + 12 + 12 + 4 + 4 + 8);
            EXPECT_GE(warm.deviceToHostBytes, image);
            EXPECT_LE(warm.deviceToHostBytes, image + 4 * warm.chunksTotal + 64) << "per-ray data came back";
            EXPECT_LT(warm.hostToDeviceBytes, 4096u + 8 * warm.chunksTotal);
        }
    }
}

}  // namespace
}  // namespace vastray

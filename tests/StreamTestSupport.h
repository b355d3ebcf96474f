#pragma once
// Renders through the streaming renderer and the Embree reference for tests (stream_tests and
// stress_tests): one Vulkan device per binary, budgets that give an exact slot count.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>

#include "TestTmp.h"
#include "vastray/core/EnvironmentMap.h"
#include "vastray/core/RenderImage.h"
#include "vastray/core/RenderOptions.h"
#include "vastray/cpu/EmbreeRenderer.h"
#include "vastray/cpu/RenderScene.h"
#include "vastray/gpu/VulkanChunkBackend.h"
#include "vastray/gpu/VulkanDevice.h"
#include "vastray/streamer/Generate.h"
#include "vastray/streamer/PackageBuilder.h"
#include "vastray/streamer/ScenePackage.h"
#include "vastray/streamer/StreamingRenderer.h"

namespace vastray::test {

// `mesh`'s package NAME.vast in the test folder `folder`, cut into chunks of `chunkBytes`.
inline std::string meshPackage(const std::string& folder, const std::string& name, TriangleMesh mesh,
                               uint64_t chunkBytes = 64 << 10) {
    const std::filesystem::path dir = testTmpDir(folder);
    std::filesystem::create_directories(dir);
    const std::string path = (dir / (name + ".vast")).string();
    PackageBuildOptions options;
    options.chunkSizeBytes = chunkBytes;
    options.progress = Progress::Mode::None;
    auto report = buildPackage(std::move(mesh), path, options);
    EXPECT_TRUE(report) << report.message();
    return path;
}

// A generated mesh's package NAME.vast in the test folder `folder` (64 KiB chunks); `material`
// (when given) replaces every material, their names kept.
inline std::string generatedMaterialPackage(const std::string& folder, const std::string& name, GeneratorKind kind,
                                            uint64_t triangles, const Material* material = nullptr) {
    auto mesh = generateMesh({kind, triangles, 1});
    EXPECT_TRUE(mesh) << mesh.message();
    if (!mesh) return {};
    if (material)
        for (Material& m : mesh->materials) {
            const std::string kept = m.name;
            m = *material;
            m.name = kept;
        }
    return meshPackage(folder, name, std::move(mesh).value());
}

// One device for the whole binary (a Vulkan instance per test costs ~0.1 s on lavapipe). These
// tests run on lavapipe in CI: no usable device is a failure, never a skip.
inline gpu::VulkanDevice& sharedVulkanDevice() {
    static std::unique_ptr<gpu::VulkanDevice> d = [] {
        auto created = gpu::VulkanDevice::create();
        if (!created) {
            ADD_FAILURE() << "no usable Vulkan device: " << created.message();
            std::abort();
        }
        return std::move(created).value();
    }();
    return *d;
}

// One streaming render of a package through the Vulkan backend with this budget.
inline Result<RenderImage> renderVulkan(const std::string& path, const RenderOptions& options, uint64_t budget,
                                        StreamingStats* stats = nullptr, uint32_t maxPathsPerWave = 1u << 21,
                                        bool overlapLoads = true, bool prefetchScene = true,
                                        const gpu::ChunkUploadOptions& upload = {}, bool streamWaves = true,
                                        const gpu::PathStateOptions& pathState = {}, uint32_t windowTiles = 0,
                                        bool partialResidency = true, bool restartInShade = true) {
    auto reader = PackageReader::open(path);
    if (!reader) return reader.status();
    StreamingOptions streaming;
    streaming.maxPathsPerWave = maxPathsPerWave;
    streaming.overlapLoads = overlapLoads;
    streaming.prefetchScene = prefetchScene;
    streaming.streamWaves = streamWaves;
    streaming.windowTiles = windowTiles;
    streaming.partialResidency = partialResidency;
    streaming.restartInShade = restartInShade;
    StreamingStats local;
    StreamingStats& s = stats ? *stats : local;
    s.memoryBudgetBytes = budget;
    return renderStreaming(
        **reader, options, streaming,
        [&](const PackageInfo& info, const ChunkAttributes& a) {
            return gpu::createVulkanChunkBackend(sharedVulkanDevice(), info, a, budget, gpu::kWaveShareOutOfCore,
                                                 upload, gpu::environmentBytes(options.environment) + gpu::volumeReserveBytes(info, budget),
                                                 pathState);
        },
        nullptr, &s);
}

// Two renders of one open scene at this budget: the first pages the chunks in between walk
// passes, the second finds every chunk resident (in core) or pages again (out of core).
// Returns both images.
inline Result<std::pair<RenderImage, RenderImage>> renderVulkanColdAndWarm(const std::string& path,
                                                                           const RenderOptions& options, uint64_t budget,
                                                                           StreamingStats* cold, StreamingStats* warm,
                                                                           RenderStats* warmRender = nullptr) {
    auto reader = PackageReader::open(path);
    if (!reader) return reader.status();
    auto scene = StreamingScene::open(**reader, requiredAttributes((*reader)->info(), options), StreamingOptions{},
                                      [&](const PackageInfo& info, const ChunkAttributes& a) {
                                          return gpu::createVulkanChunkBackend(sharedVulkanDevice(), info, a, budget);
                                      });
    if (!scene) return scene.status();
    cold->memoryBudgetBytes = warm->memoryBudgetBytes = budget;
    auto first = (*scene)->render(options, nullptr, cold);
    if (!first) return first.status();
    auto second = (*scene)->render(options, warmRender, warm);
    if (!second) return second.status();
    return std::make_pair(std::move(first).value(), std::move(second).value());
}

// sqrt(sum (a - b)^2 / sum b^2): the error of image a against reference b, relative to b's energy.
// A lat-long environment map of w x h texels, every one (r, g, b).
inline std::shared_ptr<const EnvironmentMap> constantEnvironmentMap(const std::string& name, uint32_t w, uint32_t h,
                                                                    float r, float g, float b) {
    const size_t texels = size_t(w) * h;
    auto map = makeEnvironmentMap(name, w, h, std::vector<float>(texels, r), std::vector<float>(texels, g),
                                  std::vector<float>(texels, b));
    EXPECT_TRUE(map) << map.message();
    return map ? *map : nullptr;
}

inline double relativeRmse(const std::vector<float>& a, const std::vector<float>& b) {
    double se = 0, energy = 0;
    for (size_t i = 0; i < b.size(); ++i) {
        const double d = double(a[i]) - double(b[i]);
        se += d * d, energy += double(b[i]) * b[i];
    }
    return std::sqrt(se / std::max(energy, 1e-30));
}

// The mean of an image's channel 0 over its pixels, and its standard error from their spread
// (noise and the image's own variation both count: a loose bound for an image that varies).
struct Mean {
    double mean = 0, standardError = 0;
};
inline Mean pixelMean(const RenderImage& image) {
    const size_t n = image.rgb.size() / 3;
    double sum = 0, squares = 0;
    for (size_t i = 0; i < n; ++i) sum += image.rgb[3 * i], squares += double(image.rgb[3 * i]) * image.rgb[3 * i];
    const double mean = sum / double(n);
    return {mean, std::sqrt(std::max(0.0, squares / double(n) - mean * mean) / double(n))};
}

// The Embree reference of the same package (without the streaming-only AOVs).
inline Result<RenderImage> renderEmbree(const std::string& path, RenderOptions options) {
    auto scene = loadRenderScene(path);
    if (!scene) return scene.status();
    options.aovs &= ~kAovStreamingOnly;
    return renderWithEmbree(*scene, options);
}

// The smallest budget (in 4 KiB steps) that gives exactly `slots` chunk slots to a render with
// these AOVs, or 0 (also when the package has fewer chunks than that). stagingInDeviceMemory:
// the staging bytes DMA uploads ask for where their staging area is device memory (lavapipe).
inline uint64_t budgetForSlots(const std::string& path, uint32_t slots, uint32_t aovs,
                               uint64_t stagingInDeviceMemory = 0, uint64_t reservedBytes = 0) {
    auto reader = PackageReader::open(path);
    if (!reader) return 0;
    RenderOptions options;
    options.aovs = aovs;
    const ChunkAttributes a = requiredAttributes((*reader)->info(), options);
    if ((*reader)->info().chunks.size() < slots) return 0;  // never that many slots
    auto minimum = gpu::planPool((*reader)->info(), a, 1ull << 40, true, gpu::kWaveShareOutOfCore, stagingInDeviceMemory,
                                 reservedBytes);
    if (!minimum) return 0;
    for (uint64_t budget = minimum->minimumBytes;; budget += 4 * 1024) {
        auto plan = gpu::planPool((*reader)->info(), a, budget, true, gpu::kWaveShareOutOfCore, stagingInDeviceMemory,
                                  reservedBytes);
        if (plan && plan->slots >= slots) return plan->slots == slots ? budget : 0;
    }
}

// Renders again with exactly two chunk slots (and `reservedBytes` kept for a map or volumes):
// the image must equal `inCore` bit for bit, with more chunk loads than the package's
// `chunks` and the device bytes within the budget.
inline void expectTwoSlotRenderEquals(const std::string& path, const RenderOptions& options, uint64_t reservedBytes,
                                      const RenderImage& inCore, uint64_t chunks) {
    const uint64_t tight = budgetForSlots(path, 2, options.aovs, 0, reservedBytes);
    ASSERT_GT(tight, 0u);
    StreamingStats stats;
    auto streamed = renderVulkan(path, options, tight, &stats);
    ASSERT_TRUE(streamed) << streamed.message();
    EXPECT_GT(stats.chunkLoads, chunks) << "two slots page chunks in more than once";
    EXPECT_LE(stats.peakDeviceBytes, tight);
    EXPECT_EQ(std::memcmp(streamed->rgb.data(), inCore.rgb.data(), inCore.rgb.size() * 4), 0);
}

}  // namespace vastray::test

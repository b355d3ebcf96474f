#include "vastray/cpu/EmbreeRenderer.h"

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <chrono>
#include <limits>
#include <memory>
#include <optional>

#include "Integrators.h"
#include "vastray/core/Volume.h"
#include "vastray/core/VecMath.h"

namespace vastray {
namespace {

constexpr uint32_t kTileSize = 16;
using Clock = std::chrono::steady_clock;

struct Tile {
    uint32_t x0, y0, x1, y1;
};

// Tile `index` of the region `b`, in frame pixels.
Tile tileAt(uint32_t index, const PixelBounds& b) {
    const uint32_t tilesX = (b.width() + kTileSize - 1) / kTileSize;
    const uint32_t x0 = b.x0 + (index % tilesX) * kTileSize, y0 = b.y0 + (index / tilesX) * kTileSize;
    return {x0, y0, std::min(x0 + kTileSize, b.x1), std::min(y0 + kTileSize, b.y1)};
}

// The AOVs come from one unjittered ray through the pixel centre, so they are exact
// rather than averaged over samples (a primid cannot be averaged).
void shadeAovs(const ShadingContext& context, const Ray& ray, uint32_t framePixel, uint64_t pixel, RenderImage& image,
               uint64_t& rays) {
    SceneHit hit;
    ++rays;
    // Keyed as the device keys its AOV rays: the pixel, sample 0, bounce 0.
    const uint32_t alphaBase = alphaRayBase({framePixel, 0, 0}, false, context.options.seed);
    if (!context.scene.intersect(ray, std::numeric_limits<float>::infinity(), &hit, alphaBase)) return;
    const SurfacePoint point = surfaceAt(context, hit, ray.direction, {0.0f, context.cameraSpread});
    if (image.aovs & kAovDepth) image.depth[pixel] = hit.t;
    if (image.aovs & kAovNormal)
        for (int c = 0; c < 3; ++c) image.normal[3 * pixel + c] = point.shadingNormal[c];
    if (image.aovs & kAovAlbedo)
        for (int c = 0; c < 3; ++c) image.albedo[3 * pixel + c] = point.albedo[c];
    if (image.aovs & kAovPrimId) image.primId[pixel] = hit.triangle;
    if ((image.aovs & kAovUv) && !context.mesh.uvs.empty()) {
        const uint32_t* corners = &context.mesh.indices[3 * size_t(hit.triangle)];
        const std::array<float, 2> uv = interpolateUv(context.mesh.uvs[corners[0]], context.mesh.uvs[corners[1]],
                                                      context.mesh.uvs[corners[2]], hit.u, hit.v);
        image.uv[2 * pixel] = uv[0], image.uv[2 * pixel + 1] = uv[1];
    }
}

// Frame pixel (x, y): its random numbers are keyed by its index in the frame, whatever part of
// the frame the image holds, so a region's pixels equal the whole frame's bit for bit.
void renderPixel(const ShadingContext& context, const CameraRays& camera, uint32_t x, uint32_t y,
                 RenderImage& image, uint64_t& rays) {
    const RenderOptions& options = context.options;
    const uint32_t framePixel = y * options.width + x;
    const uint64_t pixel = uint64_t(y - image.originY) * image.width + (x - image.originX);
    double sum[3] = {0, 0, 0};
    uint32_t hits = 0;
    for (uint32_t sample = 0; sample < options.samplesPerPixel; ++sample) {
        const RandomKey key{framePixel, sample, 0};
        const Ray ray = camera.primary(x, y, randomFloat(key, kDimPixelX, options.seed),
                                       randomFloat(key, kDimPixelY, options.seed));
        const SampleResult s = options.integrator == IntegratorKind::Path
                                   ? tracePath(context, ray, key, rays)
                                   : traceAmbientOcclusion(context, ray, key, rays);
        for (int c = 0; c < 3; ++c) sum[c] += s.radiance[c];
        hits += s.cameraRayHit;
    }
    for (int c = 0; c < 3; ++c) image.rgb[3 * pixel + c] = float(sum[c] / options.samplesPerPixel);
    image.alpha[pixel] = float(double(hits) / options.samplesPerPixel);
    if (image.aovs != kAovNone) shadeAovs(context, camera.primary(x, y, 0.5f, 0.5f), framePixel, pixel, image, rays);
}

uint64_t renderTiles(const ShadingContext& context, const CameraRays& camera, RenderImage& image,
                     const RenderProgress& progress) {
    const PixelBounds bounds = renderBounds(context.options);
    const uint32_t tilesX = (bounds.width() + kTileSize - 1) / kTileSize;
    const uint32_t tileCount = tilesX * ((bounds.height() + kTileSize - 1) / kTileSize);
    std::atomic<uint64_t> rays{0}, tilesDone{0};
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, tileCount, 1),
                      [&](const tbb::blocked_range<uint32_t>& range) {
                          for (uint32_t index = range.begin(); index != range.end(); ++index) {
                              const Tile tile = tileAt(index, bounds);
                              uint64_t tileRays = 0;
                              for (uint32_t y = tile.y0; y < tile.y1; ++y)
                                  for (uint32_t x = tile.x0; x < tile.x1; ++x)
                                      renderPixel(context, camera, x, y, image, tileRays);
                              rays += tileRays;
                              const uint64_t done = ++tilesDone;
                              if (progress) progress(done, tileCount);
                          }
                      });
    return rays.load();
}

double secondsSince(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace

Result<RenderImage> renderWithEmbree(const RenderScene& scene, const RenderOptions& options,
                                     RenderStats* stats, const RenderProgress& progress) {
    VASTRAY_TRY(validateRenderOptions(options));
    if (options.aovs & kAovStreamingOnly)
        return Status::error("the chunkid and cost AOVs need a streaming backend (--backend vulkan)");
    if (options.volumes)  // the CPU tracking reads voxels in memory (PackageReader::readVolumes)
        for (const Volume& v : *options.volumes)
            if (v.voxels.size() != v.brickCount() * kVolumeBrickVoxels)
                return Status::error("volume '" + v.name + "': the Embree renderer needs its voxels in memory "
                                     "(PackageReader::readVolumes), not left in the package");
    std::optional<tbb::global_control> threadLimit;
    if (options.threads > 0)
        threadLimit.emplace(tbb::global_control::max_allowed_parallelism, options.threads);

    const Clock::time_point buildStart = Clock::now();
    auto embree = EmbreeScene::build(scene.mesh, scene.textures, scene.primitiveIds);
    if (!embree) return embree.status();
    const double buildSeconds = secondsSince(buildStart);

    // Automatic framing frames the mesh and its volumes.
    const Aabb framed = boundsWithVolumes(scene.bounds.isEmpty() ? scene.mesh.bounds() : scene.bounds, options.volumes.get());
    const Camera camera = options.frameScene ? frameBounds(framed, options.camera.fovYDegrees,
                                                           float(options.width) / float(options.height), options.camera.up)
                                             : options.camera;
    VASTRAY_TRY(validateCamera(camera).withContext("camera: "));
    const CameraRays cameraRays(camera, options.width, options.height);
    const bool cones = options.textureLod == TextureLodMode::Cone;
    const ShadingContext context{scene.mesh,     **embree, options, normalize(options.environment.sunDirection),
                                 scene.textures, cones ? cameraRays.coneSpread() : 0.0f,
                                 cones ? kConeScatterSpread : 0.0f};
    const PixelBounds bounds = renderBounds(options);
    RenderImage image;
    image.allocate(bounds.width(), bounds.height(), options.aovs);
    image.placeInFrame(bounds.x0, bounds.y0, options.width, options.height);
    recordCamera(image, camera, options.width, options.height);

    const Clock::time_point renderStart = Clock::now();
    const uint64_t rays =
        renderTiles(context, cameraRays, image, progress);
    if (image.aovs & kAovPrimId)
        for (uint32_t& id : image.primId)
            if (id != kMissPrimId) id = scene.primitiveId(id);
    if (stats) {
        stats->backend = "embree";
        stats->renderSeconds = secondsSince(renderStart);
        stats->buildSeconds = buildSeconds;
        stats->rays = rays;
        stats->triangles = scene.mesh.triangleCount();
        stats->peakHostBytes = peakHostBytes();
    }
    return image;
}

}  // namespace vastray

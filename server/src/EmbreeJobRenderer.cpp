// The Embree reference renderer behind the JobRenderer seam, with a host cache of decoded
// scenes shared by every job.
#include <list>
#include <mutex>

#include "vastray/cpu/EmbreeRenderer.h"
#include "vastray/cpu/RenderScene.h"
#include "vastray/server/JobRenderer.h"
#include "vastray/streamer/ScenePackage.h"

namespace vastray::server {
namespace {

uint64_t sceneBytes(const RenderScene& scene) {
    const TriangleMesh& m = scene.mesh;
    return m.positions.size() * sizeof(Vec3f) + m.indices.size() * sizeof(uint32_t) +
           m.materialIds.size() * sizeof(uint32_t) + scene.primitiveIds.size() * sizeof(uint32_t) +
           m.materials.size() * sizeof(Material);
}

// Decoded scenes by package path, least recently used at the back. Used from the worker
// thread only, but locked so that a future second worker needs no change here.
class SceneCache {
public:
    explicit SceneCache(uint64_t capacityBytes) : capacity_(capacityBytes) {}

    // The scene and how many chunks were decoded to get it (0 on a cache hit).
    Result<std::shared_ptr<const RenderScene>> get(const std::string& path, uint64_t* chunkLoads) {
        std::lock_guard<std::mutex> lock(mutex_);
        for (auto it = entries_.begin(); it != entries_.end(); ++it) {
            if (it->path != path) continue;
            entries_.splice(entries_.begin(), entries_, it);
            *chunkLoads = 0;
            return entries_.front().scene;
        }
        auto reader = PackageReader::open(path);
        if (!reader) return reader.status();
        auto scene = renderSceneFromPackage(**reader);
        if (!scene) return scene.status();
        *chunkLoads = (*reader)->info().chunks.size();
        auto shared = std::make_shared<const RenderScene>(std::move(*scene));
        insert(path, shared);
        return shared;
    }

private:
    struct Entry {
        std::string path;
        std::shared_ptr<const RenderScene> scene;
        uint64_t bytes = 0;
    };

    void insert(const std::string& path, std::shared_ptr<const RenderScene> scene) {
        const uint64_t bytes = sceneBytes(*scene);
        // A scene larger than the whole cache is rendered but not kept.
        if (bytes > capacity_) return;
        entries_.push_front({path, std::move(scene), bytes});
        used_ += bytes;
        while (used_ > capacity_) {
            used_ -= entries_.back().bytes;
            entries_.pop_back();
        }
    }

    std::mutex mutex_;
    std::list<Entry> entries_;
    uint64_t capacity_ = 0, used_ = 0;
};

class EmbreeJobRenderer final : public JobRenderer {
public:
    explicit EmbreeJobRenderer(uint64_t hostCacheBytes) : cache_(hostCacheBytes) {}

    std::string name() const override { return "embree"; }

    Result<RenderImage> render(const JobRenderRequest& request, const JobProgressCallback& progress,
                               const std::atomic<bool>& cancel, JobRenderStats* stats) override {
        if (cancel) return Status::error("cancelled before loading the scene");
        uint64_t chunkLoads = 0;
        auto scene = cache_.get(request.scenePath, &chunkLoads);
        if (!scene) return scene.status();
        if (stats) stats->chunkLoads = chunkLoads;
        if (progress) progress({0, 0, chunkLoads});
        if (cancel) return Status::error("cancelled before rendering");
        RenderProgress tiles;
        if (progress)
            tiles = [&progress, chunkLoads](uint64_t done, uint64_t total) {
                progress({done, total, chunkLoads});
            };
        std::atomic<uint64_t> passes{0};  // tiles report from the render's threads
        RenderProgress tilesCounted = [&](uint64_t done, uint64_t total) {
            passes = total;
            if (tiles) tiles(done, total);
        };
        RenderOptions options = request.options;
        VASTRAY_TRY(applySceneCamera((*scene)->mesh.cameras, request.sceneCamera, options));
        if (request.sceneLights)
            applySceneLights((*scene)->mesh.lights, (*scene)->bounds, options);
        applySceneEmitters((*scene)->emitters, (*scene)->mesh.materials, options);
        RenderStats render;
        auto image = renderWithEmbree(**scene, options, &render, tilesCounted);
        if (stats) stats->passes = passes, stats->render = render;
        // Rays are counted when the render ends (its tiles do not report them).
        if (image && progress) progress({passes, passes, chunkLoads, render.rays, 0});
        return image;
    }

private:
    SceneCache cache_;
};

}  // namespace

std::unique_ptr<JobRenderer> makeEmbreeJobRenderer(uint64_t hostCacheBytes) {
    return std::make_unique<EmbreeJobRenderer>(hostCacheBytes);
}

}  // namespace vastray::server

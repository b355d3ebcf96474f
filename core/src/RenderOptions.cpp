#include "vastray/core/RenderOptions.h"

#include <string>
#include <vector>

#include "vastray/core/VecMath.h"

namespace vastray {

Result<IntegratorKind> parseIntegrator(std::string_view name) {
    if (name == "path") return IntegratorKind::Path;
    if (name == "ao") return IntegratorKind::AmbientOcclusion;
    return Status::error("unknown integrator '" + std::string(name) + "' (expected path or ao)");
}

void applyUpAxis(Vec3f up, RenderOptions& options) {
    const Vec3f unit = normalize(up);
    options.environment.up = unit;
    options.environment.sunDirection = rotateFromYUp(unit, Environment{}.sunDirection);
    options.camera.up = unit;
}

const char* integratorName(IntegratorKind kind) { return kind == IntegratorKind::Path ? "path" : "ao"; }

Result<uint32_t> parseAovList(std::string_view list) {
    uint32_t flags = kAovNone;
    while (!list.empty()) {
        const size_t comma = list.find(',');
        const std::string_view name = list.substr(0, comma);
        if (name == "depth")
            flags |= kAovDepth;
        else if (name == "normal")
            flags |= kAovNormal;
        else if (name == "albedo")
            flags |= kAovAlbedo;
        else if (name == "primid")
            flags |= kAovPrimId;
        else if (name == "chunkid")
            flags |= kAovChunkId;
        else if (name == "cost")
            flags |= kAovCost;
        else if (name == "uv")
            flags |= kAovUv;
        else
            return Status::error("unknown AOV '" + std::string(name) +
                                 "' (expected depth, normal, albedo, primid, chunkid, cost, uv)");
        if (comma == std::string_view::npos) break;
        list.remove_prefix(comma + 1);
        if (list.empty()) return Status::error("AOV list ends with a comma");
    }
    return flags;
}

void applySceneLights(std::span<const PunctualLight> lights, const Aabb& bounds, RenderOptions& options) {
    options.lights.reset();
    if (!lights.empty()) options.lights = std::make_shared<const std::vector<LightEntry>>(makeLightTable(lights, bounds));
}

std::shared_ptr<const EmitterTable> sceneEmitterTable(std::span<const EmissiveTriangle> emitters,
                                                      std::span<const Material> materials) {
    if (emitters.empty()) return nullptr;
    auto table = std::make_shared<EmitterTable>(makeEmitterTable(emitters, materials));
    if (table->entries.empty()) return nullptr;
    return table;
}

void applySceneEmitters(std::span<const EmissiveTriangle> emitters, std::span<const Material> materials,
                        RenderOptions& options) {
    options.emitters = sceneEmitterTable(emitters, materials);
}

PixelBounds renderBounds(const RenderOptions& options) {
    return options.region.value_or(PixelBounds{0, 0, options.width, options.height});
}

// The region is part of the frame and holds at least one pixel.
static Status validateRegion(const RenderOptions& o) {
    if (!o.region) return Status::ok();
    const PixelBounds& r = *o.region;
    const std::string text = std::to_string(r.x0) + "," + std::to_string(r.y0) + "," + std::to_string(r.x1) + "," +
                             std::to_string(r.y1);
    if (r.x1 > o.width || r.y1 > o.height)
        return Status::error("region " + text + " reaches beyond the " + std::to_string(o.width) + "x" +
                             std::to_string(o.height) + " frame (x1 <= " + std::to_string(o.width) +
                             ", y1 <= " + std::to_string(o.height) + "; x1 and y1 are exclusive)");
    if (r.x0 >= r.x1 || r.y0 >= r.y1)
        return Status::error("region " + text + " is empty (needs x0 < x1 and y0 < y1)");
    return Status::ok();
}

// The index of the camera `choice` names: its exact name, else (a name longer than a package
// stores) the one stored under its cut (storedCameraName), else its index; cameras.size() if none.
static Result<size_t> findSceneCamera(std::span<const SceneCamera> cameras, const std::string& choice,
                                      const std::string& names) {
    for (size_t i = 0; i < cameras.size(); ++i)
        if (cameras[i].name == choice) return i;
    const std::string stored = storedCameraName(choice);
    if (stored != choice) {
        std::vector<size_t> matches;
        for (size_t i = 0; i < cameras.size(); ++i)
            if (cameras[i].name == stored) matches.push_back(i);
        if (matches.size() > 1)
            return Status::error("scene camera '" + choice + "': cameras " + std::to_string(matches[0]) + " and " +
                                 std::to_string(matches[1]) + " are both stored as '" + stored +
                                 "' (names are kept to " + std::to_string(kMaxSceneCameraNameBytes) +
                                 " bytes); pick one by index; the scene has " + names);
        if (matches.size() == 1) return matches[0];
    }
    if (choice.find_first_not_of("0123456789") == std::string::npos && choice.size() < 10) return size_t(std::stoul(choice));
    return cameras.size();
}

Status applySceneCamera(std::span<const SceneCamera> cameras, const std::string& choice, RenderOptions& options) {
    if (choice.empty()) {
        if (!options.frameScene || cameras.empty()) return Status::ok();
        options.frameScene = false;
        options.camera = cameras.front().camera;
        return Status::ok();
    }
    if (!options.frameScene) return Status::error("--camera " + choice + " and --eye/--target exclude each other");
    std::string names;
    for (size_t i = 0; i < cameras.size(); ++i) names += (i ? ", " : "") + std::to_string(i) + " '" + cameras[i].name + "'";
    if (cameras.empty()) return Status::error("scene camera '" + choice + "': the scene defines no cameras");
    auto index = findSceneCamera(cameras, choice, names);
    if (!index) return index.status();
    if (*index >= cameras.size())
        return Status::error("scene camera '" + choice + "': no camera of that name or index; the scene has " + names);
    options.frameScene = false;
    options.camera = cameras[*index].camera;
    return Status::ok();
}

Status validateRenderOptions(const RenderOptions& o) {
    auto outside = [](const char* what, uint64_t value, uint64_t lo, uint64_t hi) {
        return Status::error(std::string(what) + " " + std::to_string(value) + " is outside [" +
                             std::to_string(lo) + ", " + std::to_string(hi) + "]");
    };
    if (o.width < 1 || o.width > kMaxImageSide) return outside("image width", o.width, 1, kMaxImageSide);
    if (o.height < 1 || o.height > kMaxImageSide) return outside("image height", o.height, 1, kMaxImageSide);
    if (o.samplesPerPixel < 1 || o.samplesPerPixel > kMaxSamplesPerPixel)
        return outside("samples per pixel", o.samplesPerPixel, 1, kMaxSamplesPerPixel);
    if (o.maxDepth > kMaxDepthLimit) return outside("max depth", o.maxDepth, 0, kMaxDepthLimit);
    if (o.threads > 4096) return outside("threads", o.threads, 0, 4096);
    VASTRAY_TRY(validateRegion(o));
    if (!(o.aoDistance >= 0.0f)) return Status::error("ambient occlusion distance must be >= 0");
    if (!o.frameScene)
        VASTRAY_TRY(validateCamera(o.camera).withContext("camera: "));
    else
        VASTRAY_TRY(checkFov(o.camera.fovYDegrees));
    return Status::ok();
}

}  // namespace vastray

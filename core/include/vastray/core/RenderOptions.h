#pragma once
// What a render is asked to do, independent of the backend. CLI flags map one-to-one onto
// these fields; defaults are documented here and in docs/RENDERING.md.
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "vastray/core/Camera.h"
#include "vastray/core/Emitters.h"
#include "vastray/core/Light.h"
#include "vastray/core/RayCone.h"
#include "vastray/core/Result.h"

namespace vastray {

enum class IntegratorKind { Path, AmbientOcclusion };

Result<IntegratorKind> parseIntegrator(std::string_view name);
const char* integratorName(IntegratorKind kind);

// Which extra images to produce besides the beauty (bit flags).
enum AovFlags : uint32_t {
    kAovNone = 0,
    kAovDepth = 1u << 0,
    kAovNormal = 1u << 1,
    kAovAlbedo = 1u << 2,
    kAovPrimId = 1u << 3,
    kAovChunkId = 1u << 4,  // streaming backends only: the chunk whose cell produced the hit
    kAovCost = 1u << 5,     // streaming backends only: cells visited and triangles tested per pixel
    kAovUv = 1u << 6,       // the hit's texture coordinates; (0, 0) where the scene has none, or on a miss
};
// Backends without chunks (the Embree reference) cannot produce these.
constexpr uint32_t kAovStreamingOnly = kAovChunkId | kAovCost;
// "depth,normal,albedo,primid,chunkid,cost,uv" (any subset, any order); "" is none.
Result<uint32_t> parseAovList(std::string_view list);

struct EnvironmentMap;  // vastray/core/EnvironmentMap.h
struct Volume;          // vastray/core/Volume.h

// The environment of the `path` integrator. With h = dot(d, up), the sky's radiance for unit
// direction d is `ground` when h < 0, else horizon + (zenith - horizon) * h; with a `map`, the
// map's radiance instead (its zenith is `up`), importance sampled by next-event estimation. The
// sun is a directional light: irradiance `sunIrradiance` on a surface facing `sunDirection`
// (towards the sun).
struct Environment {
    std::array<float, 3> zenith{0.25f, 0.45f, 0.9f};
    std::array<float, 3> horizon{0.85f, 0.9f, 1.0f};
    std::array<float, 3> ground{0.3f, 0.28f, 0.25f};
    Vec3f up{0.0f, 1.0f, 0.0f};                            // unit: the sky's zenith
    Vec3f sunDirection{0.4f, 0.8f, 0.3f};                  // need not be unit; normalized when used
    std::array<float, 3> sunIrradiance{3.0f, 2.9f, 2.7f};  // zero: no sun
    std::shared_ptr<const EnvironmentMap> map;             // none: the sky above
    float mapRotationDegrees = 0.0f;  // turns the map about up (environmentFrame), [-360, 360]
};

// The default sun's colour, per unit of --sun intensity (its largest component is 1), and the
// largest intensity accepted (the default sun is 3).
constexpr std::array<float, 3> kSunTint{1.0f, 2.9f / 3.0f, 2.7f / 3.0f};
constexpr float kMaxSunIntensity = 1e6f;


constexpr uint32_t kMaxImageSide = 16384;
constexpr uint32_t kMaxSamplesPerPixel = 65536;
constexpr uint32_t kMaxDepthLimit = 1024;

// A rectangle of pixels of the full frame: columns [x0, x1), rows [y0, y1) (row 0 at the top;
// x1 and y1 exclusive, like pbrt-v4's --pixelbounds).
struct PixelBounds {
    uint32_t x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    uint32_t width() const { return x1 - x0; }
    uint32_t height() const { return y1 - y0; }
    uint64_t pixelCount() const { return uint64_t(width()) * height(); }
    bool operator==(const PixelBounds&) const = default;
};

struct RenderOptions {
    uint32_t width = 640, height = 480;
    uint32_t samplesPerPixel = 16;
    IntegratorKind integrator = IntegratorKind::Path;
    uint32_t maxDepth = 5;  // scattering events per path; 0 shows emitters and sky only
    uint32_t seed = 0;
    uint32_t aovs = kAovNone;
    uint32_t threads = 0;     // 0: all cores
    float aoDistance = 0.0f;  // occlusion range of `ao`; 0: unbounded
    // How the maps' level of detail is picked (core/RayCone.h; docs/RENDERING.md "Texture level
    // of detail"): ray cones, or level 0 everywhere.
    TextureLodMode textureLod = TextureLodMode::Cone;
    bool frameScene = true;   // ignore `camera` and frame the scene bounds
    // Render only these pixels of the width x height frame (same camera, same per-pixel random
    // numbers, so the pixels equal the whole frame's bit for bit); none: the whole frame.
    std::optional<PixelBounds> region;
    Camera camera;
    Environment environment;
    // The scene's density volumes (the package's, PackageReader::readVolumes); none: no volume
    // code runs. The `path` integrator scatters in them; `ao` and the AOVs see surfaces only.
    std::shared_ptr<const std::vector<Volume>> volumes;
    // The scene's punctual lights as next-event estimation picks them (makeLightTable,
    // applySceneLights); none or empty: no punctual-light code runs.
    std::shared_ptr<const std::vector<LightEntry>> lights;
    // The scene's emissive triangles as next-event estimation samples them (makeEmitterTable,
    // applySceneEmitters); none or empty: they are found only by the paths that hit them, and no
    // emitter code runs.
    std::shared_ptr<const EmitterTable> emitters;
};

// Turns the world's up to the unit vector `up` (+Y or +Z from --up-axis): the sky's zenith,
// the default sun (its Y-up direction turned by rotateFromYUp) and the camera's up (which
// automatic framing also looks down along). An explicit sun or camera up is set after this.
void applyUpAxis(Vec3f up, RenderOptions& options);

// The camera a render uses when the scene defines some (`cameras`, in file order): `choice`
// names one (its name, else its 0-based index); empty picks the first, unless the options
// already place the camera (frameScene false: --eye/--target). A name longer than a package
// keeps (kMaxSceneCameraNameBytes) also picks the camera stored under its cut name
// (storedCameraName), unless two are: then it is an error that asks for the index. Sets eye,
// target, up and field of view. Errors name the choice and list the scene's cameras.
Status applySceneCamera(std::span<const SceneCamera> cameras, const std::string& choice, RenderOptions& options);

// The scene's punctual lights (a package's or an imported file's) for a scene within `bounds`;
// none sets no table.
void applySceneLights(std::span<const PunctualLight> lights, const Aabb& bounds, RenderOptions& options);

// The emitter table of the scene's emissive triangles (a package's, or an imported mesh's
// collectEmitters) with its materials; null when none is sampled. A caller that renders one scene
// again (the service's open scenes) makes it once and shares it: the device backend then uploads
// it once too.
std::shared_ptr<const EmitterTable> sceneEmitterTable(std::span<const EmissiveTriangle> emitters,
                                                      std::span<const Material> materials);
// options.emitters = sceneEmitterTable(emitters, materials).
void applySceneEmitters(std::span<const EmissiveTriangle> emitters, std::span<const Material> materials,
                        RenderOptions& options);

// The pixels a render produces: `region`, or the whole frame.
PixelBounds renderBounds(const RenderOptions& options);

// Every limit above; the message names the field and the limit.
Status validateRenderOptions(const RenderOptions& options);

}  // namespace vastray

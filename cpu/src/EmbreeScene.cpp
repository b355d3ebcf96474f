#include "vastray/cpu/EmbreeScene.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "vastray/core/PathShading.h"
#include "vastray/core/VecMath.h"
#include "vastray/core/VertexAttributes.h"

namespace vastray {
namespace {

// What the filter functions read: our own copy of the triangles, so that facing is
// decided from the same vertices and winding everywhere (docs/GEOMETRY.md).
struct TriangleData {
    std::vector<Vec3f> positions;
    std::vector<uint32_t> indices;
    std::vector<uint8_t> doubleSided;  // per triangle
    // Cut-outs and blends (only when a material has one): per triangle its material when that one
    // is alpha-tested, else kNoAlpha; the UVs (none without them), materials, textures and
    // primitive ids (the blends' coins) the alpha test reads.
    static constexpr uint32_t kNoAlpha = 0xFFFFFFFFu;
    std::vector<uint32_t> alphaMaterial;
    std::vector<std::array<float, 2>> uvs;
    std::vector<Material> materials;
    std::span<const DecodedTexture> textures;
    std::vector<uint32_t> primitiveIds;  // empty: the identity

    // Whether the hit at barycentrics (u, v) is no hit for the ray keyed rayBase
    // (core/PathShading.h alphaDiscards).
    bool cutAway(uint32_t triangle, float u, float v, uint32_t rayBase) const {
        if (alphaMaterial.empty() || alphaMaterial[triangle] == kNoAlpha) return false;
        const uint32_t* c = &indices[3 * size_t(triangle)];
        const std::array<float, 2> uv =
            uvs.empty() ? std::array<float, 2>{0, 0} : interpolateUv(uvs[c[0]], uvs[c[1]], uvs[c[2]], u, v);
        return alphaDiscards(materials[alphaMaterial[triangle]], textures, uv, rayBase,
                             primitiveIds.empty() ? triangle : primitiveIds[triangle]);
    }

    bool frontFacing(uint32_t triangle, Vec3f direction) const {
        const Vec3f v0 = positions[indices[3 * triangle]];
        const Vec3f v1 = positions[indices[3 * triangle + 1]];
        const Vec3f v2 = positions[indices[3 * triangle + 2]];
        return dot(direction, cross(v1 - v0, v2 - v0)) < 0.0f;
    }
};

// rtcIntersect1 context extended with the nearest back-facing hit on a double-sided
// triangle. Those hits are rejected during traversal and reconsidered afterwards, so a
// front face at the same distance always wins whatever order the BVH visits them in.
struct HitContext {
    RTCIntersectContext base;
    uint32_t alphaBase = 0;  // the ray's key for its blend coins (alphaRayBase)
    float backT = std::numeric_limits<float>::infinity();
    uint32_t backTriangle = RTC_INVALID_GEOMETRY_ID;
    float backU = 0, backV = 0;
};

Vec3f rayDirection(const RTCFilterFunctionNArguments* args, unsigned i) {
    return {RTCRayN_dir_x(args->ray, args->N, i), RTCRayN_dir_y(args->ray, args->N, i),
            RTCRayN_dir_z(args->ray, args->N, i)};
}

void intersectFilter(const RTCFilterFunctionNArguments* args) {
    const auto* data = static_cast<const TriangleData*>(args->geometryUserPtr);
    auto* context = reinterpret_cast<HitContext*>(args->context);
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] != -1) continue;
        const uint32_t triangle = RTCHitN_primID(args->hit, args->N, i);
        if (data->cutAway(triangle, RTCHitN_u(args->hit, args->N, i), RTCHitN_v(args->hit, args->N, i),
                          context->alphaBase)) {
            args->valid[i] = 0;
            continue;
        }
        if (data->frontFacing(triangle, rayDirection(args, i))) continue;
        args->valid[i] = 0;
        if (!data->doubleSided[triangle]) continue;
        const float t = RTCRayN_tfar(args->ray, args->N, i);
        if (t < context->backT || (t == context->backT && triangle < context->backTriangle)) {
            context->backT = t;
            context->backTriangle = triangle;
            context->backU = RTCHitN_u(args->hit, args->N, i);
            context->backV = RTCHitN_v(args->hit, args->N, i);
        }
    }
}

// rtcOccluded1 context extended with the ray's key for its blend coins.
struct OcclusionContext {
    RTCIntersectContext base;
    uint32_t alphaBase = 0;
};

void occludedFilter(const RTCFilterFunctionNArguments* args) {
    const auto* data = static_cast<const TriangleData*>(args->geometryUserPtr);
    const uint32_t alphaBase = reinterpret_cast<const OcclusionContext*>(args->context)->alphaBase;
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] != -1) continue;
        const uint32_t triangle = RTCHitN_primID(args->hit, args->N, i);
        if ((!data->doubleSided[triangle] && !data->frontFacing(triangle, rayDirection(args, i))) ||
            data->cutAway(triangle, RTCHitN_u(args->hit, args->N, i), RTCHitN_v(args->hit, args->N, i), alphaBase))
            args->valid[i] = 0;
    }
}

void recordError(void* userPtr, RTCError code, const char* message) {
    auto* last = static_cast<std::string*>(userPtr);
    *last = "Embree error " + std::to_string(int(code)) + ": " + (message ? message : "");
}

RTCRayHit makeRayHit(const Ray& ray, float tMax) {
    RTCRayHit rh{};
    rh.ray.org_x = ray.origin.x;
    rh.ray.org_y = ray.origin.y;
    rh.ray.org_z = ray.origin.z;
    rh.ray.dir_x = ray.direction.x;
    rh.ray.dir_y = ray.direction.y;
    rh.ray.dir_z = ray.direction.z;
    rh.ray.tnear = 0.0f;
    rh.ray.tfar = tMax;
    rh.ray.mask = 0xFFFFFFFFu;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
    return rh;
}

}  // namespace

struct EmbreeScene::Impl {
    std::string lastError;
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    TriangleData triangles;

    ~Impl() {
        if (scene) rtcReleaseScene(scene);
        if (device) rtcReleaseDevice(device);
    }
    Status failure(const std::string& what) const {
        return Status::error("embree: " + what + (lastError.empty() ? std::string() : ": " + lastError));
    }
    Status attachGeometry();
};

Status EmbreeScene::Impl::attachGeometry() {
    const size_t vertexCount = triangles.positions.size(), triangleCount = triangles.indices.size() / 3;
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    if (!geometry) return failure("cannot create the triangle geometry");
    // rtcSetNewGeometryBuffer pads the vertex buffer as Embree's SIMD loads require.
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), vertexCount));
    auto* indices = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t), triangleCount));
    if (!vertices || !indices) {
        rtcReleaseGeometry(geometry);
        return failure("cannot allocate " + std::to_string(triangleCount) + " triangles");
    }
    static_assert(sizeof(Vec3f) == 3 * sizeof(float));
    std::memcpy(vertices, triangles.positions.data(), vertexCount * sizeof(Vec3f));
    std::memcpy(indices, triangles.indices.data(), triangles.indices.size() * sizeof(uint32_t));
    rtcSetGeometryUserData(geometry, &triangles);
    rtcSetGeometryIntersectFilterFunction(geometry, intersectFilter);
    rtcSetGeometryOccludedFilterFunction(geometry, occludedFilter);
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(scene, geometry);
    rtcReleaseGeometry(geometry);
    return rtcGetDeviceError(device) == RTC_ERROR_NONE ? Status::ok() : failure("geometry setup failed");
}

EmbreeScene::EmbreeScene() : impl_(std::make_unique<Impl>()) {}
EmbreeScene::~EmbreeScene() = default;

Result<std::unique_ptr<EmbreeScene>> EmbreeScene::build(const TriangleMesh& mesh,
                                                        std::span<const DecodedTexture> textures,
                                                        std::span<const uint32_t> primitiveIds) {
    if (mesh.triangleCount() > std::numeric_limits<uint32_t>::max() / 3)
        return Status::error("embree: " + std::to_string(mesh.triangleCount()) +
                             " triangles exceed 32-bit ids");
    std::unique_ptr<EmbreeScene> self(new EmbreeScene());
    Impl& impl = *self->impl_;
    impl.triangles.positions = mesh.positions;
    impl.triangles.indices = mesh.indices;
    impl.triangles.doubleSided.resize(mesh.triangleCount());
    for (uint64_t t = 0; t < mesh.triangleCount(); ++t) {
        const uint32_t m = mesh.materialOf(t);
        impl.triangles.doubleSided[t] = m < mesh.materials.size() ? mesh.materials[m].doubleSided : 1;
    }
    // Without UVs no map is read: a cut-out is opaque, a blend has its factor's alpha.
    const uint64_t mapped = mesh.uvs.empty() ? 0 : textures.size();
    auto tested = [&](const Material& m) { return isAlphaTested(m, mapped); };
    if (std::any_of(mesh.materials.begin(), mesh.materials.end(), tested)) {
        TriangleData& d = impl.triangles;
        d.uvs = mesh.uvs, d.materials = mesh.materials, d.textures = textures.first(mapped);
        d.primitiveIds.assign(primitiveIds.begin(), primitiveIds.end());
        d.alphaMaterial.resize(mesh.triangleCount());
        for (uint64_t t = 0; t < mesh.triangleCount(); ++t) {
            const uint32_t m = mesh.materialOf(t) < mesh.materials.size() ? mesh.materialOf(t) : 0;
            d.alphaMaterial[t] = tested(mesh.materials[m]) ? m : TriangleData::kNoAlpha;
        }
    }
    impl.device = rtcNewDevice(nullptr);
    if (!impl.device)
        return Status::error("embree: cannot create a device (error " +
                             std::to_string(int(rtcGetDeviceError(nullptr))) + ")");
    rtcSetDeviceErrorFunction(impl.device, recordError, &impl.lastError);
    impl.scene = rtcNewScene(impl.device);
    if (!impl.scene) return impl.failure("cannot create a scene");
    rtcSetSceneFlags(impl.scene, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(impl.scene, RTC_BUILD_QUALITY_HIGH);
    if (mesh.triangleCount() > 0) VASTRAY_TRY(impl.attachGeometry());
    rtcCommitScene(impl.scene);
    if (rtcGetDeviceError(impl.device) != RTC_ERROR_NONE) return impl.failure("scene build failed");
    return self;
}

bool EmbreeScene::intersect(const Ray& ray, float tMax, SceneHit* hit, uint32_t alphaBase) const {
    HitContext context;
    rtcInitIntersectContext(&context.base);
    context.alphaBase = alphaBase;
    RTCRayHit rh = makeRayHit(ray, tMax);
    rtcIntersect1(impl_->scene, &context.base, &rh);
    const bool front = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
    const bool back = context.backTriangle != RTC_INVALID_GEOMETRY_ID;
    if (!front && !back) return false;
    if (front && !(back && context.backT < rh.ray.tfar)) {
        *hit = {rh.ray.tfar, rh.hit.primID, rh.hit.u, rh.hit.v, true};
    } else {
        *hit = {context.backT, context.backTriangle, context.backU, context.backV, false};
    }
    return true;
}

bool EmbreeScene::occluded(const Ray& ray, float tMax, uint32_t alphaBase) const {
    OcclusionContext context;
    rtcInitIntersectContext(&context.base);
    context.alphaBase = alphaBase;
    RTCRay r = makeRayHit(ray, tMax).ray;
    rtcOccluded1(impl_->scene, &context.base, &r);
    return r.tfar < 0.0f;  // Embree sets tfar to -inf on an occluded ray
}

}  // namespace vastray

#include "import/AssimpLights.h"

#include <assimp/light.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "vastray/core/Camera.h"
#include "vastray/core/VecMath.h"

namespace vastray::import {
namespace {

constexpr float kHalfPi = 1.57079632679489661923f;

// What the mapping left out or approximated, one warning per kind at the end.
struct LightNotes {
    uint64_t ambientOrArea = 0, unplaced = 0, attenuationApproximated = 0, conesNarrowed = 0, clamped = 0;
};

std::string number(float v) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", double(v));
    return text;
}

bool finite(const aiColor3D& c) { return std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b); }

// colour * intensity -> a colour whose largest component is 1 and that component as the
// intensity. Non-finite or negative values are kept where validateLight refuses them by name.
void splitColour(const aiColor3D& c, PunctualLight& l) {
    if (!finite(c)) {
        l.intensity = std::isfinite(c.r) ? (std::isfinite(c.g) ? c.b : c.g) : c.r;
        return;
    }
    const float peak = std::max({c.r, c.g, c.b});
    l.intensity = std::max(peak, 0.0f);
    if (peak > 0.0f) l.color = {c.r / peak, c.g / peak, c.b / peak};
    else if (std::min({c.r, c.g, c.b}) < 0.0f) l.color = {c.r, c.g, c.b};
}

// The file's 1 / (c + l d + q d^2) as our 1 / d^2: exact for a pure quadratic term, else equal
// at d = 1 (counted). A small term can lift an intensity within the limit above it (FBX files in
// centimetres: 1000 / 2.2e-7): clamped to kMaxLightIntensity (counted). Directional lights have
// no falloff.
Status applyAttenuation(const aiLight& source, PunctualLight& l, LightNotes& notes) {
    if (l.type == LightType::Directional) return Status::ok();
    const float c = source.mAttenuationConstant, lin = source.mAttenuationLinear;
    const float q = source.mAttenuationQuadratic;
    auto valid = [](float v) { return std::isfinite(v) && v >= 0.0f; };
    if (!valid(c) || !valid(lin) || !valid(q))
        return Status::error("attenuation (constant " + number(c) + ", linear " + number(lin) +
                             ", quadratic " + number(q) + ") is not finite and >= 0");
    if (c == 0.0f && lin == 0.0f && q > 0.0f) {
        l.intensity /= q;
    } else {
        ++notes.attenuationApproximated;
        if (const float atOne = c + lin + q; atOne > 0.0f) l.intensity /= atOne;
    }
    if (!(l.intensity <= kMaxLightIntensity)) {
        ++notes.clamped;
        l.intensity = kMaxLightIntensity;
    }
    return Status::ok();
}

// assimp's full cone angles -> glTF's half angles, at most a hemisphere.
void halveCone(const aiLight& source, PunctualLight& l, LightNotes& notes) {
    float inner = 0.5f * source.mAngleInnerCone, outer = 0.5f * source.mAngleOuterCone;
    if (std::isfinite(outer) && outer > kHalfPi) {
        ++notes.conesNarrowed;
        outer = kHalfPi, inner = std::min(inner, kHalfPi);
    }
    if (inner == outer) inner = std::nextafter(outer, 0.0f);  // assimp allows equal angles, glTF not
    l.innerConeAngle = inner, l.outerConeAngle = outer;
}

// One light into `l`: true, or false when it is not imported (counted in `notes`).
Result<bool> convertLight(const aiScene& scene, const aiLight& source, size_t index, LightNotes& notes,
                          PunctualLight& l) {
    switch (source.mType) {
        case aiLightSource_DIRECTIONAL: l.type = LightType::Directional; break;
        case aiLightSource_POINT: l.type = LightType::Point; break;
        case aiLightSource_SPOT: l.type = LightType::Spot; break;
        default: ++notes.ambientOrArea; return false;
    }
    const aiNode* node = scene.mRootNode ? scene.mRootNode->FindNode(source.mName) : nullptr;
    if (!node) {
        ++notes.unplaced;
        return false;
    }
    l.name = storedCameraName(source.mName.length > 0 ? source.mName.C_Str()
                                                      : "light " + std::to_string(index));
    const aiMatrix4x4 m = nodeToWorld(*node);
    const aiVector3D position = m * source.mPosition, direction = aiMatrix3x3(m) * source.mDirection;
    l.position = {position.x, position.y, position.z};
    if (l.type != LightType::Point) {
        const Vec3f d{direction.x, direction.y, direction.z};
        if (!(length(d) > 0.0f) || !std::isfinite(length(d))) {
            ++notes.unplaced;
            return false;
        }
        l.direction = normalize(d);
    }
    splitColour(source.mColorDiffuse, l);
    VASTRAY_TRY(validateLight(l));  // the file's own values: a huge or non-finite colour is refused
    VASTRAY_TRY(applyAttenuation(source, l, notes));
    if (l.type == LightType::Spot) halveCone(source, l, notes);
    VASTRAY_TRY(validateLight(l));
    return true;
}

void warnAbout(const LightNotes& notes, ImportReport& report) {
    report.warnUnused("ambient or area lights", notes.ambientOrArea,
                      "only directional, point and spot lights are rendered");
    report.warnUnused("lights", notes.unplaced, "placed by no node, or placed degenerately");
    if (notes.attenuationApproximated > 0)
        report.warnings.push_back(std::to_string(notes.attenuationApproximated) +
                                  " lights with constant or linear attenuation: rendered with inverse-square "
                                  "falloff, equal to the file's at distance 1");
    if (notes.clamped > 0)
        report.warnings.push_back(std::to_string(notes.clamped) + " lights brighter than " +
                                  std::to_string(int(kMaxLightIntensity)) +
                                  " once divided by their attenuation: clamped to that limit");
    if (notes.conesNarrowed > 0)
        report.warnings.push_back(std::to_string(notes.conesNarrowed) +
                                  " spot lights wider than a hemisphere: narrowed to one");
}

}  // namespace

aiMatrix4x4 nodeToWorld(const aiNode& node) {
    aiMatrix4x4 m = node.mTransformation;
    for (const aiNode* parent = node.mParent; parent; parent = parent->mParent)
        m = parent->mTransformation * m;
    return m;
}

Result<std::vector<PunctualLight>> assimpLights(const aiScene& scene, ImportReport& report) {
    if (scene.mNumLights > kMaxLights)
        return Status::error(std::to_string(scene.mNumLights) + " lights exceed the limit of " +
                             std::to_string(kMaxLights));
    std::vector<PunctualLight> lights;
    LightNotes notes;
    for (unsigned i = 0; i < scene.mNumLights; ++i) {
        const aiLight& source = *scene.mLights[i];
        PunctualLight l;
        auto imported = convertLight(scene, source, i, notes, l);
        if (!imported) {
            const std::string name = source.mName.length > 0 ? source.mName.C_Str() : std::to_string(i);
            return imported.status().withContext("light '" + name + "': ");
        }
        if (*imported) lights.push_back(std::move(l));
    }
    warnAbout(notes, report);
    return lights;
}

}  // namespace vastray::import

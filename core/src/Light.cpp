#include "vastray/core/Light.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "vastray/core/VecMath.h"

namespace vastray {
namespace {

constexpr float kPiF = 3.14159265358979323846f;

std::string number(float v) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", double(v));
    return text;
}

Status checkRange(const char* field, float value, float lo, float hi) {
    if (std::isfinite(value) && value >= lo && value <= hi) return Status::ok();
    return Status::error(std::string(field) + " " + number(value) + " is outside [" + number(lo) + ", " + number(hi) + "]");
}

bool finite(Vec3f v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

float power(const PunctualLight& l, float sceneRadius) {
    const float flux = std::max(l.color[0], std::max(l.color[1], l.color[2])) * l.intensity;
    switch (l.type) {
        case LightType::Directional: return kPiF * sceneRadius * sceneRadius * flux;
        case LightType::Spot: return 2.0f * kPiF * (1.0f - std::cos(l.outerConeAngle)) * flux;
        case LightType::Point: break;
    }
    return 4.0f * kPiF * flux;
}

}  // namespace

const char* lightTypeName(LightType type) {
    switch (type) {
        case LightType::Directional: return "directional";
        case LightType::Point: return "point";
        case LightType::Spot: return "spot";
    }
    return "unknown";
}

Status validateLight(const PunctualLight& l) {
    if (uint32_t(l.type) > uint32_t(LightType::Spot))
        return Status::error("type " + std::to_string(uint32_t(l.type)) + " is not directional, point or spot");
    for (float c : l.color) VASTRAY_TRY(checkRange("color component", c, 0.0f, 1.0f));
    VASTRAY_TRY(checkRange("intensity", l.intensity, 0.0f, kMaxLightIntensity));
    VASTRAY_TRY(checkRange("range", l.range, 0.0f, 3.4e38f));
    if (!finite(l.position) || std::max({std::fabs(l.position.x), std::fabs(l.position.y), std::fabs(l.position.z)}) > 1e18f)
        return Status::error("position is not finite or beyond +-1e18");
    if (!finite(l.direction) || std::fabs(length(l.direction) - 1.0f) > 1e-3f)
        return Status::error("direction is not a unit vector");
    if (l.type == LightType::Spot) {
        VASTRAY_TRY(checkRange("outerConeAngle", l.outerConeAngle, 0.0f, kPiF / 2.0f));
        VASTRAY_TRY(checkRange("innerConeAngle", l.innerConeAngle, 0.0f, kPiF / 2.0f));
        if (!(l.innerConeAngle < l.outerConeAngle))
            return Status::error("innerConeAngle " + number(l.innerConeAngle) + " is not below outerConeAngle " +
                                 number(l.outerConeAngle));
    }
    return Status::ok();
}

std::vector<LightEntry> makeLightTable(std::span<const PunctualLight> lights, const Aabb& bounds) {
    const float radius = bounds.lo.x <= bounds.hi.x ? 0.5f * length(bounds.hi - bounds.lo) : 1.0f;
    std::vector<LightEntry> table;
    std::vector<double> powers;
    double total = 0.0;
    for (const PunctualLight& l : lights) {
        const double p = power(l, std::max(radius, 1e-6f));
        if (!(p > 0.0)) continue;
        LightEntry e;
        e.type = l.type;
        e.position = l.position;
        e.direction = normalize(l.direction);
        e.radiant = Vec3f{l.color[0], l.color[1], l.color[2]} * l.intensity;
        if (l.type == LightType::Spot) {
            const float cosOuter = std::cos(l.outerConeAngle);
            e.coneScale = 1.0f / std::max(1e-3f, std::cos(l.innerConeAngle) - cosOuter);
            e.coneOffset = -cosOuter * e.coneScale;
        }
        table.push_back(e);
        powers.push_back(p);
        total += p;
    }
    double sum = 0.0;
    for (size_t i = 0; i < table.size(); ++i) {
        sum += powers[i];
        table[i].pick = float(powers[i] / total);
        table[i].cdf = i + 1 == table.size() ? 1.0f : float(sum / total);
    }
    return table;
}

uint32_t pickLight(std::span<const LightEntry> table, float u) {
    uint32_t lo = 0, hi = uint32_t(table.size()) - 1;  // the answer lies in [lo, hi]
    while (lo < hi) {
        const uint32_t mid = (lo + hi) / 2;
        if (table[mid].cdf > u) hi = mid; else lo = mid + 1;
    }
    return lo;
}

bool lightAt(const LightEntry& e, Vec3f point, Vec3f* direction, float* distance, Vec3f* irradiance) {
    if (e.type == LightType::Directional) {
        *direction = e.direction * -1.0f;
        *distance = INFINITY;
        *irradiance = e.radiant;
        return true;
    }
    const Vec3f d = e.position - point;
    const float squared = dot(d, d);
    if (!(squared > 0.0f)) return false;
    *distance = std::sqrt(squared);
    *direction = d * (1.0f / *distance);
    float attenuation = 1.0f / squared;
    if (e.type == LightType::Spot) {
        const float cone = std::clamp(dot(e.direction, *direction * -1.0f) * e.coneScale + e.coneOffset, 0.0f, 1.0f);
        attenuation *= cone * cone;
    }
    *irradiance = e.radiant * attenuation;
    return attenuation > 0.0f;
}

}  // namespace vastray

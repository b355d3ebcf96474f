#include "vastray/core/Emitters.h"

#include <algorithm>
#include <cmath>

#include "vastray/core/PathShading.h"
#include "vastray/core/VecMath.h"
#include "vastray/core/VertexAttributes.h"

namespace vastray {
namespace {

double emissionWeight(const Material& m) {
    return std::max({double(m.emissive[0]), double(m.emissive[1]), double(m.emissive[2])});
}

double triangleArea(Vec3f v0, Vec3f v1, Vec3f v2) { return 0.5 * double(length(geometricNormal(v0, v1, v2))); }

// The barycentrics (u2 s, s - u2 s), s = sqrt(u1), of the uniform point emitterPoint draws.
std::array<float, 2> emitterBarycentrics(float u1, float u2) {
    const float s = std::sqrt(u1);
    const float u = u2 * s;
    return {u, s - u};
}

}  // namespace

bool isSampledEmitter(const Material& m, uint64_t textureCount) {
    return emissionWeight(m) > 0.0 && std::isfinite(emissionWeight(m)) && !isCutout(m, textureCount) &&
           !isBlended(m, textureCount);
}

std::vector<EmissiveTriangle> collectEmitters(const TriangleMesh& mesh, uint64_t textureCount,
                                              std::span<const uint32_t> triangles) {
    std::vector<uint8_t> sampled(mesh.materials.size());
    bool any = false;
    for (size_t m = 0; m < mesh.materials.size(); ++m) {
        sampled[m] = isSampledEmitter(mesh.materials[m], textureCount) ? 1 : 0;
        any = any || sampled[m];
    }
    std::vector<EmissiveTriangle> out;
    if (!any) return out;
    auto visit = [&](uint64_t t) {
        const uint32_t material = mesh.materialOf(t);
        if (material >= sampled.size() || !sampled[material]) return;
        const uint32_t* i = &mesh.indices[3 * t];
        EmissiveTriangle e{mesh.positions[i[0]], mesh.positions[i[1]], mesh.positions[i[2]], material};
        if (!mesh.uvs.empty()) e.t0 = mesh.uvs[i[0]], e.t1 = mesh.uvs[i[1]], e.t2 = mesh.uvs[i[2]];
        if (triangleArea(e.v0, e.v1, e.v2) > 0.0) out.push_back(e);
    };
    if (triangles.empty())
        for (uint64_t t = 0; t < mesh.triangleCount(); ++t) visit(t);
    else
        for (uint32_t t : triangles) visit(t);
    return out;
}

EmitterTable makeEmitterTable(std::span<const EmissiveTriangle> triangles, std::span<const Material> materials) {
    EmitterTable table;
    table.areaDensity.assign(materials.size(), 0.0f);
    std::vector<double> weights;
    double power = 0.0;
    for (const EmissiveTriangle& t : triangles) {
        const double w = triangleArea(t.v0, t.v1, t.v2) * emissionWeight(materials[t.material]);
        if (!(w > 0.0) || !std::isfinite(w)) continue;
        table.entries.push_back({t.v0, t.v1, t.v2, t.material, 1.0f, 0, t.t0, t.t1, t.t2});
        weights.push_back(w);
        power += w;
    }
    if (table.entries.empty() || !(power > 0.0) || !std::isfinite(power)) {
        table.entries.clear();
        return table;
    }
    for (const EmitterEntry& e : table.entries)
        table.areaDensity[e.material] = float(emissionWeight(materials[e.material]) / power);
    // Vose's alias method: columns of height n p_i; a short column takes the rest of its height
    // from a tall one, which shrinks by as much.
    const size_t n = weights.size();
    std::vector<double> scaled(n);
    std::vector<uint32_t> small, large;
    for (size_t i = 0; i < n; ++i) {
        scaled[i] = weights[i] / power * double(n);
        (scaled[i] < 1.0 ? small : large).push_back(uint32_t(i));
    }
    while (!small.empty() && !large.empty()) {
        const uint32_t s = small.back(), l = large.back();
        small.pop_back();
        table.entries[s].keep = float(scaled[s]);
        table.entries[s].alias = l;
        scaled[l] -= 1.0 - scaled[s];
        if (scaled[l] < 1.0) {
            large.pop_back();
            small.push_back(l);
        }
    }
    // What rounding leaves is a full column of its own.
    for (uint32_t i : small) table.entries[i].keep = 1.0f, table.entries[i].alias = i;
    for (uint32_t i : large) table.entries[i].keep = 1.0f, table.entries[i].alias = i;
    return table;
}

uint32_t pickEmitter(const EmitterTable& table, uint32_t bits, float u) {
    const auto column = uint32_t((uint64_t(bits) * table.entries.size()) >> 32);
    const EmitterEntry& e = table.entries[column];
    return u < e.keep ? column : e.alias;
}

Vec3f emitterPoint(const EmitterEntry& e, float u1, float u2) {
    const auto [u, v] = emitterBarycentrics(u1, u2);
    return barycentricPosition(e.v0, e.v1, e.v2, u, v);
}

std::array<float, 2> emitterUv(const EmitterEntry& e, float u1, float u2) {
    const auto [u, v] = emitterBarycentrics(u1, u2);
    return interpolateUv(e.t0, e.t1, e.t2, u, v);
}

}  // namespace vastray

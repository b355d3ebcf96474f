#include "vastray/core/EnvironmentMap.h"

#include <algorithm>
#include <cmath>

#include "vastray/core/Sampling.h"
#include "vastray/core/VecMath.h"

namespace vastray {
namespace {

// The texel of unit-square point (u, v), clamped to the image.
uint64_t texelAt(const EnvironmentMap& map, float u, float v) {
    const uint32_t x = std::min(uint32_t(u * float(map.width)), map.width - 1);
    const uint32_t y = std::min(uint32_t(v * float(map.height)), map.height - 1);
    return uint64_t(y) * map.width + x;
}

// The texel towards unit d, and sin(theta) there. theta and sin(theta) come from the
// components along up and across it (atan2, not acos: exact to a few ulps at the poles too).
uint64_t texelToward(const EnvironmentMap& map, const Frame& frame, Vec3f d, float* sinTheta) {
    const float x = dot(d, frame.tangent), y = dot(d, frame.bitangent), z = dot(d, frame.normal);
    *sinTheta = std::sqrt(x * x + y * y);
    float phi = std::atan2(y, x);
    if (phi < 0.0f) phi += 2.0f * kPi;
    return texelAt(map, phi * (0.5f / kPi), std::atan2(*sinTheta, z) * (1.0f / kPi));
}

// The last index i in [0, n) with cdf[i] <= u (cdf has n + 1 entries, cdf[0] = 0, cdf[n] = 1),
// and u's place between cdf[i] and cdf[i + 1]. Entries of zero weight are never chosen.
uint32_t pickInterval(const float* cdf, uint32_t n, float u, float* offset) {
    uint32_t lo = 0, hi = n;  // the answer lies in [lo, hi)
    while (hi - lo > 1) {
        const uint32_t mid = (lo + hi) / 2;
        if (cdf[mid] <= u) lo = mid; else hi = mid;
    }
    const float width = cdf[lo + 1] - cdf[lo];
    *offset = width > 0.0f ? std::clamp((u - cdf[lo]) / width, 0.0f, 1.0f) : 0.5f;
    return lo;
}

// Cumulative sums of `weights` divided by their total into `cdf` (n + 1 entries, the last 1).
void cumulate(const double* weights, uint32_t n, double total, float* cdf) {
    double sum = 0;
    cdf[0] = 0.0f;
    for (uint32_t i = 0; i < n; ++i) {
        sum += weights[i];
        cdf[i + 1] = total > 0 ? float(sum / total) : float(i + 1) / float(n);
    }
    cdf[n] = 1.0f;
}

// Scales the planes' texels into map.rgb (each checked: finite, >= 0, <= the limit after scaling).
Status fillTexels(const std::string& source, const std::vector<float>* planes[3], float scale, EnvironmentMap& map) {
    map.rgb.resize(3 * planes[0]->size());
    for (uint64_t i = 0; i < planes[0]->size(); ++i)
        for (int k = 0; k < 3; ++k) {
            const float c = (*planes[k])[i], value = c * scale;
            if (!(c >= 0.0f) || !std::isfinite(c) || !std::isfinite(value) || value > kMaxEnvironmentRadiance)
                return Status::error(source + ": texel (" + std::to_string(i % map.width) + ", " +
                                     std::to_string(i / map.width) + ") channel " + "RGB"[k] + " is " +
                                     std::to_string(c) +
                                     (scale != 1.0f ? " (scaled by " + std::to_string(scale) + ")" : "") +
                                     ": environment radiance must be finite, at least 0 and at most 1e18");
            map.rgb[3 * i + k] = value;
        }
    return Status::ok();
}

// The sampling tables of map.rgb: each texel weighs its mean RGB times sin(theta) at its centre.
void buildDistribution(EnvironmentMap& map) {
    const uint32_t width = map.width, height = map.height;
    const uint64_t texels = uint64_t(width) * height;
    map.density.resize(texels);
    map.marginalCdf.resize(height + 1);
    map.conditionalCdf.resize(uint64_t(height) * (width + 1));
    std::vector<double> weights(texels), rowWeights(height);
    double total = 0;
    for (uint32_t y = 0; y < height; ++y) {
        const double sinTheta = std::sin(kPi * (double(y) + 0.5) / double(height));
        double row = 0;
        for (uint64_t i = uint64_t(y) * width; i < uint64_t(y + 1) * width; ++i) {
            weights[i] = (double(map.rgb[3 * i]) / 3.0 + double(map.rgb[3 * i + 1]) / 3.0 +
                          double(map.rgb[3 * i + 2]) / 3.0) * sinTheta;
            row += weights[i];
        }
        rowWeights[y] = row;
        total += row;
        cumulate(&weights[uint64_t(y) * width], width, row, &map.conditionalCdf[uint64_t(y) * (width + 1)]);
    }
    cumulate(rowWeights.data(), height, total, map.marginalCdf.data());
    map.sampleable = total > 0;
    for (uint64_t i = 0; i < texels; ++i) map.density[i] = total > 0 ? float(weights[i] * double(texels) / total) : 0.0f;
}

}  // namespace

Result<std::shared_ptr<const EnvironmentMap>> makeEnvironmentMap(const std::string& source, uint32_t width,
                                                                 uint32_t height, const std::vector<float>& r,
                                                                 const std::vector<float>& g,
                                                                 const std::vector<float>& b, float scale) {
    if (width == 0 || height == 0 || width > kMaxEnvironmentSide || height > kMaxEnvironmentSide ||
        uint64_t(width) * height > kMaxEnvironmentTexels)
        return Status::error(source + ": an environment map of " + std::to_string(width) + "x" +
                             std::to_string(height) + " texels is outside the limits (each side 1 to " +
                             std::to_string(kMaxEnvironmentSide) + ", at most " +
                             std::to_string(kMaxEnvironmentTexels) + " texels)");
    if (!(scale >= 0.0f && scale <= kMaxEnvironmentRadiance))
        return Status::error(source + ": the environment scale " + std::to_string(scale) + " is outside [0, 1e18]");
    const uint64_t texels = uint64_t(width) * height;
    if (r.size() != texels || g.size() != texels || b.size() != texels)
        return Status::error(source + ": the environment map needs R, G and B channels of " + std::to_string(width) +
                             "x" + std::to_string(height) + " values");
    auto map = std::make_shared<EnvironmentMap>();
    map->width = width, map->height = height;
    const std::vector<float>* planes[3] = {&r, &g, &b};
    VASTRAY_TRY(fillTexels(source, planes, scale, *map));
    buildDistribution(*map);
    return std::shared_ptr<const EnvironmentMap>(std::move(map));
}

Frame environmentFrame(Vec3f up, float rotationDegrees) {
    Frame frame = frameAround(up);
    if (rotationDegrees == 0.0f) return frame;
    const float a = rotationDegrees * (kPi / 180.0f), c = std::cos(a), s = std::sin(a);
    const Vec3f t = frame.tangent, b = frame.bitangent;
    frame.tangent = t * c + b * s;
    frame.bitangent = b * c - t * s;
    return frame;
}

Vec3f environmentRadiance(const EnvironmentMap& map, const Frame& frame, Vec3f d) {
    float sinTheta;
    const uint64_t t = texelToward(map, frame, d, &sinTheta);
    return {map.rgb[3 * t], map.rgb[3 * t + 1], map.rgb[3 * t + 2]};
}

float environmentPdf(const EnvironmentMap& map, const Frame& frame, Vec3f d) {
    if (!map.sampleable) return 0.0f;
    float sinTheta;
    const uint64_t t = texelToward(map, frame, d, &sinTheta);
    if (sinTheta <= 0.0f) return 0.0f;
    return map.density[t] / (2.0f * kPi * kPi * sinTheta);
}

EnvironmentSample sampleEnvironment(const EnvironmentMap& map, const Frame& frame, float u1, float u2) {
    EnvironmentSample s;
    if (!map.sampleable) return s;
    float dv = 0, du = 0;
    const uint32_t y = pickInterval(map.marginalCdf.data(), map.height, u1, &dv);
    const uint32_t x = pickInterval(&map.conditionalCdf[uint64_t(y) * (map.width + 1)], map.width, u2, &du);
    const float v = (float(y) + dv) / float(map.height), u = (float(x) + du) / float(map.width);
    const float theta = kPi * v, phi = 2.0f * kPi * u;
    const float sinTheta = std::sin(theta);
    if (!(sinTheta > 0.0f)) return s;
    const uint64_t t = uint64_t(y) * map.width + x;
    s.direction = normalize(frame.toWorld(
        {sinTheta * std::cos(phi), sinTheta * std::sin(phi), std::cos(theta)}));
    s.radiance = {map.rgb[3 * t], map.rgb[3 * t + 1], map.rgb[3 * t + 2]};
    s.pdf = map.density[t] / (2.0f * kPi * kPi * sinTheta);
    return s;
}

float powerHeuristic(float chosen, float other) {
    if (!(chosen > 0.0f)) return 0.0f;
    const float ratio = other / chosen;
    return 1.0f / (1.0f + ratio * ratio);
}

}  // namespace vastray

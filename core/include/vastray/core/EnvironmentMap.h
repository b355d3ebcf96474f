#pragma once
// A latitude-longitude environment map (`--environment FILE`) and its importance sampling,
// shared by the Embree reference and the device (gpu/shaders/common/Environment.glsl does the
// same steps on the arrays below). docs/RENDERING.md, "Environment map", specifies it.
//
// Mapping: row 0 of the image is the zenith (Environment::up), the last row the nadir; column u
// is the azimuth phi = 2 pi u measured from the map frame's tangent towards its bitangent: those
// of frameAround(up) (core/Sampling.h) turned about up by the map's rotation (environmentFrame).
// A direction d has cos(theta) = dot(d, up), u = phi / 2 pi,
// v = theta / pi, and the radiance of the texel (floor(u W), floor(v H)): nearest texel, no
// filtering, so that the sampling density below is exactly the lookup's.
//
// Sampling picks a texel with probability proportional to its weight (the mean of its R, G
// and B times sin(theta) at its centre: the solid angle it covers) by a row (marginal) and a
// column (conditional) inverse CDF, then a uniform point inside it; the density over the unit
// square is `density` of that texel, over solid angle density / (2 pi^2 sin(theta)).
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "vastray/core/Result.h"
#include "vastray/core/Sampling.h"
#include "vastray/core/Vec3.h"

namespace vastray {

// Limits of a map (each side, and the texel count: 20 device bytes per texel).
constexpr uint32_t kMaxEnvironmentSide = 16384;
constexpr uint64_t kMaxEnvironmentTexels = uint64_t(1) << 26;
// Largest --environment-scale (and texel value after scaling) accepted.
constexpr float kMaxEnvironmentRadiance = 1e18f;

struct EnvironmentMap {
    uint32_t width = 0, height = 0;
    std::vector<float> rgb;             // 3 per texel, row 0 first (the zenith)
    std::vector<float> density;         // per texel: the sampling density over the unit square
    std::vector<float> marginalCdf;     // height + 1: the rows' cumulative weight, 0 ... 1
    std::vector<float> conditionalCdf;  // height * (width + 1): per row, the columns' cumulative weight
    // False when every texel is black: nothing to sample, the map only reads as black.
    bool sampleable = false;
    // Device bytes of the arrays above (the GPU keeps all four).
    uint64_t deviceBytes() const {
        return 4 * (rgb.size() + density.size() + marginalCdf.size() + conditionalCdf.size());
    }
};

// Builds a map from planes of width x height floats (row 0 at the top), each texel multiplied
// by `scale`. Errors name `source`, the texel and the limit: sizes beyond the limits, negative,
// NaN or infinite values (before and after scaling).
Result<std::shared_ptr<const EnvironmentMap>> makeEnvironmentMap(const std::string& source, uint32_t width,
                                                                 uint32_t height, const std::vector<float>& r,
                                                                 const std::vector<float>& g,
                                                                 const std::vector<float>& b, float scale = 1.0f);

// Reads an image file's R, G and B channels through OpenImageIO (.exr, .hdr, .pfm, .png, ...;
// part of vastray_image) and builds the map. Sizes are checked before the pixels are read.
Result<std::shared_ptr<const EnvironmentMap>> readEnvironmentMap(const std::string& path, float scale = 1.0f);

// Largest |--environment-rotate| in degrees.
constexpr float kMaxEnvironmentRotation = 360.0f;

// The map's frame: normal = unit `up` (the zenith); tangent and bitangent those of
// frameAround(up) turned about up by `rotationDegrees` (t cos a + b sin a, b cos a - t sin a), so
// that the map turns with the rotation; exactly frameAround(up) at 0.
Frame environmentFrame(Vec3f up, float rotationDegrees);

// The map's radiance towards unit direction d, in the map frame `frame`.
Vec3f environmentRadiance(const EnvironmentMap& map, const Frame& frame, Vec3f d);
// The solid-angle density with which sampleEnvironment picks unit direction d (0 where it
// never does).
float environmentPdf(const EnvironmentMap& map, const Frame& frame, Vec3f d);

struct EnvironmentSample {
    Vec3f direction;  // unit
    Vec3f radiance;
    float pdf = 0;    // solid angle; 0: no sample (the map is not sampleable, or a pole)
};
// A direction drawn from the map's density with u1, u2 in [0, 1).
EnvironmentSample sampleEnvironment(const EnvironmentMap& map, const Frame& frame, float u1, float u2);

// The power heuristic's weight (beta = 2) of a strategy of density `chosen` against one of
// density `other`: chosen^2 / (chosen^2 + other^2), computed without overflow; 0 when chosen is 0.
float powerHeuristic(float chosen, float other);

}  // namespace vastray

// Fuzzes the environment map's validation and importance sampling (core/EnvironmentMap.h) with
// arbitrary texels: NaN, infinities, negatives, denormals, huge values and black rows. The
// first two bytes give the width and height (1..64), the third the scale; the rest are the R, G, B
// planes' floats (missing ones are 0). A map that is accepted must sample and look up finite,
// non-negative values and unit directions. (The file is read by OpenImageIO, a library of its
// own; `vastray render --environment` checks its size before reading the pixels.)
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "vastray/core/EnvironmentMap.h"
#include "vastray/core/VecMath.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 3) return 0;
    const uint32_t w = data[0] % 64 + 1, h = data[1] % 64 + 1;
    const float scales[] = {1.0f, 0.0f, 2.0f, 1e-30f, 1e18f, 1e30f, -1.0f, NAN};
    const float scale = scales[data[2] % 8];
    std::vector<float> planes[3];
    size_t at = 3;
    for (auto& plane : planes) {
        plane.assign(size_t(w) * h, 0.0f);
        for (float& v : plane) {
            if (at + 4 > size) break;
            std::memcpy(&v, data + at, 4);
            at += 4;
        }
    }
    auto map = vastray::makeEnvironmentMap("fuzz", w, h, planes[0], planes[1], planes[2], scale);
    if (!map) return 0;
    const vastray::Frame frames[] = {vastray::environmentFrame({0, 1, 0}, 0.0f), vastray::environmentFrame({0, 0, 1}, 90.0f),
                                     vastray::environmentFrame(vastray::normalize(vastray::Vec3f{1, -2, 0.5f}), -33.0f)};
    for (int i = 0; i < 64; ++i) {
        const vastray::Frame& up = frames[i % 3];
        const float u1 = float((i * 37) % 64) / 64.0f, u2 = float((i * 11) % 64) / 64.0f;
        const vastray::EnvironmentSample s = vastray::sampleEnvironment(**map, up, u1, u2);
        if (!(s.pdf >= 0.0f) || !std::isfinite(s.pdf)) std::abort();
        if (s.pdf > 0.0f) {
            if (std::fabs(vastray::length(s.direction) - 1.0f) > 1e-4f) std::abort();
            for (int c = 0; c < 3; ++c)
                if (!(s.radiance[c] >= 0.0f) || !std::isfinite(s.radiance[c])) std::abort();
            const float pdf = vastray::environmentPdf(**map, up, s.direction);
            if (!(pdf >= 0.0f) || !std::isfinite(pdf)) std::abort();
        }
        const vastray::Vec3f look = vastray::environmentRadiance(**map, up, vastray::normalize({u1 - 0.5f, u2 - 0.5f, 0.3f}));
        for (int c = 0; c < 3; ++c)
            if (!(look[c] >= 0.0f) || !std::isfinite(look[c])) std::abort();
    }
    return 0;
}

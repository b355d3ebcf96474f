#pragma once
// The figures a render reports. The CLI (--stats, --stats-json), the server and the
// benchmarks all read this one struct.
#include <cstdint>
#include <string>

namespace vastray {

struct RenderStats {
    std::string backend;
    double renderSeconds = 0;    // tracing and shading only: no scene load or BVH build
    double buildSeconds = 0;     // acceleration structure build
    uint64_t rays = 0;           // camera, AOV, scattered and shadow rays traced
    uint64_t triangles = 0;      // distinct triangles in the scene
    uint64_t peakHostBytes = 0;  // peak resident set of the process

    double raysPerSecond() const { return renderSeconds > 0 ? double(rays) / renderSeconds : 0.0; }
};

// Peak resident set size of this process so far (getrusage), in bytes.
uint64_t peakHostBytes();

}  // namespace vastray

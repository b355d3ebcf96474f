#pragma once
// Helpers shared by the importers (private to streamer/src/import).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <new>
#include <string>
#include <string_view>
#include <vector>

#include "vastray/core/Mesh.h"
#include "vastray/core/Result.h"
#include "vastray/core/VertexAttributes.h"

namespace vastray::import {

// "dir/bunny.ply" -> "bunny.ply": every message is prefixed with the file name only.
std::string fileNameOf(const std::string& path);

// "dir/bunny.ply" -> "dir"; "bunny.ply" -> ".".
std::string directoryOf(const std::string& path);

// Lower-case extension without the dot ("GLB" -> "glb"), empty when there is none.
std::string lowerExtension(const std::string& path);

// Relative URIs inside the model folder only: no scheme (file:, http:, C:), no absolute
// path, no ".." component. data: URIs never reach the file system. Used for glTF buffer URIs
// and OBJ mtllib names alike.
bool isSafeRelativeUri(const std::string& uri, std::string& why);

// Whether `file`, with links resolved, lies inside `folder` (links resolved too). A file
// that does not exist counts as inside when its existing folders do (its read then fails).
bool insideFolder(const std::filesystem::path& folder, const std::filesystem::path& file);

// OBJ faces and PLY face lists are ear-clipped (Triangulate.h): a polygon of 10^6 corners
// imports in about a second. The limit bounds one face's scratch memory, not the time.
constexpr uint64_t kMaxPolygonCorners = uint64_t(1) << 24;

// glTF triangle fans are fans by definition (spec 3.7.2.1): every triangle shares the first
// corner, so the partitioner's cells near that corner each hold all n of them and its time
// grows as n^2 (10^5 corners took 10 s). Exporters write far smaller fans.
constexpr uint64_t kMaxFanCorners = 4096;

// A descriptor for a regular file, refused by name when the path is a FIFO, socket, device
// or directory (a FIFO without a writer would otherwise block the read for ever).
Result<int> openRegularFile(const std::string& path);

// The whole file in memory (regular files only); importers parse from this buffer (no iostreams on the hot path).
Result<std::vector<char>> readWholeFile(const std::string& path);

// Runs an importer body so that no exception crosses the API: allocation failure on a
// huge but honest file, or a throw from a third-party parser, becomes an error value.
template <typename Fn>
auto guarded(const std::string& path, Fn&& body) -> decltype(body()) {
    try {
        return body();
    } catch (const std::bad_alloc&) {
        return Status::error(fileNameOf(path) + ": out of memory while importing");
    } catch (const std::exception& e) {
        return Status::error(fileNameOf(path) + ": " + e.what());
    }
}

// A Phong-style specular colour and exponent (MTL Ks/Ns, assimp's specular colour and shininess)
// as the metallic-roughness model's dielectric layer (docs/RENDERING.md, "Materials"): weight
// the colour's largest component (clamped to 1), GGX alpha sqrt(2 / (exponent + 2)), about the
// width of a Phong lobe of that exponent. No layer when the weight is not above 0.
inline void setPhongSpecular(Material& m, float weight, float exponent) {
    if (!(weight > 0.0f)) return;
    m.specular = std::min(weight, 1.0f);
    m.roughness = std::sqrt(std::sqrt(2.0f / (std::max(exponent, 0.0f) + 2.0f)));
}

// Why a texture coordinate pair is refused ("(nan, 0) is not finite"), or "" when it is kept:
// finite and within +-kMaxAbsUv (docs/HARDENING.md).
inline std::string uvProblem(double u, double v) {
    char text[64];
    std::snprintf(text, sizeof text, "(%.9g, %.9g)", u, v);
    if (!std::isfinite(u) || !std::isfinite(v)) return std::string(text) + " is not finite";
    if (std::fabs(u) > kMaxAbsUv || std::fabs(v) > kMaxAbsUv)
        return std::string(text) + " lies beyond the texture coordinate limit of +-1e6";
    return "";
}

inline Status errorIn(const std::string& fileName, const std::string& message) {
    return Status::error(fileName + ": " + message);
}

}  // namespace vastray::import

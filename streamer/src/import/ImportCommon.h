#pragma once
// Helpers shared by the importers (private to streamer/src/import).
#include <cstdint>
#include <exception>
#include <filesystem>
#include <new>
#include <string>
#include <string_view>
#include <vector>

#include "vastray/core/Result.h"

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

// Polygons (OBJ faces, PLY face lists, glTF triangle fans) are fan-triangulated: every
// triangle of an n-gon shares its first corner, so the partitioner's cells near that corner
// each hold all n of them and its time grows as n^2 (10^5 corners took 10 s, 10^6 did not
// finish). Exporters write far smaller polygons; larger ones are refused by name.
constexpr uint64_t kMaxPolygonCorners = 4096;

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

inline Status errorIn(const std::string& fileName, const std::string& message) {
    return Status::error(fileName + ": " + message);
}

}  // namespace vastray::import

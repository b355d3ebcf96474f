#pragma once
// Helpers shared by the importers (private to streamer/src/import).
#include <cstdint>
#include <exception>
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

// The whole file in memory; importers parse from this buffer (no iostreams on the hot path).
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

#pragma once
#include <string>
#include <vector>

#include "vastray/core/Result.h"
#include "vastray/streamer/ScenePackage.h"

namespace vastray {

// Writes `info` (its chunks' offsets and checksums are filled in here) and the blobs, in
// chunk-id order, to `path + ".tmp"`, then renames it: a crash never leaves a half-written
// package under the real name. Same inputs give the same bytes.
Status writePackage(const std::string& path, PackageInfo& info, const std::vector<std::vector<uint8_t>>& blobs);

}  // namespace vastray

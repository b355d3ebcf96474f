#pragma once
#include <string>
#include <vector>

#include "vastray/core/Result.h"
#include "vastray/streamer/ScenePackage.h"

namespace vastray {

// Writes `info` (its chunks' and volumes' offsets and checksums are filled in here) and the
// blobs, in chunk-id order, to `path + ".tmp"`, then renames it: a crash or an error never leaves
// a half-written package under the real name (nor the .tmp file). Each volume's bricks are read
// one batch at a time (readVolumeBrick: from memory, or from their file for a volume opened with
// openVdbVolume) and written straight away; a brick that cannot be read fails the write with its
// source's message. Same inputs give the same bytes.
Status writePackage(const std::string& path, PackageInfo& info, const std::vector<std::vector<uint8_t>>& blobs);

}  // namespace vastray

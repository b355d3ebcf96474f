#pragma once
#include <functional>
#include <string>
#include <vector>

#include "package/TexturePages.h"
#include "vastray/core/Result.h"
#include "vastray/streamer/ScenePackage.h"

namespace vastray {

// Writes `info` (its chunks' and volumes' offsets and checksums are filled in here) and the
// blobs, in chunk-id order, to `path + ".tmp"`, then renames it: a crash or an error never leaves
// a half-written package under the real name (nor the .tmp file). Each volume's bricks are read
// one batch at a time (readVolumeBrick: from memory, or from their file for a volume opened with
// openVdbVolume) and written straight away; a brick that cannot be read fails the write with its
// source's message. Textures are built one at a time (`build`: decode, mip levels, pages), their
// pages compressed and written, so that one texture's pyramid is in memory at once; the
// materials' maps name them in this order. A texture that cannot be built fails the write with
// its message. Same inputs give the same bytes.
struct TextureInput {
    std::string name;
    std::function<Result<TexturePyramid>()> build;
};
Status writePackage(const std::string& path, PackageInfo& info, const std::vector<std::vector<uint8_t>>& blobs,
                    const std::vector<TextureInput>& textures = {});

}  // namespace vastray

// readEnvironmentMap (vastray/core/EnvironmentMap.h): the image through the OpenImageIO module.
#include "vastray/core/EnvironmentMap.h"
#include "vastray/core/FilePath.h"
#include "vastray/core/ImageFile.h"
#include "PfmFile.h"

namespace vastray {

Result<std::shared_ptr<const EnvironmentMap>> readEnvironmentMap(const std::string& path, float scale) {
    // A .pfm is read here, without the OpenImageIO module (as it is written: PfmFile.h).
    auto channels = lowerExtension(path) == ".pfm" ? readPfmFile(path, kMaxEnvironmentTexels)
                                                    : readImageChannels(path, {"R", "G", "B"}, kMaxEnvironmentTexels);
    if (!channels) return channels.status().withContext("--environment: ");
    for (size_t c = 0; c < 3; ++c)
        if (channels->planes[c].empty())
            return Status::error("--environment: " + path + " has no " + "RGB"[c] +
                                 " channel (an environment map needs R, G and B)");
    return makeEnvironmentMap(path, channels->width, channels->height, channels->planes[0], channels->planes[1],
                              channels->planes[2], scale);
}

}  // namespace vastray

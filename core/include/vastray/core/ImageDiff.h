#pragma once
// Compares two rendered images (vastray diff). Built on OpenImageIO's compare functions.
#include <cstdint>
#include <string>
#include <vector>

#include "vastray/core/Result.h"

namespace vastray {

struct ImageDiffReport {
    uint32_t width = 0, height = 0;
    std::vector<std::string> channels;
    double beautyRmse = 0;  // over R,G,B of every pixel
    double beautyPsnr = 0;  // dB, peak 1.0 (OIIO's definition); +inf when identical
    double beautyMaxError = 0;
    bool hasDepth = false;
    double depthMeanRelativeError = 0;  // mean |zA - zB| / |zB| over pixels where both hit
    uint64_t depthHitMismatch = 0;      // pixels where one image hit and the other missed
    bool hasPrimId = false;
    double primIdAgreement = 0;  // fraction of pixels with the same primid
};

// An error when either file cannot be read, or their sizes or channel lists differ.
Result<ImageDiffReport> diffImageFiles(const std::string& pathA, const std::string& pathB);

}  // namespace vastray

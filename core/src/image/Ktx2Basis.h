#pragma once
// Basis Universal (KHR_texture_basisu: ETC1S with BasisLZ, UASTC with or without Zstandard) through
// Binomial's transcoder, vendored in third_party/basisu (its README says which version and why).
#include <cstdint>
#include <string>
#include <vector>

#include "vastray/core/Result.h"

namespace vastray::ktx2 {

// Level 0 of a Basis Universal KTX2 file (a container readContainer accepted) as width x height
// RGBA8 texels, row 0 first as stored (no swizzle or orientation applied). Errors name `name`.
Result<std::vector<uint8_t>> transcodeBasis(const std::string& name, const std::vector<uint8_t>& bytes);

}  // namespace vastray::ktx2

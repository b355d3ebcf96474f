#pragma once
// A PNG file's bytes of the texels given (the importer's own encoder), for tests writing textures.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "import/PngWriter.h"

namespace vastray::test {

inline std::string png(uint32_t width, uint32_t height, uint32_t channels, const std::vector<uint8_t>& texels) {
    auto bytes = import::encodePng(width, height, channels, texels);
    EXPECT_TRUE(bytes.isOk()) << bytes.message();
    return bytes ? std::string(bytes->begin(), bytes->end()) : std::string();
}

}  // namespace vastray::test

#include <gtest/gtest.h>

#include "vastray/core/ByteSize.h"

namespace vastray {

TEST(ByteSize, ParsesBinarySuffixes) {
    EXPECT_EQ(*parseByteSize("16MiB"), 16ull << 20);
    EXPECT_EQ(*parseByteSize("512 KiB"), 512ull << 10);
    EXPECT_EQ(*parseByteSize("2GiB"), 2ull << 30);
    EXPECT_EQ(*parseByteSize("1.5GiB"), 3ull << 29);
    EXPECT_EQ(*parseByteSize("4096"), 4096u);
    EXPECT_EQ(*parseByteSize("64b"), 64u);
}

TEST(ByteSize, RejectsBadInput) {
    for (const char* bad : {"", "MiB", "-1MiB", "12 parsecs", "0.3B", "99999999999999999999", "20000000TiB"}) {
        auto r = parseByteSize(bad);
        EXPECT_FALSE(r.isOk()) << bad;
        EXPECT_NE(r.message().find(bad[0] ? bad : "size"), std::string::npos) << r.message();
    }
}

TEST(ByteSize, Formats) {
    EXPECT_EQ(formatBytes(512), "512 B");
    EXPECT_EQ(formatBytes(16ull << 20), "16.0 MiB");
}

}  // namespace vastray

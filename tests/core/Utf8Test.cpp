// Names kept in a package's fixed fields stay whole, valid UTF-8 (vastray/core/Utf8.h).
#include <gtest/gtest.h>

#include "vastray/core/Utf8.h"

namespace vastray {
namespace {

TEST(Utf8, CutNeverSplitsACharacter) {
    std::string euro;  // 3 bytes each: 21 take 63 bytes, the 22nd would straddle 64
    for (int i = 0; i < 30; ++i) euro += "\xE2\x82\xAC";
    EXPECT_EQ(cutUtf8(euro, 64), euro.substr(0, 63));
    EXPECT_EQ(cutUtf8(euro, 63), euro.substr(0, 63));
    EXPECT_EQ(cutUtf8(euro, 2), "") << "no whole character fits";
    EXPECT_EQ(cutUtf8("abc", 64), "abc");
    EXPECT_EQ(cutUtf8(std::string("ab\0cd", 5), 64), "ab");
    EXPECT_EQ(cutUtf8(std::string(10, '\x80'), 4), std::string(4, '\x80')) << "not UTF-8: cut at the limit";
    EXPECT_EQ(validUtf8(cutUtf8(euro, 64)), cutUtf8(euro, 64));
}

TEST(Utf8, InvalidBytesBecomeQuestionMarks) {
    const std::string valid = "Caf\xC3\xA9 \xE2\x82\xAC \xF0\x9F\x8E\xA5 \xF4\x8F\xBF\xBF";  // é, €, 🎥, U+10FFFF
    EXPECT_EQ(validUtf8(valid), valid);
    EXPECT_EQ(validUtf8("ab\xE2\x82"), "ab??") << "a character cut short";
    EXPECT_EQ(validUtf8("\x80x"), "?x") << "a lone continuation byte";
    EXPECT_EQ(validUtf8("\xC0\x80"), "??") << "an overlong NUL";
    EXPECT_EQ(validUtf8("\xE0\x80\xAF"), "???") << "an overlong '/'";
    EXPECT_EQ(validUtf8("\xED\xA0\x80"), "???") << "a surrogate";
    EXPECT_EQ(validUtf8("\xF4\x90\x80\x80"), "????") << "above U+10FFFF";
    EXPECT_EQ(validUtf8("\xFF\xFE"), "??");
    EXPECT_EQ(validUtf8(""), "");
}

}  // namespace
}  // namespace vastray

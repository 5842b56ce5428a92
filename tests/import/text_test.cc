// Text from source files: names in other encodings become UTF-8, and file bytes shown in messages are
// quoted and escaped (src/core/text.h).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "core/text.h"

namespace mocap {
namespace {

TEST(ImportText, ValidUtf8IsKeptAndOtherTextIsReadAsWindows1252) {
  EXPECT_EQ(TextToUtf8("Kopf \xc3\xa9"), "Kopf \xc3\xa9");  // already UTF-8: unchanged
  EXPECT_EQ(TextToUtf8("Kopf \xe9"), "Kopf \xc3\xa9");      // cp1252 e-acute
  EXPECT_EQ(TextToUtf8("\x80\x99\x81"), "\xe2\x82\xac\xe2\x84\xa2\xc2\x81");  // euro, trademark, undefined
  EXPECT_FALSE(IsValidUtf8("\xc0\xaf"));      // overlong '/'
  EXPECT_FALSE(IsValidUtf8("\xed\xa0\x80"));  // surrogate
  EXPECT_TRUE(IsValidUtf8(TextToUtf8("\xff\xfe\xc3")));
  // One line in cp1252 does not change how the UTF-8 lines around it are read.
  EXPECT_EQ(LinesToUtf8("\xc3\xa9\n\xe9\n"), "\xc3\xa9\n\xc3\xa9\n");
}

TEST(ImportText, QuoteForMessageEscapesControlAndInvalidBytesAndTruncates) {
  EXPECT_EQ(QuoteForMessage("Probe"), "'Probe'");
  EXPECT_EQ(QuoteForMessage("\x1b]0;pwned\x07"), "'\\x1b]0;pwned\\x07'");
  EXPECT_EQ(QuoteForMessage("a'b\\c\n"), "'a\\x27b\\x5cc\\x0a'");
  EXPECT_EQ(QuoteForMessage("\xe9\xc3\xa9"), "'\\xe9\xc3\xa9'");  // invalid escaped, valid UTF-8 kept
  EXPECT_EQ(QuoteForMessage("\xc2\x9b" "2J"), "'\\xc2\\x9b2J'");   // the 8-bit CSI is a control too
  EXPECT_EQ(QuoteForMessage(std::string(500, 'x'), 10), "'xxxxxxxxxx'...");
  EXPECT_EQ(QuoteForMessage("ab\xc3\xa9", 3), "'ab\\xc3'...");  // a character cut in half is escaped
}

}  // namespace
}  // namespace mocap

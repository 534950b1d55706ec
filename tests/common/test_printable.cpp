#include <gtest/gtest.h>

#include <string>

#include "thermodec/common/printable.h"

using namespace thermodec;

TEST(Printable, escapes_terminal_sequences_direction_overrides_and_invalid_utf8) {
  EXPECT_EQ(printable("radiator"), "radiator");
  EXPECT_EQ(printable("Kühler ☀"), "Kühler ☀");  // valid UTF-8 stays as it is
  EXPECT_EQ(printable("\x1b[31mred"), "\\x1b[31mred");
  EXPECT_EQ(printable("a\u202Eb"), "a\\u202eb");
  EXPECT_EQ(printable("nul\0byte", 99), "nul");  // a C string ends at NUL; a view keeps it
  EXPECT_EQ(printable(std::string_view("nul\0byte", 8)), "nul\\x00byte");
  EXPECT_EQ(printable("\xff\xfe"), "\\xff\\xfe");
  EXPECT_EQ(printable("\xc2\x9b"), "\\x9b");  // C1 control (CSI)
}

TEST(Printable, cuts_a_huge_field_and_says_how_long_it_was) {
  const std::string field(1 << 20, 'x');
  const std::string shown = printable(field, 40);
  EXPECT_EQ(shown, std::string(40, 'x') + "... (1048576 bytes)");
}

TEST(Printable, names_control_characters) {
  EXPECT_FALSE(has_control_characters("solar array +Y"));
  EXPECT_FALSE(has_control_characters("Kühler"));
  EXPECT_TRUE(has_control_characters("tab\there"));
  EXPECT_TRUE(has_control_characters("\x1b[2J"));
  EXPECT_TRUE(has_control_characters("x\u202Ey"));
  EXPECT_TRUE(has_control_characters("x\u2066y"));
  EXPECT_TRUE(has_control_characters("\x7f"));
}

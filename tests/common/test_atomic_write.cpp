#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/scratch_dir.h"
#include "thermodec/common/atomic_write.h"
#include "thermodec/common/errors.h"

namespace fs = std::filesystem;
using namespace thermodec;

namespace {
fs::path temp_dir(const char* name) { return thermodec::test::scratch_dir("thermodec_test", name); }
std::string read(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}
}  // namespace

TEST(AtomicWrite, writes_whole_file_and_leaves_no_temporary) {
  auto d = temp_dir("aw1");
  write_text_atomically(d / "sub" / "out.txt", "hello");
  EXPECT_EQ(read(d / "sub" / "out.txt"), "hello");
  int n = 0;
  for (auto& e : fs::directory_iterator(d / "sub")) { (void)e; ++n; }
  EXPECT_EQ(n, 1);
}

TEST(AtomicWrite, failed_writer_keeps_previous_content) {
  auto d = temp_dir("aw2");
  write_text_atomically(d / "out.txt", "old");
  EXPECT_THROW(write_file_atomically(d / "out.txt", [](std::ostream&) { throw InvalidInput("x"); }),
               InvalidInput);
  EXPECT_EQ(read(d / "out.txt"), "old");
}

TEST(AtomicWrite, refuses_to_overwrite_an_input) {
  auto d = temp_dir("aw3");
  write_text_atomically(d / "in.obj", "v 0 0 0\n");
  EXPECT_THROW(write_text_atomically(d / "in.obj", "x", {d / "in.obj"}), InvalidInput);
  EXPECT_EQ(read(d / "in.obj"), "v 0 0 0\n");
}

// io/subprocess.h: external programs run without a shell.

#include "io/subprocess.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "io/text_file.h"
#include "support/scratch_dir_test.h"

namespace softwrist::io {
namespace {

using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

class Subprocess : public testing::ScratchDirTest {};

// Exit status, captured output, input written to a child, a missing program named, and a child that stops reading
// reported instead of killing us with SIGPIPE.
TEST_F(Subprocess, RunsWithoutAShell) {
  EXPECT_EQ(run_process({"sh", "-c", "exit 3"}), 3);
  EXPECT_EQ(run_process({"sh", "-c", "kill -9 $$"}), 128 + 9);
  EXPECT_EQ(run_process({"echo", "a b", "$HOME"}, {.stdout_file = dir_ / "echo.txt"}), 0);
  EXPECT_EQ(read_text_file(dir_ / "echo.txt"), "a b $HOME\n");
  EXPECT_THAT([&] { run_process({"softwrist-no-such-program"}); },
              ThrowsMessage<std::runtime_error>(HasSubstr("cannot run softwrist-no-such-program")));
  {
    ProcessInput cat({"cat"}, {.stdout_file = dir_ / "cat.txt"});
    const std::string text = "frame\n";
    cat.write(reinterpret_cast<const unsigned char*>(text.data()), text.size());
    EXPECT_EQ(cat.finish(), 0);
  }
  EXPECT_EQ(read_text_file(dir_ / "cat.txt"), "frame\n");
  ProcessInput gone({"true"});
  const std::vector<unsigned char> block(1 << 20);
  EXPECT_THAT(
      [&] {
        for (int i = 0; i < 64; ++i) gone.write(block.data(), block.size());
      },
      ThrowsMessage<std::runtime_error>(HasSubstr("true stopped reading its input")));
}

}  // namespace
}  // namespace softwrist::io

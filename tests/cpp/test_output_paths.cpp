// Outputs are never inputs, nor each other, nor a file of another kind; one writer per output
// (a lock with the owner's pid and host; stale locks of dead processes taken over).
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "app/output_paths.hpp"
#include "io/file_header.hpp"
#include "io/h5_file.hpp"
#include "io/output_lock.hpp"
#include "io_test_support.hpp"

using namespace granudrag;
using namespace granudrag::support;

namespace {

void write_text(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

void write_kind(const std::string& path, const std::string& format) {
  h5::File f = h5::File::create(path);
  write_file_header(f, format);
  f.commit();
}

}  // namespace

TEST(OutputPaths, AnOutputThatIsAnInputIsRefusedByPathSymlinkAndHardLink) {
  TempDir dir;
  write_kind(dir.file("b.h5"), "granudrag-bed");
  const std::string bed = dir.file("b.h5");
  const std::string same = error_of([&] {
    check_outputs({{"bed", bed}}, {{"output", bed, "granudrag-run"}});
  });
  EXPECT_MENTIONS(same,
                  "--output " + bed + " is the same file as --bed " + bed + ": choose another output path");
  // Another spelling of the same path.
  std::filesystem::create_directory(dir.file("sub"));
  const std::string dotted = dir.file("sub/../b.h5");
  EXPECT_MENTIONS(error_of([&] {
                    check_outputs({{"bed", bed}}, {{"output", dotted, "granudrag-run"}});
                  }),
                  "is the same file as --bed");
  std::filesystem::create_symlink(bed, dir.file("soft.h5"));
  EXPECT_MENTIONS(error_of([&] {
                    check_outputs({{"bed", dir.file("soft.h5")}}, {{"output", bed, "granudrag-run"}});
                  }),
                  "is the same file as --bed");
  std::filesystem::create_hard_link(bed, dir.file("hard.h5"));
  EXPECT_MENTIONS(error_of([&] {
                    check_outputs({{"bed", bed}}, {{"output", dir.file("hard.h5"), "granudrag-run"}});
                  }),
                  "--output " + dir.file("hard.h5") + " is the same file as --bed");
  // A different file is fine.
  EXPECT_NO_THROW(check_outputs({{"bed", bed}}, {{"output", dir.file("r.h5"), "granudrag-run"}}));
}

TEST(OutputPaths, TwoOutputsOfOneCommandMustDiffer) {
  TempDir dir;
  const std::string a = dir.file("x");
  EXPECT_MENTIONS(error_of([&] {
                    check_outputs({}, {{"output", a, "text"}, {"the copy", a, "text"}});
                  }),
                  "the copy " + a + " is the same file as --output " + a);
}

TEST(OutputPaths, AFileOfAnotherKindIsNotReplaced) {
  TempDir dir;
  write_kind(dir.file("b.h5"), "granudrag-bed");
  write_kind(dir.file("r.h5"), "granudrag-run");
  write_text(dir.file("notes.txt"), "keep me\n");
  write_text(dir.file("empty.h5"), "");
  EXPECT_EQ(file_kind(dir.file("b.h5")), "granudrag-bed");
  EXPECT_EQ(file_kind(dir.file("notes.txt")), "other");
  EXPECT_EQ(file_kind(dir.file("none")), "missing");
  EXPECT_MENTIONS(error_of([&] {
                    check_outputs({}, {{"output", dir.file("b.h5"), "granudrag-run"}});
                  }),
                  "exists and is a bed file, not a run file");
  EXPECT_MENTIONS(error_of([&] {
                    check_outputs({}, {{"output", dir.file("r.h5"), "granudrag-bed"}});
                  }),
                  "exists and is a run file, not a bed file");
  EXPECT_MENTIONS(error_of([&] {
                    check_outputs({}, {{"output", dir.file("notes.txt"), "granudrag-bed"}});
                  }),
                  "exists and is not an HDF5 file");
  EXPECT_MENTIONS(error_of([&] {
                    check_outputs({}, {{"output", dir.file("b.h5"), "text"}});
                  }),
                  "exists and is a bed file, not a text file");
  EXPECT_MENTIONS(error_of([&] {
                    check_outputs({}, {{"output", dir.path().string(), "text"}});
                  }),
                  "is a directory");
  // Same kind, empty, text over text, and an unreadable checkpoint (moved aside by the pull).
  EXPECT_NO_THROW(check_outputs({}, {{"output", dir.file("r.h5"), "granudrag-run"}}));
  EXPECT_NO_THROW(check_outputs({}, {{"output", dir.file("empty.h5"), "granudrag-bed"}}));
  EXPECT_NO_THROW(check_outputs({}, {{"output", dir.file("notes.txt"), "text"}}));
  EXPECT_NO_THROW(
      check_outputs({}, {{"the checkpoint", dir.file("notes.txt"), "granudrag-checkpoint", false, true}}));
  EXPECT_MENTIONS(
      error_of([&] {
        check_outputs({}, {{"the checkpoint", dir.file("b.h5"), "granudrag-checkpoint", false, true}});
      }),
      "is a bed file, not a checkpoint");
}

TEST(OutputPaths, ConfigFilesAreInputs) {
  const auto in = config_inputs({"--lx", "4", "--config", "a.yaml", "--config=b.yaml"});
  ASSERT_EQ(in.size(), 2u);
  EXPECT_EQ(in[0].path, "a.yaml");
  EXPECT_EQ(in[1].path, "b.yaml");
  EXPECT_MENTIONS(error_of([&] {
                    check_outputs(in, {{"output", "./a.yaml", "text"}});
                  }),
                  "--output ./a.yaml is the same file as --config a.yaml");
}

TEST(OutputLock, ASecondWriterIsRefusedAndTheLockIsRemovedAtTheEnd) {
  TempDir dir;
  const std::string out = dir.file("r.h5");
  {
    OutputLock lock(out);
    const std::string text = read_text(out + ".lock");
    EXPECT_EQ(text, "pid " + std::to_string(::getpid()) + " host " + host_name() + "\n");
    EXPECT_MENTIONS(error_of([&] { OutputLock again(out); }), "already locked by this process");
  }
  EXPECT_FALSE(std::filesystem::exists(out + ".lock"));
  // Held by a live process on this host (the test's parent).
  write_text(out + ".lock", "pid " + std::to_string(::getppid()) + " host " + host_name() + "\n");
  const std::string live = error_of([&] { OutputLock lock(out); });
  EXPECT_MENTIONS(live, "is being written by process " + std::to_string(::getppid()) + " on this host");
  EXPECT_TRUE(std::filesystem::exists(out + ".lock"));
  // Held on another host: cannot be checked, so refused, with the command that removes it.
  write_text(out + ".lock", "pid 12 host some-other-node\n");
  const std::string foreign = error_of([&] { OutputLock lock(out); });
  EXPECT_MENTIONS(foreign, "on host some-other-node");
  EXPECT_MENTIONS(foreign, "rm '" + out + ".lock'");
  // Unreadable lock: refused, saying how to remove it.
  write_text(out + ".lock", "garbage");
  EXPECT_MENTIONS(error_of([&] { OutputLock lock(out); }), "rm '" + out + ".lock'");
}

TEST(OutputLock, AStaleLockOfADeadProcessIsTakenOver) {
  TempDir dir;
  const std::string out = dir.file("r.h5");
  // A child that exits at once: its pid is then not running (reaped below).
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  ASSERT_GT(child, 0);
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  write_text(out + ".lock", "pid " + std::to_string(child) + " host " + host_name() + "\n");
  {
    OutputLock lock(out);
    EXPECT_EQ(read_text(out + ".lock"), "pid " + std::to_string(::getpid()) + " host " + host_name() + "\n");
  }
  EXPECT_FALSE(std::filesystem::exists(out + ".lock"));
}

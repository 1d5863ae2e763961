// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/io/atomic_file.h"

#include <gtest/gtest.h>

#include <stdexcept>

#include "io/io_test_util.h"
#include "ramiform/core/errors.h"

namespace ramiform {
namespace {

using io_test::read_bytes;
using io_test::TempDir;
using io_test::write_bytes;

struct WriterBroke : std::runtime_error {
  WriterBroke() : std::runtime_error("writer broke") {}
};

TEST(AtomicFile, WritesContentAndLeavesNoTemporary) {
  TempDir dir;
  const std::string path = dir.file("out.bin");
  const std::string bytes("a\0b\nc\r\n", 7);
  write_file_atomically(
      path, [&](std::ostream& out) { out.write(bytes.data(), 7); }, FileMode::kBinary);
  EXPECT_EQ(read_bytes(path), bytes);
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"out.bin"});
}

TEST(AtomicFile, ReplacesAnExistingFile) {
  TempDir dir;
  const std::string path = dir.file("out.txt");
  write_bytes(path, "old content that is longer");
  write_file_atomically(path, [](std::ostream& out) { out << "new"; });
  EXPECT_EQ(read_bytes(path), "new");
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"out.txt"});
}

TEST(AtomicFile, ThrowingWriterLeavesNothingBehind) {
  TempDir dir;
  const std::string path = dir.file("out.txt");
  EXPECT_THROW(write_file_atomically(path,
                                     [](std::ostream& out) {
                                       out << "partial output";
                                       out.flush();
                                       throw WriterBroke();
                                     }),
               WriterBroke);
  EXPECT_FALSE(io_test::fs::exists(path));
  EXPECT_TRUE(dir.entries().empty());
}

TEST(AtomicFile, ThrowingWriterKeepsTheOldFile) {
  TempDir dir;
  const std::string path = dir.file("keep.txt");
  write_bytes(path, "precious");
  EXPECT_THROW(write_file_atomically(path, [](std::ostream&) { throw WriterBroke(); }),
               WriterBroke);
  EXPECT_EQ(read_bytes(path), "precious");
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"keep.txt"});
}

TEST(AtomicFile, StreamFailureIsAFailureAndLeavesNothing) {
  TempDir dir;
  const std::string path = dir.file("bad.txt");
  try {
    write_file_atomically(path, [](std::ostream& out) {
      out << "x";
      out.setstate(std::ios::badbit);
    });
    FAIL() << "expected Failure";
  } catch (const Failure& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
  EXPECT_TRUE(dir.entries().empty());
}

TEST(AtomicFile, MissingDirectoryIsNotCreated) {
  TempDir dir;
  const std::string path = dir.file("no/such/dir/out.txt");
  try {
    write_file_atomically(path, [](std::ostream& out) { out << "x"; });
    FAIL() << "expected Failure";
  } catch (const Failure& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("does not exist"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(io_test::fs::exists(dir.path() / "no"));
}

TEST(AtomicFile, TargetThatIsADirectoryFails) {
  TempDir dir;
  io_test::fs::create_directory(dir.path() / "sub");
  EXPECT_THROW(write_file_atomically(dir.file("sub"), [](std::ostream& out) { out << "x"; }),
               Failure);
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"sub"});
}

TEST(HeldOutputs, NothingAppearsUntilPublishAndEverythingThen) {
  TempDir dir;
  write_bytes(dir.file("b.txt"), "old b");
  HeldOutputs group;
  write_file_atomically(group.add(dir.file("a.txt")), [](std::ostream& out) { out << "A"; });
  write_file_atomically(group.add(dir.file("b.txt")), [](std::ostream& out) { out << "B"; });
  // Writing the same target again replaces its held content.
  write_file_atomically(group.add(dir.file("a.txt")), [](std::ostream& out) { out << "A2"; });
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"b.txt"});
  EXPECT_EQ(read_bytes(dir.file("b.txt")), "old b");
  group.publish();
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"a.txt", "b.txt"}));
  EXPECT_EQ(read_bytes(dir.file("a.txt")), "A2");
  EXPECT_EQ(read_bytes(dir.file("b.txt")), "B");
}

TEST(HeldOutputs, AGroupDroppedBeforePublishLeavesNothing) {
  TempDir dir;
  write_bytes(dir.file("keep.txt"), "precious");
  {
    HeldOutputs group;
    write_file_atomically(group.add(dir.file("new.txt")), [](std::ostream& out) { out << "x"; });
    write_file_atomically(group.add(dir.file("keep.txt")), [](std::ostream& out) { out << "y"; });
    // A later step fails: the group goes out of scope unpublished.
  }
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"keep.txt"});
  EXPECT_EQ(read_bytes(dir.file("keep.txt")), "precious");
}

}  // namespace
}  // namespace ramiform

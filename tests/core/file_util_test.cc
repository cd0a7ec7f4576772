#include "core/file_util.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "tests/test_util.h"

namespace semvox {
namespace {

size_t CountFiles(const std::filesystem::path& dir) {
  size_t n = 0;
  for (auto& e : std::filesystem::directory_iterator(dir)) n += e.is_regular_file();
  return n;
}

TEST(WriteFileAtomic, WritesContentAndLeavesNoTemporary) {
  testing::ScratchDir dir("atomic");
  ASSERT_TRUE(WriteFileAtomic(dir.File("a.txt"), "hello").ok());
  EXPECT_EQ(testing::ReadText(dir.File("a.txt")), "hello");
  ASSERT_TRUE(WriteFileAtomic(dir.File("a.txt"), "again").ok());
  EXPECT_EQ(testing::ReadText(dir.File("a.txt")), "again");
  EXPECT_EQ(CountFiles(dir.path()), 1u);
}

TEST(WriteFileAtomic, FailsCleanlyWhenTheDirectoryIsMissing) {
  testing::ScratchDir dir("atomic_missing");
  Status st = WriteFileAtomic(dir.File("no/such/dir/a.txt"), "x");
  EXPECT_FALSE(st.ok());
  EXPECT_NE(st.message().find("a.txt"), std::string::npos);
}

TEST(WriteViaTemporary, RemovesTheTemporaryOnFailure) {
  testing::ScratchDir dir("via_tmp");
  Status st = WriteViaTemporary(dir.File("b.bin"), [](const std::string& tmp) {
    testing::WriteText(tmp, "partial");
    return Status::Internal("writer failed");
  });
  EXPECT_FALSE(st.ok());
  EXPECT_EQ(CountFiles(dir.path()), 0u);
}

TEST(EnsureWritableDirectory, CreatesParentsAndRejectsFiles) {
  testing::ScratchDir dir("ensure");
  EXPECT_TRUE(EnsureWritableDirectory(dir.File("x/y/z")).ok());
  testing::WriteText(dir.File("file"), "x");
  Status st = EnsureWritableDirectory(dir.File("file"));
  EXPECT_EQ(st.code(), StatusCode::kInvalidInput);
  EXPECT_FALSE(EnsureWritableDirectory(dir.File("file/sub")).ok());
}

}  // namespace
}  // namespace semvox

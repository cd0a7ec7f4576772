// `semvox rooms` end to end through the binary: a hand-drawn map of two rooms joined by a door gives
// two rooms; bad input gives one clear line and exit code 2 with no output left behind.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <set>

#include "io/image_io.h"
#include "tests/rooms/rooms_test_util.h"
#include "tests/test_util.h"

namespace semvox {
namespace {

struct CliResult {
  int exit_code;
  std::string out, err;
};

CliResult RunSemvox(const testing::ScratchDir& dir, const std::string& args) {
  const std::string out = dir.File("stdout.txt"), err = dir.File("stderr.txt");
  const std::string cmd = std::string(SEMVOX_BINARY) + " " + args + " > " + out + " 2> " + err;
  const int rc = std::system(cmd.c_str());
  return {WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, testing::ReadText(out), testing::ReadText(err)};
}

TEST(RoomsCommand, HandDrawnTwoRoomsWithADoorGiveTwoRooms) {
  ASSERT_TRUE(std::filesystem::exists(SEMVOX_BINARY)) << "build the semvox binary first: " << SEMVOX_BINARY;
  testing::ScratchDir dir("rooms_cli");
  const testing::GreyMap map = testing::TwoRoomsWithDoor();
  ImageRgb8 grey(map.image.width, map.image.height, 1);
  grey.data = map.image.data;
  ASSERT_TRUE(WriteImage(dir.File("map.png"), grey).ok());
  for (const char* method : {"distance", "morphological"}) {
    const std::string out = dir.File(std::string("out_") + method);
    const CliResult r = RunSemvox(dir, "rooms " + dir.File("map.png") + " --resolution 0.05 --method " + method +
                                           " -q -o " + out);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    Result<ImageU16> ids = ReadImageU16(out + "/rooms.png");
    ASSERT_TRUE(ids.ok()) << ids.status().message();
    ASSERT_EQ(ids->width, map.image.width);
    ASSERT_EQ(ids->height, map.image.height);
    std::set<int> rooms(ids->data.begin(), ids->data.end());
    rooms.erase(0);
    EXPECT_EQ(rooms.size(), 2u) << method;
    EXPECT_TRUE(std::filesystem::exists(out + "/rooms.geojson"));
    EXPECT_TRUE(std::filesystem::exists(out + "/rooms.svg"));
  }
}

TEST(RoomsCommand, BadInputIsOneLineAndExitCodeTwo) {
  ASSERT_TRUE(std::filesystem::exists(SEMVOX_BINARY)) << "build the semvox binary first: " << SEMVOX_BINARY;
  testing::ScratchDir dir("rooms_cli_bad");
  CliResult r = RunSemvox(dir, "rooms " + dir.File("missing.png") + " -o " + dir.File("out"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("missing.png"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir.File("out/rooms.png")));
  testing::WriteText(dir.File("not_an_image.png"), "hello");
  r = RunSemvox(dir, "rooms " + dir.File("not_an_image.png") + " -o " + dir.File("out"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("not_an_image.png"), std::string::npos) << r.err;
  r = RunSemvox(dir, "rooms " + dir.File("not_an_image.png") + " --method voronoi -o " + dir.File("out"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
}

}  // namespace
}  // namespace semvox

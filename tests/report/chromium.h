// Headless Chromium for the report tests: loads a page (a file URL, fragment allowed), dumps its DOM, takes a
// screenshot and collects what the page wrote to the console. WebGL runs on SwiftShader (software).
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>

#include "io/image_io.h"
#include "tests/test_util.h"

namespace semvox::testing {

inline int Shell(const std::string& cmd) {
  const int rc = std::system(cmd.c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

// The chromium binary, or "" when it is not installed (tests then skip).
inline std::string FindChromium() {
  for (const char* c : {"/usr/bin/chromium", "/usr/bin/chromium-browser"})
    if (std::filesystem::exists(c)) return c;
  return "";
}

struct PageLoad {
  int exit_code = -1;
  std::string dom;      // --dump-dom after the load event.
  std::string console;  // Lines the page logged (uncaught errors included), one per line.
  std::string log;      // Chromium's whole stderr, for failure messages.
  ImageRgb8 shot;       // Empty unless a window size was given.
};

// Loads `url` once in headless Chromium with a profile under `scratch`; with width > 0 also takes a screenshot
// of a width x height window.
inline PageLoad LoadPage(const std::string& chromium, const std::string& url, const std::string& scratch, int width = 0, int height = 0,
                         const std::string& extra_flags = "") {
  static int counter = 0;
  const std::string tag = scratch + "/chromium" + std::to_string(counter++);
  std::ostringstream cmd;
  cmd << chromium << " --headless --no-sandbox --no-first-run --disable-extensions --hide-scrollbars --force-device-scale-factor=1"
      << " --use-angle=swiftshader --enable-unsafe-swiftshader --enable-logging=stderr --v=0"
      << " --user-data-dir=" << tag << "_profile --dump-dom " << extra_flags;
  if (width > 0) cmd << " --window-size=" << width << "," << height << " --screenshot=" << tag << ".png";
  cmd << " '" << url << "' > " << tag << "_dom.html 2> " << tag << "_log.txt";
  PageLoad p;
  p.exit_code = Shell(cmd.str());
  p.dom = ReadText(tag + "_dom.html");
  p.log = ReadText(tag + "_log.txt");
  std::istringstream lines(p.log);
  for (std::string line; std::getline(lines, line);)
    if (line.find(":CONSOLE") != std::string::npos) p.console += line + "\n";
  if (width > 0) {
    Result<ImageRgb8> img = ReadImageRgb8(tag + ".png");
    if (img.ok()) p.shot = std::move(img).value();
  }
  return p;
}

}  // namespace semvox::testing

// `dmgplace view` end to end: place on the built-in cabinet, write the page, open it in Debian's
// headless chromium and check from the dumped DOM that the scene rendered without script errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>

#include "dmgplace/tools/viewer/write_viewer.hpp"
#include "run_cli.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using namespace dmgplace;

namespace {

// `dmgplace ARGS...`'s exit code; its output is not needed.
int cli(const std::vector<test::Arg>& args) { return test::run_cli(args, false).exit_code; }

std::string chromium() {
  for (const char* c : {"chromium", "chromium-browser"})
    if (const auto found = tools::find_executable(c)) return found->string();
  return {};
}

// The value of data-NAME on the status element of the dumped DOM, or "" when missing.
std::string status_attr(const std::string& dom, const std::string& name) {
  std::smatch m;
  const std::regex status_div("<div id=\"dmgplace-status\"[^>]*>");
  if (!std::regex_search(dom, m, status_div)) return {};
  const std::string tag = m.str();
  if (!std::regex_search(tag, m, std::regex("data-" + name + "=\"([^\"]*)\""))) return {};
  return m[1];
}

class Viewer : public ::testing::Test {
 protected:
  // Bakes the cabinet, dmgarm and the bottle once, places for ~2 s and writes the page.
  static void SetUpTestSuite() {
    test::set_up_suite_or_exit("Viewer", [] { bake(); });
  }
  static void bake() {
    dir_ = new test::TempDir();
    const fs::path data = test::source_dir() / "datasets", d = dir_->path(), art = d / "artifacts";
    fs::create_directories(art);
    ASSERT_EQ(cli({"make-objects", "--out", d}), 0);
    ASSERT_EQ(cli({"bake-robot", data / "robots/dmgarm/dmgarm.urdf", "--srdf", data / "robots/dmgarm/dmgarm.srdf",
                   "--arm", "dmgarm_link0:dmgarm_tcp", "--out", art / "dmgarm.h5"}),
              0);
    ASSERT_EQ(cli({"bake-object", d / "bottle.stl", "--mass", "0.15", "--out", art / "bottle.h5"}), 0);
    const std::string volume = test::builtin_volume("cabinet");
    ASSERT_EQ(cli({"bake-env", data / "scenes/cabinet.yaml", "--volume", volume, "--out", art / "cabinet.h5"}), 0);
    // Exit 3 means "no solution": the page must still show the scene, so both are fine here.
    const int placed = cli({"place", data / "queries/cabinet_bottle_side.yaml", "--artifacts", art, "--time-limit", "3",
                            "--out", d / "place"});
    ASSERT_TRUE(placed == 0 || placed == 3) << "place exited with " << placed;
    ASSERT_EQ(cli({"view", d / "place", "--html", d / "scene.html"}), 0);
  }
  static void TearDownTestSuite() { delete dir_; }
  static test::TempDir* dir_;
};
test::TempDir* Viewer::dir_ = nullptr;

}  // namespace

TEST_F(Viewer, PageRendersInHeadlessChromium) {
  const std::string browser = chromium();
  if (browser.empty()) GTEST_SKIP() << "chromium is not installed; scripts/deps installs it";
  const fs::path d = dir_->path(), page = d / "scene.html";
  const nlohmann::json result = nlohmann::json::parse(test::read_text(d / "place/result.json"));
  std::size_t waypoints = 0;
  if (result["solved"].get<bool>()) waypoints = result["best"]["path"].size() + result["best"]["retreat"].size();
  std::printf("placement %s: %zu path+retreat waypoints\n", result["solved"].get<bool>() ? "solved" : "not solved",
              waypoints);
  if (!result["solved"].get<bool>()) std::printf("  %s\n", result.value("reason", std::string()).c_str());

  // SwiftShader: software WebGL, so no GPU is needed; virtual time lets the page run its frames.
  const std::vector<std::string> flags = {browser,
                                          "--headless",
                                          "--no-sandbox",
                                          "--disable-gpu",
                                          "--use-angle=swiftshader",
                                          "--enable-unsafe-swiftshader",
                                          "--window-size=1024,768",
                                          "--virtual-time-budget=5000",
                                          "--user-data-dir=" + (d / "profile").string()};
  const std::string url = "file://" + page.string();
  auto with = [&](std::vector<std::string> extra) {
    std::vector<std::string> argv = flags;
    argv.insert(argv.end(), extra.begin(), extra.end());
    return argv;
  };
  test::ProcessOptions capture_log;
  capture_log.stderr_to = test::StderrTo::capture;  // chromium's log, checked for script errors
  const test::ProcessResult dom =
      tools::run_process(with({"--enable-logging=stderr", "--v=0", "--dump-dom", url}), capture_log);
  const std::string& log = dom.error_output;
  ASSERT_EQ(dom.exit_code, 0) << log;
  EXPECT_EQ(log.find("Uncaught"), std::string::npos) << log;
  EXPECT_EQ(status_attr(dom.output, "errors"), "0")
      << dom.output.substr(std::min(dom.output.size(), dom.output.find("<div id=\"errors\"")), 2000);
  EXPECT_EQ(status_attr(dom.output, "ready"), "true");
  EXPECT_EQ(status_attr(dom.output, "steps"), std::to_string(waypoints));
  EXPECT_NE(dom.output.find("steps: " + std::to_string(waypoints)), std::string::npos);
  EXPECT_GE(std::atoi(status_attr(dom.output, "rendered").c_str()), 1);
  // The robot, the cabinet and the object fill a good part of the 1024x768 canvas.
  EXPECT_GT(std::atof(status_attr(dom.output, "nonbackground").c_str()), 0.05);

  const fs::path shot = d / "shot.png";
  test::ProcessOptions quiet;
  quiet.stderr_to = test::StderrTo::discard;
  const test::ProcessResult shoot = tools::run_process(with({"--screenshot=" + shot.string(), url}), quiet);
  ASSERT_EQ(shoot.exit_code, 0);
  const std::string png = test::read_text(shot);
  ASSERT_GT(png.size(), 20000u) << "a near-empty screenshot";
  EXPECT_EQ(png.substr(1, 3), "PNG");
  // Keep it for people to look at when the test runs in CI.
  const fs::path keep = fs::temp_directory_path() / "dmgplace-viewer-test.png";
  std::error_code ec;
  fs::copy_file(shot, keep, fs::copy_options::overwrite_existing, ec);
  std::printf("screenshot: %s\n", (ec ? shot : keep).c_str());
}

TEST_F(Viewer, PageIsSelfContained) {
  const std::string html = test::read_text(dir_->path() / "scene.html");
  EXPECT_NE(html.find("\"three\": \"data:text/javascript;base64,"), std::string::npos);
  EXPECT_EQ(html.find("http://"), std::string::npos);
  EXPECT_EQ(html.find("src=\"http"), std::string::npos);
}

// A trajectory.json beside the result whose times run backwards is refused, naming it and the element.
TEST_F(Viewer, ABadTrajectoryNamesTheFileAndElement) {
  const fs::path place = dir_->path() / "place";
  if (!nlohmann::json::parse(test::read_text(place / "result.json"))["solved"].get<bool>())
    GTEST_SKIP() << "no solution in the placement's time";
  nlohmann::json t = nlohmann::json::parse(test::read_text(place / "trajectory.json"));
  ASSERT_GE(t["approach"]["time"].size(), 2u);
  t["approach"]["time"][1] = -1.0;
  test::TempDir d;
  fs::copy_file(place / "result.json", d / "result.json");
  test::write_text(d / "trajectory.json", t.dump());
  const std::string msg =
      test::error_of([&] { tools::viewer::write_viewer(d.path(), d / "x.html", dir_->path() / "artifacts"); });
  EXPECT_NE(msg.find((d.path() / "trajectory.json").string() + ": /approach/time/1"), std::string::npos) << msg;
  EXPECT_FALSE(fs::exists(d / "x.html"));
}

TEST(ViewerInput, MissingResultNamesTheFile) {
  test::TempDir d;
  const std::string msg = test::error_of([&] { tools::viewer::write_viewer(d.path(), d / "x.html"); });
  EXPECT_NE(msg.find((d.path() / "result.json").string()), std::string::npos) << msg;
  EXPECT_FALSE(fs::exists(d / "x.html"));
}

TEST(ViewerInput, BadResultNamesTheElement) {
  test::TempDir d;
  test::write_text(d / "result.json", R"({"query": {"robot": "r.h5", "object": "o.h5", "environment": "e.h5",
    "start": [0, 0], "initial_grasp": [0, 0, 0, 0, 0, 0, 1]}, "joint_names": ["a", "b"], "solved": true,
    "best": {"time": 1, "objective": 2, "pose": [0, 0, 0], "grasp": {}}})");
  const std::string msg = test::error_of([&] { tools::viewer::write_viewer(d.path(), d / "x.html"); });
  EXPECT_NE(msg.find("result.json: /best/pose"), std::string::npos) << msg;
}

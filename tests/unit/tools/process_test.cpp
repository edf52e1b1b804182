// run_process and find_executable: arguments reach the program exactly as given (no shell ever
// sees them), exit codes and signals come back, and failures to start are clear errors. Also the
// whitelist for names that become file names.
#include <gtest/gtest.h>
#include <signal.h>

#include <filesystem>
#include <string>
#include <vector>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/tools/system/file_names.hpp"
#include "dmgplace/tools/system/process.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using namespace dmgplace;
using namespace dmgplace::tools;

namespace {
// Texts a shell would expand, split or run.
const std::vector<std::string> kTricky = {"two words",
                                          "'single'",
                                          "\"double\"",
                                          "$(touch PWNED)",
                                          "`touch PWNED`",
                                          "x'$(touch PWNED)'",
                                          "a;touch PWNED",
                                          "*",
                                          "$HOME",
                                          "back\\slash",
                                          "new\nline",
                                          "",
                                          "-n",
                                          "> PWNED"};
}  // namespace

TEST(RunProcess, ArgumentsArePassedVerbatim) {
  test::TempDir dir;
  ProcessOptions o;
  o.cwd = dir.path();  // where a shell would have created PWNED
  for (const std::string& arg : kTricky) {
    const ProcessResult r = run_process({"printf", "%s", arg}, o);
    EXPECT_EQ(r.exit_code, 0) << arg;
    EXPECT_EQ(r.output, arg);
  }
  // All at once: each stays one argument.
  std::vector<std::string> argv{"printf", "[%s]"};
  std::string expected;
  for (const std::string& arg : kTricky) {
    argv.push_back(arg);
    expected += "[" + arg + "]";
  }
  const ProcessResult r = run_process(argv, o);
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_EQ(r.output, expected);
  EXPECT_TRUE(fs::is_empty(dir.path())) << "a shell ran one of the arguments";
}

TEST(RunProcess, ExitCodesAndSignalsArePropagated) {
  EXPECT_EQ(run_process({"true"}).exit_code, 0);
  EXPECT_EQ(run_process({"false"}).exit_code, 1);
  EXPECT_EQ(run_process({"timeout", "0.05", "sleep", "5"}).exit_code, 124);
  ProcessOptions quiet;
  quiet.stderr_to = StderrTo::discard;
  EXPECT_EQ(run_process({"env", "/nonexistent/dmgplace-test-program"}, quiet).exit_code, 127);
  // timeout re-raises the signal that ended its command on itself: a child killed by SIGKILL.
  const ProcessResult killed = run_process({"timeout", "--preserve-status", "-s", "KILL", "0.05", "sleep", "5"});
  EXPECT_EQ(killed.signal, SIGKILL);
  EXPECT_EQ(killed.exit_code, -1);
  EXPECT_EQ(run_process({"true"}).signal, 0);
}

TEST(RunProcess, AProgramThatCannotStartIsAClearError) {
  std::string e = test::error_of([] { run_process({"dmgplace-no-such-program-7f3a", "x"}); });
  EXPECT_NE(e.find("dmgplace-no-such-program-7f3a"), std::string::npos) << e;
  EXPECT_NE(e.find("not found in $PATH"), std::string::npos) << e;
  e = test::error_of([] { run_process({"/nonexistent/dmgplace-prog"}); });
  EXPECT_NE(e.find("/nonexistent/dmgplace-prog: cannot run: No such file or directory"), std::string::npos) << e;
  test::TempDir dir;
  test::write_text(dir / "not_executable", "#!/bin/sh\n");
  e = test::error_of([&] { run_process({(dir / "not_executable").string()}); });
  EXPECT_NE(e.find((dir / "not_executable").string() + ": cannot run: Permission denied"), std::string::npos) << e;
  e = test::error_of([&] {
    ProcessOptions o;
    o.cwd = dir / "no_such_folder";
    run_process({"true"}, o);
  });
  EXPECT_NE(e.find((dir / "no_such_folder").string()), std::string::npos) << e;
  EXPECT_NE(e.find("not a folder"), std::string::npos) << e;
  e = test::error_of([] { run_process({}); });
  EXPECT_NE(e.find("no program to run"), std::string::npos) << e;
}

TEST(RunProcess, WorkingFolderEnvironmentAndInput) {
  test::TempDir dir;
  ProcessOptions o;
  o.cwd = dir.path();
  EXPECT_EQ(run_process({"pwd", "-P"}, o).output, fs::canonical(dir.path()).string() + "\n");
  // A relative program path means the caller's folder, not the child's (and may hold a space).
  const auto printf_program = find_executable("printf");
  ASSERT_TRUE(printf_program.has_value());
  fs::create_directories(dir / "bin dir");
  fs::copy_file(*printf_program, dir / "bin dir/my printf");
  struct InFolder {  // this process's working folder, restored on every way out
    fs::path before = fs::current_path();
    explicit InFolder(const fs::path& p) { fs::current_path(p); }
    ~InFolder() { fs::current_path(before); }
  };
  {
    InFolder in_dir(dir.path());
    ProcessOptions elsewhere;
    elsewhere.cwd = "/";
    EXPECT_EQ(run_process({"bin dir/my printf", "%s", "relative"}, elsewhere).output, "relative");
  }

  ProcessOptions env;
  env.env = {{"DMGPLACE_TEST_VAR", "a b $(touch PWNED)"}, {"HOME", "/nowhere"}, {"DMGPLACE_TEST_VAR", "last wins"}};
  EXPECT_EQ(run_process({"printenv", "DMGPLACE_TEST_VAR"}, env).output, "last wins\n");
  EXPECT_EQ(run_process({"printenv", "HOME"}, env).output, "/nowhere\n");
  ASSERT_NE(std::getenv("PATH"), nullptr);
  EXPECT_EQ(run_process({"printenv", "PATH"}, env).output, std::string(std::getenv("PATH")) + "\n")
      << "the rest is inherited";
  env.env = {{"A=B", "x"}};
  EXPECT_NE(test::error_of([&] { run_process({"true"}, env); }).find("'A=B' is not a variable name"),
            std::string::npos);

  ProcessOptions in;
  in.input = std::string("binary\0data\n", 12);
  EXPECT_EQ(run_process({"cat"}, in).output, *in.input);
  // More than a pipe holds, both ways at once: no deadlock.
  std::string big(3 << 20, 'x');
  for (std::size_t i = 0; i < big.size(); i += 4099) big[i] = char('a' + i % 26);
  in.input = big;
  EXPECT_EQ(run_process({"cat"}, in).output, big);
  // A child that never reads its input: no SIGPIPE for us, its exit code as usual.
  EXPECT_EQ(run_process({"true"}, in).exit_code, 0);
  EXPECT_EQ(run_process({"false"}, in).exit_code, 1);
  // No input: stdin is empty, not this process's.
  EXPECT_EQ(run_process({"cat"}).output, "");
}

TEST(RunProcess, StandardErrorGoesWhereAsked) {
  const std::vector<std::string> both = {"ls", "-d", "/", "/nonexistent-dmgplace-folder"};
  ProcessOptions o;
  o.stderr_to = StderrTo::merge;
  ProcessResult r = run_process(both, o);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("/\n"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("nonexistent-dmgplace-folder"), std::string::npos) << r.output;
  o.stderr_to = StderrTo::capture;
  r = run_process(both, o);
  EXPECT_EQ(r.output, "/\n");
  EXPECT_NE(r.error_output.find("nonexistent-dmgplace-folder"), std::string::npos) << r.error_output;
  o.stderr_to = StderrTo::discard;
  r = run_process(both, o);
  EXPECT_EQ(r.output, "/\n");
  EXPECT_EQ(r.error_output, "");
}

TEST(FindExecutable, SearchesPathWithoutAShell) {
  const auto sh = find_executable("sh");
  ASSERT_TRUE(sh.has_value());
  EXPECT_EQ(sh->filename(), "sh");
  EXPECT_TRUE(fs::exists(*sh));
  EXPECT_FALSE(find_executable("dmgplace-no-such-program-7f3a").has_value());
  EXPECT_FALSE(find_executable("").has_value());
  EXPECT_FALSE(find_executable("sh; touch PWNED").has_value());
  ASSERT_TRUE(find_executable(sh->string()).has_value()) << "a path is checked as it is";
  EXPECT_EQ(*find_executable(sh->string()), *sh);
  // A file that is there but not executable, and a folder, are not programs.
  test::TempDir dir;
  test::write_text(dir / "plain", "x");
  EXPECT_FALSE(find_executable((dir / "plain").string()).has_value());
  EXPECT_FALSE(find_executable(dir.path().string()).has_value());
  // What it finds is what run_process runs.
  const auto printf_program = find_executable("printf");
  ASSERT_TRUE(printf_program.has_value());
  EXPECT_EQ(run_process({printf_program->string(), "%s", "ok"}).output, "ok");
}

TEST(FileNames, OnlyTheWhitelistIsAccepted) {
  for (const char* good : {"a", "cabinet_bottle_side", "no-regrasp", "v1.2", "A-Z_0-9", "...", ".hidden"})
    EXPECT_TRUE(is_safe_file_name(good)) << good;
  for (const char* bad : {"", ".", "..", "a/b", "/abs", "a\\b", "a b", "x'$(touch PWNED)'", "$(id)", "a;b", "tab\t",
                          "new\nline", "caf\xc3\xa9", "q\"", "*", "~"})
    EXPECT_FALSE(is_safe_file_name(bad)) << bad;
  const std::string e =
      test::error_of([] { check_file_name_component("x'$(touch PWNED)'", "spec.yaml", "problems[3].name"); });
  EXPECT_NE(e.find("spec.yaml: problems[3].name: 'x'$(touch PWNED)'"), std::string::npos) << e;
  EXPECT_NE(e.find("letters, digits, '.', '_' and '-'"), std::string::npos) << e;
  EXPECT_NO_THROW(check_file_name_component("side", "spec.yaml", "problems[0].name"));
}

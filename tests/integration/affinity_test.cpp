// Issue 17: inside a CPU set (taskset, a cgroup cpuset, a Slurm allocation) a bake uses the CPUs it
// may run on, not the machine's: `taskset -c 0 dmgplace bake-env` never runs a second thread.
#include <gtest/gtest.h>
#include <sched.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <string>
#include <thread>

#include "test_support.hpp"

namespace {

int threads_of(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("Threads:", 0) == 0) return std::stoi(line.substr(8));
  return 0;
}

}  // namespace

TEST(Affinity, ABakeOnOneCpuRunsOneThread) {
  dmgplace::test::TempDir dir;
  const std::string cli = dmgplace::test::cli_path();
  const std::string scene = (dmgplace::test::source_dir() / "datasets/scenes/cabinet.yaml").string();
  const std::string out = (dir / "cabinet.h5").string();
  const pid_t pid = ::fork();
  if (pid == 0) {
    cpu_set_t one;
    CPU_ZERO(&one);
    CPU_SET(0, &one);
    if (sched_setaffinity(0, sizeof one, &one) != 0) ::_exit(120);
    ::execl(cli.c_str(), cli.c_str(), "bake-env", scene.c_str(), "--volume", "0.55,-0.40,0.45,0.88,0.40,1.05",
            "--margin", "0.9", "--sdf-resolution", "0.015", "--band", "0.25", "--out", out.c_str(), (char*)nullptr);
    ::_exit(127);
  }
  int most = 0, status = 0, samples = 0;
  while (::waitpid(pid, &status, WNOHANG) == 0) {
    most = std::max(most, threads_of(pid));
    ++samples;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ASSERT_TRUE(WIFEXITED(status));
  ASSERT_EQ(WEXITSTATUS(status), 0);
  EXPECT_GT(samples, 10) << "the bake ended before it could be watched";
  EXPECT_EQ(most, 1);
}

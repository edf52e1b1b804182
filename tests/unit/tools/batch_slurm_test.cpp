// `dmgplace batch --slurm` without a cluster: the scripts it writes, and the two sbatch calls it
// makes (a stand-in sbatch records its arguments and answers job ids as sbatch --parsable does).
#include "dmgplace/tools/batch/batch_slurm.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sched.h>
#include <sys/wait.h>
#include <unistd.h>

#include "dmgplace/runtime/system/available_cpus.hpp"
#include "test_support.hpp"

namespace dmgplace::tools {
namespace {
namespace fs = std::filesystem;
using ::testing::HasSubstr;

TEST(BatchSlurm, WritesTwoArrayJobsAndSubmitsTheQueriesAfterTheBakes) {
  test::TempDir dir;
  const fs::path fake = dir / "sbatch";
  test::write_text(fake,
                   "#!/bin/sh\necho \"$@\" >> \"$(dirname \"$0\")/calls.txt\"\n"
                   "n=$(wc -l < \"$(dirname \"$0\")/calls.txt\")\necho \"100$n;cluster\"\n");
  fs::permissions(fake, fs::perms::owner_all);
  SlurmOptions o{
      "/opt/dmgplace/bin/dmgplace", dir / "it's a manifest.yaml", dir / "out", 3, "batch", "01:30:00", fake.string()};
  const auto s = submit_slurm(o);
  EXPECT_EQ(s.bakes_job, "1001");
  EXPECT_EQ(s.queries_job, "1002");
  const std::string calls = test::read_text(dir / "calls.txt");
  EXPECT_THAT(calls, HasSubstr("--parsable " + s.bakes_script.string()));
  EXPECT_THAT(calls, HasSubstr("--parsable --dependency=afterok:1001 " + s.queries_script.string()));
  const std::string bakes = test::read_text(s.bakes_script);
  EXPECT_THAT(bakes, HasSubstr("#SBATCH --array=1-3"));
  EXPECT_THAT(bakes, HasSubstr("#SBATCH --partition=batch"));
  EXPECT_THAT(bakes, HasSubstr("#SBATCH --time=01:30:00"));
  EXPECT_THAT(bakes, HasSubstr("--phase bakes --shard \"${SLURM_ARRAY_TASK_ID}/3\""));
  EXPECT_THAT(bakes, HasSubstr("'" + dir.path().string() + "/it'\\''s a manifest.yaml'"));  // one word, nothing run
  EXPECT_THAT(test::read_text(s.queries_script), HasSubstr("--phase queries"));
}

TEST(BatchSlurm, RefusesMalformedOptionsAndReportsSbatchErrors) {
  test::TempDir dir;
  SlurmOptions o{"dmgplace", dir / "m.yaml", dir / "out", 2, "", "1h", "sbatch"};
  EXPECT_THAT(test::error_of([&] { submit_slurm(o, false); }), HasSubstr("expected HH:MM:SS"));
  o.time = "";
  o.partition = "a;b";
  EXPECT_THAT(test::error_of([&] { submit_slurm(o, false); }), HasSubstr("expected a partition name"));
  o.partition = "";
  const fs::path fake = dir / "sbatch";
  test::write_text(fake, "#!/bin/sh\necho 'sbatch: error: invalid partition' >&2\nexit 1\n");
  fs::permissions(fake, fs::perms::owner_all);
  o.sbatch = fake.string();
  EXPECT_THAT(test::error_of([&] { submit_slurm(o); }), HasSubstr("invalid partition"));
}

// Every "0 = all CPUs" default counts the CPUs the process may use (taskset, cgroup cpusets, Slurm).
TEST(AvailableCpus, FollowsTheAffinityMask) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    cpu_set_t one;
    CPU_ZERO(&one);
    CPU_SET(0, &one);
    if (sched_setaffinity(0, sizeof one, &one) != 0) ::_exit(2);
    ::_exit(runtime::available_cpus() == 1 ? 0 : 1);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0);
  EXPECT_GE(runtime::available_cpus(), 1);
}

}  // namespace
}  // namespace dmgplace::tools

#include "dmgplace/tools/batch/batch_state.hpp"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "dmgplace/formats/artifact_header.hpp"
#include "dmgplace/formats/artifact_kind.hpp"
#include "dmgplace/formats/atomic_file.hpp"
#include "dmgplace/formats/error.hpp"

namespace dmgplace::tools {
namespace fs = std::filesystem;
using nlohmann::ordered_json;
namespace {

fs::path state_dir(const fs::path& out) { return out / "state"; }

std::string host_name() {
  char b[256] = {0};
  ::gethostname(b, sizeof b - 1);
  return b;
}

std::string read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace

void write_plan(const BatchPlan& plan) {
  ordered_json tasks = ordered_json::array();
  for (const auto& t : plan.tasks)
    tasks.push_back({{"id", t.id},
                     {"kind", t.kind},
                     {"name", t.name},
                     {"output", t.output.string()},
                     {"deps", t.deps},
                     {"robot", t.robot},
                     {"object", t.object},
                     {"environment", t.environment},
                     {"grasp", t.grasp},
                     {"variant", t.variant},
                     {"seed", t.seed},
                     {"g0", t.g0}});
  fs::create_directories(state_dir(plan.out));
  formats::write_file_atomically(plan.out / "batch.json",
                                 ordered_json{{"name", plan.name}, {"tasks", tasks}}.dump(1) + "\n");
}

BatchPlan read_plan(const fs::path& out) {
  const fs::path file = out / "batch.json";
  std::error_code ec;
  if (!fs::is_regular_file(file, ec))
    throw Error(file.string(), "", "no batch here (run `dmgplace batch MANIFEST --out DIR` first)");
  const auto j = nlohmann::json::parse(read_file(file), nullptr, false);
  if (j.is_discarded() || !j.contains("tasks")) throw Error(file.string(), "", "not a batch plan (corrupt?)");
  BatchPlan plan;
  plan.out = out;
  plan.name = j.value("name", "");
  try {
    for (const auto& x : j["tasks"]) {
      BatchTask t;
      t.id = x.at("id"), t.kind = x.at("kind"), t.name = x.at("name"), t.output = x.at("output").get<std::string>();
      t.deps = x.at("deps").get<std::vector<std::string>>();
      t.robot = x.value("robot", ""), t.object = x.value("object", ""), t.environment = x.value("environment", "");
      t.grasp = x.value("grasp", ""), t.variant = x.value("variant", ""), t.seed = x.value("seed", 0);
      t.g0 = x.at("g0").get<std::array<double, 7>>();
      plan.tasks.push_back(std::move(t));
    }
  } catch (const nlohmann::json::exception& e) {
    throw Error(file.string(), "tasks", std::string("malformed: ") + e.what());
  }
  return plan;
}

void write_record(const fs::path& out, const TaskRecord& r) {
  fs::create_directories(state_dir(out));
  const ordered_json j{{"id", r.id},
                       {"name", r.name},
                       {"kind", r.kind},
                       {"ok", r.ok},
                       {"exit_code", r.exit_code},
                       {"seconds", r.seconds},
                       {"error", r.error},
                       {"stderr_tail", r.stderr_tail},
                       {"finished_utc", formats::utc_now_iso8601()}};
  formats::write_file_atomically(state_dir(out) / (r.id + ".json"), j.dump(1) + "\n");
}

std::optional<TaskRecord> read_record(const fs::path& out, const std::string& id) {
  const fs::path p = state_dir(out) / (id + ".json");
  std::error_code ec;
  if (!fs::is_regular_file(p, ec)) return std::nullopt;
  const auto j = nlohmann::json::parse(read_file(p), nullptr, false);
  if (j.is_discarded() || j.value("id", "") != id) return std::nullopt;  // torn or foreign: not done
  TaskRecord r;
  r.id = id, r.name = j.value("name", ""), r.kind = j.value("kind", ""), r.ok = j.value("ok", false);
  r.exit_code = j.value("exit_code", 0), r.seconds = j.value("seconds", 0.0), r.error = j.value("error", "");
  r.stderr_tail = j.value("stderr_tail", ""), r.finished_utc = j.value("finished_utc", "");
  return r;
}

bool task_done(const fs::path& out, const BatchTask& t) {
  const auto r = read_record(out, t.id);
  if (!r || !r->ok) return false;
  std::error_code ec;
  if (t.kind == "query") return fs::is_regular_file(t.output / "result.json", ec);
  return fs::is_regular_file(t.output, ec) && formats::validate_artifact(t.output).empty();
}

namespace {
// A claim left by a process of this host that is gone (killed).
bool stale(const fs::path& lock) {
  std::istringstream holder(read_file(lock));
  std::string host;
  long pid = 0;
  holder >> host >> pid;
  return host == host_name() && pid > 0 && ::kill(pid_t(pid), 0) != 0 && errno == ESRCH;
}
}  // namespace

void remove_stale_claims(const fs::path& out) {
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(state_dir(out), ec))
    if (e.path().extension() == ".lock" && stale(e.path())) fs::remove(e.path(), ec);
}

std::optional<TaskClaim> TaskClaim::try_claim(const fs::path& out, const std::string& id) {
  fs::create_directories(state_dir(out));
  const fs::path p = state_dir(out) / (id + ".lock");
  const std::string me = host_name() + " " + std::to_string(::getpid()) + "\n";
  for (int attempt = 0; attempt < 2; ++attempt) {
    const int fd = ::open(p.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (fd >= 0) {
      const bool written = ::write(fd, me.data(), me.size()) == ssize_t(me.size());
      ::close(fd);
      if (written) return TaskClaim(p);
      fs::remove(p);
      return std::nullopt;
    }
    if (errno != EEXIST) throw Error(p.string(), "", std::string("cannot create a claim: ") + std::strerror(errno));
    // Held: by a live process (wait for it), or left by a killed one on this host (take it over).
    if (!stale(p)) return std::nullopt;
    std::error_code ec;
    fs::remove(p, ec);
  }
  return std::nullopt;
}

TaskClaim::~TaskClaim() {
  if (path_.empty()) return;
  std::error_code ec;
  fs::remove(path_, ec);
}

}  // namespace dmgplace::tools

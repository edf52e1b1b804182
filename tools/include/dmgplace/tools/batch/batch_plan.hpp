#pragma once
// A batch as a task graph: bakes first, then the queries that need them. Each task's identity is
// the SHA-256 of what it depends on (tool and schema versions, its command, its input files'
// bytes, its dependencies' identities), so a changed input or flag changes exactly the identities
// downstream of it, and an output is reused only by the task that made it.
#include <filesystem>
#include <string>
#include <vector>

#include "dmgplace/tools/batch/batch_manifest.hpp"

namespace dmgplace::tools {

struct BatchTask {
  std::string id;                 // 64 hex digits
  std::string kind;               // robot, object, environment, query
  std::string name;               // e.g. "object bottle", "query cabinet/bottle@cabinet/side/full/1"
  std::vector<std::string> args;  // dmgplace's arguments, the output included
  std::filesystem::path output;   // the artifact, or the run folder (result.json)
  std::vector<std::string> deps;  // ids of the bakes a query needs
  std::string query_yaml;         // a query's file, written into its run folder first
  // Columns of the collected dataset.
  std::string robot, object, environment, grasp, variant;
  std::array<double, 7> g0{};
  int seed = 0;
};

struct BatchPlan {
  std::string name;
  std::filesystem::path out;
  std::vector<BatchTask> tasks;  // bakes, then queries; deterministic order
};

BatchPlan plan_batch(const BatchManifest& m, const std::filesystem::path& out);

// Shard `index` (1-based) of `count`: a deterministic partition of each phase (bakes, queries)
// by position, so the shards' union is the whole plan.
bool in_shard(const BatchPlan& plan, std::size_t task, int index, int count);

}  // namespace dmgplace::tools

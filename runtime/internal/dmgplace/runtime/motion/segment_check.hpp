#pragma once
// The one way a joint-space motion is checked outside the planners: states every `resolution`
// of Euclidean (L2) joint-space length, the metric of OMPL's motion validators (longest valid
// segment). Approach paths, local-optimisation steps and retreats all go through here, so every
// published segment was checked at the same states a planner at this resolution would check.
#include <Eigen/Core>
#include <functional>
#include <vector>

namespace dmgplace::runtime {

using ValidityFn = std::function<bool(const Eigen::VectorXd&)>;

// Number of equal steps from a to b so that no step is longer than `resolution` (>= 1).
int segment_steps(const Eigen::VectorXd& a, const Eigen::VectorXd& b, double resolution);

// The states of the segment after `a` up to and including `b` are valid (a is the caller's).
bool segment_valid(const Eigen::VectorXd& a, const Eigen::VectorXd& b, double resolution, const ValidityFn& valid);

// Every state of `path` and every segment between consecutive states valid.
bool path_valid(const std::vector<std::vector<double>>& path, const ValidityFn& valid, double resolution);

}  // namespace dmgplace::runtime

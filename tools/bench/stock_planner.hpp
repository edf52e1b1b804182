#pragma once
// The benchmark baseline planner: OMPL's own RRTConnect over the stock FCL checker, as a MoveIt
// user runs it today. Not part of the product: bench-mbm compares our planner with it.
#include <cstdint>

#include "dmgplace/tools/motion/arm_problem.hpp"
#include "stock_fcl_checker.hpp"

namespace dmgplace::bench {

// Plans from p.start to p.goal with `checker` as the validity checker; the returned path is judged
// by our exact layer like ours (tools::judge_path). OMPL seeds itself once per process, so runs
// repeat only as a whole process.
tools::PlanOutcome plan_stock(const tools::ArmProblem& p, const StockFclChecker& checker, double time_limit,
                              double resolution);

}  // namespace dmgplace::bench

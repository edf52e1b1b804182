#include "dmgplace/runtime/placement/placement_query.hpp"

namespace dmgplace::runtime {

const char* to_string(PlacementVariant v) {
  switch (v) {
    case PlacementVariant::Full: return "full";
    case PlacementVariant::RandomGrasp: return "random-grasp";
    case PlacementVariant::NoRegrasp: return "no-regrasp";
  }
  return "?";
}

std::optional<PlacementVariant> parse_variant(const std::string& s) {
  for (auto v : {PlacementVariant::Full, PlacementVariant::RandomGrasp, PlacementVariant::NoRegrasp})
    if (s == to_string(v)) return v;
  return std::nullopt;
}

const char* to_string(ObjectiveTerm::Kind k) {
  switch (k) {
    case ObjectiveTerm::Kind::Clearance: return "clearance";
    case ObjectiveTerm::Kind::Depth: return "depth";
    case ObjectiveTerm::Kind::Distance: return "distance";
    case ObjectiveTerm::Kind::Upright: return "upright";
  }
  return "?";
}

std::optional<ObjectiveTerm::Kind> parse_objective_kind(const std::string& s) {
  using K = ObjectiveTerm::Kind;
  for (auto k : {K::Clearance, K::Depth, K::Distance, K::Upright})
    if (s == to_string(k)) return k;
  return std::nullopt;
}

}  // namespace dmgplace::runtime

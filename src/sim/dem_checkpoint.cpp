#include "sim/dem_checkpoint.hpp"

#include <type_traits>
#include <utility>
#include <vector>

#include "millsim/core/error.hpp"

namespace millsim::sim {

namespace {

// The real arrays every DEM checkpoint has, by dataset name (S: DemHostState, const to read).
template <class S, class V = std::conditional_t<std::is_const_v<S>, const std::vector<double>, std::vector<double>>>
std::vector<std::pair<const char*, V*>> stateArrays(S& s) {
  return {{"pos", &s.pos},        {"vel", &s.vel},         {"omega", &s.omega},     {"radius", &s.radius},
          {"mass", &s.mass},      {"inertia", &s.inertia}, {"hist_xi", &s.hist_xi}, {"dissipated", &s.dissipated},
          {"work_in", &s.work_in}};
}

// Arrays a checkpoint has only since they were added: a missing one restarts from zero.
template <class S, class V = std::conditional_t<std::is_const_v<S>, const std::vector<double>, std::vector<double>>>
std::vector<std::pair<const char*, V*>> optionalStateArrays(S& s) {
  return {{"work_external", &s.work_external}};
}

}  // namespace

io::CheckpointData demCheckpoint(const dem::DemEngine& engine, double t, std::int64_t step) {
  io::CheckpointData cp;
  cp.time = t;
  cp.step = step;
  dem::DemHostState s;
  engine.getState(s);
  for (const auto& [key, v] : stateArrays(s)) cp.reals[key] = *v;
  for (const auto& [key, v] : optionalStateArrays(s))
    if (!v->empty()) cp.reals[key] = *v;
  cp.reals["force"] = s.force;
  cp.reals["torque"] = s.torque;
  cp.ints["hist_id"] = s.hist_id;
  return cp;
}

dem::DemHostState takeDemState(const io::CheckpointData& cp, const std::string& path) {
  dem::DemHostState s;
  for (const auto& [key, v] : stateArrays(s)) {
    const auto it = cp.reals.find(key);
    if (it == cp.reals.end()) throw core::InputError(path + ": checkpoint lacks '" + key + "'");
    *v = it->second;
  }
  for (const auto& [key, v] : optionalStateArrays(s))
    if (cp.reals.count(key)) *v = cp.reals.at(key);
  // The forces of the checkpointed step (DemHostState::force); a checkpoint written before
  // they were kept has none, and the restart evaluates them (with v(t): close, not exact).
  if (cp.reals.count("force") && cp.reals.count("torque")) {
    s.force = cp.reals.at("force");
    s.torque = cp.reals.at("torque");
  }
  const auto id = cp.ints.find("hist_id");
  if (id == cp.ints.end()) throw core::InputError(path + ": checkpoint lacks 'hist_id'");
  s.hist_id = id->second;
  return s;
}

}  // namespace millsim::sim

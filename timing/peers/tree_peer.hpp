// A model-file work-precision problem (Mechanism::model_file) in a peer
// engine (peers/tree_engine.hpp), behind measure.hpp's engine interface,
// observing the problem's body's centre of mass. Built without the
// benchmarks' -march, as the model structs it reads are.
#pragma once

#include <memory>
#include <string>

#include "peer_engine.hpp"
#include "problems.hpp"

namespace timing {

// engine: an ENGINE-METHOD name of tree::engines() (e.g. "mujoco-rk4").
std::unique_ptr<PeerEngine> tree_peer(const Problem& p, const std::string& engine, double h);

}  // namespace timing

// A peer engine behind one interface, for programs that pick the engine at
// run time (peer_chain_step.cpp). The engines are measure.hpp's engine types;
// work_precision steps them directly.
#pragma once

#include <mbrt/types.hpp>

namespace timing {

class PeerEngine {
 public:
  virtual ~PeerEngine() = default;
  virtual bool step() = 0;  // one fixed step; false if the engine failed
  virtual double time() const = 0;
  virtual mbrt::Vec3 observed() = 0;  // the problem's observed point, world coordinates
};

}  // namespace timing

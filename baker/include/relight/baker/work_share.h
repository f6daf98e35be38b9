// Work split over processes: what the baker needs of a distributed bake
// (relight/baker/distributed.h implements it over MPI). The links'
// refinement runs on each process's share of the surface pairs, and the
// processes then swap what they made.
#pragma once

#include <cstdint>
#include <vector>

namespace relight::baker {

class WorkShare {
 public:
  virtual ~WorkShare() = default;
  virtual int rank() const = 0;
  virtual int ranks() const = 0;
  // Collective: every process passes its bytes and gets back every
  // process's, concatenated in rank order.
  virtual std::vector<uint8_t> AllGather(const std::vector<uint8_t>& mine) const = 0;
};

}  // namespace relight::baker

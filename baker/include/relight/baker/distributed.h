// A bake spread over processes with MPI (issue 16, docs/distributed-bake.md).
//
// Every rank reads the scene and builds the same mesh, form factors or links
// (deterministic: the same input gives the same numbers on every rank and
// thread count); the luminaires, i.e. the right-hand sides of Dobashi
// Eq. 17, are shared out by SH term count; rank 0 gathers every luminaire's
// quantised basis and alone writes the bake. Built without MPI (CMake found
// none), a session is one process and the bake is Baker::Bake().
// Thread safety: one session per process, used from the main thread.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "relight/bake/bake.h"
#include "relight/baker/baker.h"
#include "relight/baker/scene.h"
#include "relight/baker/work_share.h"

namespace relight::baker {

class DistributedSession : public WorkShare {
 public:
  // MPI_Init (when built with MPI); argc/argv as main received them.
  DistributedSession(int* argc, char*** argv);
  ~DistributedSession() override;  // MPI_Finalize
  DistributedSession(const DistributedSession&) = delete;
  DistributedSession& operator=(const DistributedSession&) = delete;

  int rank() const override { return rank_; }
  int ranks() const override { return ranks_; }
  std::vector<uint8_t> AllGather(const std::vector<uint8_t>& mine) const override;
  bool writer() const { return rank_ == 0; }
  // Nothing to do here: started by mpirun as a rank above 0 of a build
  // without MPI (rank 0 then bakes alone).
  bool idle() const { return rank_ >= ranks_; }
  // Ranks on this machine: worker threads default to the cores over them.
  int local_ranks() const { return local_ranks_; }
  // Ends every rank (MPI_Abort) so that none waits for a failed one; a
  // plain return with one process.
  void Abort(int code) const;
  // True when built with MPI.
  static bool Available();

 private:
  int rank_ = 0, ranks_ = 1, local_ranks_ = 1;
  [[maybe_unused]] bool initialised_ = false;  // used by the MPI build only
};

// Which rank bakes each luminaire: by SH terms, largest first, each to the
// rank with the fewest terms so far (ties: the lower luminaire index, the
// lower rank). Deterministic; every rank computes the same.
std::vector<int> ShareLuminaires(const Scene& scene, int ranks);

// The whole bake on the writing rank; an empty Bake on the others. Every
// rank must call it (collective). `report`: the baker's, with the sweeps and
// residual the worst over the ranks and the SH terms of every rank (on the
// writer). Throws std::runtime_error if a part does not arrive intact.
relight::Bake DistributedBake(Baker* baker, const DistributedSession& session,
                              BakeReport* report);

}  // namespace relight::baker

// DistributedSession and DistributedBake without MPI (distributed.h): one
// process. Started by mpirun anyway, only the launcher's rank 0 bakes and
// the others say why they do nothing, rather than all writing the same file.
#include <cstdio>
#include <cstdlib>

#include "relight/baker/distributed.h"

namespace relight::baker {

DistributedSession::DistributedSession(int*, char***) {
  for (const char* v : {"OMPI_COMM_WORLD_RANK", "PMI_RANK", "PMIX_RANK"}) {
    const char* text = std::getenv(v);
    if (text != nullptr && std::atoi(text) > 0) {
      rank_ = std::atoi(text);
      std::fprintf(stderr,
                   "relight-bake: rank %d: built without MPI (no libopenmpi-dev when it was "
                   "configured): rank 0 bakes alone, this rank does nothing\n",
                   rank_);
      return;
    }
  }
}

DistributedSession::~DistributedSession() = default;

void DistributedSession::Abort(int) const {}

std::vector<uint8_t> DistributedSession::AllGather(const std::vector<uint8_t>& mine) const {
  return mine;
}

bool DistributedSession::Available() { return false; }

relight::Bake DistributedBake(Baker* baker, const DistributedSession& session,
                              BakeReport* report) {
  if (!session.writer()) return relight::Bake();
  relight::Bake bake = baker->Bake();
  *report = baker->report();
  return bake;
}

}  // namespace relight::baker

// DistributedSession and DistributedBake over MPI (distributed.h). Only rank
// 0 writes; the others send it their luminaires as a bake file's bytes (the
// format's own writer and reader: what arrives is checked like any file).
#include <mpi.h>
#include <unistd.h>

#include <algorithm>
#include <climits>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>

#include "relight/baker/distributed.h"

namespace relight::baker {
namespace {

constexpr int kSizeTag = 1, kBytesTag = 2;
constexpr size_t kChunkBytes = size_t{1} << 30;  // MPI counts are int

// Launched by mpirun (Open MPI, or a PMI launcher such as srun/hydra)?
// Without it the bake is one process and MPI is never initialised, so
// relight-bake runs exactly as a build without MPI.
bool UnderLauncher() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
    if (std::getenv(v) != nullptr) return true;
  return false;
}

std::vector<uint8_t> BakeBytes(const relight::Bake& bake, int rank) {
  const char* dir = std::getenv("TMPDIR");
  const std::string path = std::string(dir && *dir ? dir : "/tmp") + "/relight-bake-part-" +
                           std::to_string(getpid()) + "-" + std::to_string(rank) + ".rlb";
  if (const Status st = WriteBake(bake, path); !st.ok()) {
    throw std::runtime_error("rank " + std::to_string(rank) + ": " + path + ": " + st.ToString());
  }
  std::ifstream in(path, std::ios::binary);
  std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::remove(path.c_str());
  return bytes;
}

void SendBytes(const std::vector<uint8_t>& bytes) {
  const uint64_t size = bytes.size();
  MPI_Send(&size, 1, MPI_UINT64_T, 0, kSizeTag, MPI_COMM_WORLD);
  for (size_t at = 0; at < bytes.size(); at += kChunkBytes) {
    const int n = static_cast<int>(std::min(kChunkBytes, bytes.size() - at));
    MPI_Send(bytes.data() + at, n, MPI_BYTE, 0, kBytesTag, MPI_COMM_WORLD);
  }
}

std::vector<uint8_t> ReceiveBytes(int from) {
  uint64_t size = 0;
  MPI_Recv(&size, 1, MPI_UINT64_T, from, kSizeTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  std::vector<uint8_t> bytes(size);
  for (size_t at = 0; at < bytes.size(); at += kChunkBytes) {
    const int n = static_cast<int>(std::min(kChunkBytes, bytes.size() - at));
    MPI_Recv(bytes.data() + at, n, MPI_BYTE, from, kBytesTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  }
  return bytes;
}

}  // namespace

DistributedSession::DistributedSession(int* argc, char*** argv) {
  if (!UnderLauncher()) return;
  // Worker threads never call MPI: only the main thread does.
  int provided = 0;
  MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
  initialised_ = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks_);
  MPI_Comm local;
  MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &local);
  MPI_Comm_size(local, &local_ranks_);
  MPI_Comm_free(&local);
}

DistributedSession::~DistributedSession() {
  if (initialised_) MPI_Finalize();
}

void DistributedSession::Abort(int code) const {
  if (initialised_ && ranks_ > 1) MPI_Abort(MPI_COMM_WORLD, code);
}

bool DistributedSession::Available() { return true; }

std::vector<uint8_t> DistributedSession::AllGather(const std::vector<uint8_t>& mine) const {
  if (ranks_ == 1) return mine;
  // Sizes first, then the bytes; int counts, so a share is below 2 GiB.
  if (mine.size() > static_cast<size_t>(INT_MAX)) {
    throw std::runtime_error("rank " + std::to_string(rank_) + ": " +
                             std::to_string(mine.size()) + " bytes to share, over 2 GiB");
  }
  const int size = static_cast<int>(mine.size());
  std::vector<int> sizes(static_cast<size_t>(ranks_)), offsets(static_cast<size_t>(ranks_), 0);
  MPI_Allgather(&size, 1, MPI_INT, sizes.data(), 1, MPI_INT, MPI_COMM_WORLD);
  size_t total = 0;
  for (int r = 0; r < ranks_; ++r) {
    if (total > static_cast<size_t>(INT_MAX)) throw std::runtime_error("over 2 GiB to share");
    offsets[static_cast<size_t>(r)] = static_cast<int>(total);
    total += static_cast<size_t>(sizes[static_cast<size_t>(r)]);
  }
  std::vector<uint8_t> all(total);
  MPI_Allgatherv(mine.data(), size, MPI_BYTE, all.data(), sizes.data(), offsets.data(), MPI_BYTE,
                 MPI_COMM_WORLD);
  return all;
}

relight::Bake DistributedBake(Baker* baker, const DistributedSession& session,
                              BakeReport* report) {
  *report = baker->report();
  if (session.ranks() == 1) {
    relight::Bake bake = baker->Bake();
    *report = baker->report();
    return bake;
  }
  const int rank = session.rank();
  const std::vector<int> owner = ShareLuminaires(baker->scene(), session.ranks());
  relight::Bake part =
      baker->BakePart([&](size_t l) { return owner[l] == rank; }, session.writer());
  *report = baker->report();
  // The solver's figures over every rank: the worst residual and sweeps, all terms.
  double residual = report->residual;
  int sweeps = report->sweeps;
  uint64_t terms = report->sh_terms;
  MPI_Reduce(&residual, &report->residual, 1, MPI_DOUBLE, MPI_MAX, 0, MPI_COMM_WORLD);
  MPI_Reduce(&sweeps, &report->sweeps, 1, MPI_INT, MPI_MAX, 0, MPI_COMM_WORLD);
  uint64_t all_terms = 0;
  MPI_Reduce(&terms, &all_terms, 1, MPI_UINT64_T, MPI_SUM, 0, MPI_COMM_WORLD);
  if (!session.writer()) {
    const bool any = std::find(owner.begin(), owner.end(), rank) != owner.end();
    SendBytes(any ? BakeBytes(part, rank) : std::vector<uint8_t>());
    return relight::Bake();
  }
  report->sh_terms = all_terms;
  // Each rank's luminaires, in scene order; rank 0's are in `part`.
  std::vector<std::vector<BakeLuminaire>> from(static_cast<size_t>(session.ranks()));
  from[0] = std::move(part.luminaires);
  for (int r = 1; r < session.ranks(); ++r) {
    const std::vector<uint8_t> bytes = ReceiveBytes(r);
    if (bytes.empty()) continue;
    relight::Bake got;
    if (const Status st = ParseBake(bytes.data(), bytes.size(), &got); !st.ok()) {
      throw std::runtime_error("the part baked by rank " + std::to_string(r) +
                               " did not arrive intact: " + st.ToString());
    }
    from[static_cast<size_t>(r)] = std::move(got.luminaires);
  }
  std::vector<size_t> next(from.size(), 0);
  part.luminaires.clear();
  for (size_t l = 0; l < owner.size(); ++l) {
    const auto r = static_cast<size_t>(owner[l]);
    if (next[r] >= from[r].size()) {
      throw std::runtime_error("rank " + std::to_string(r) + " sent fewer luminaires than it owns");
    }
    part.luminaires.push_back(std::move(from[r][next[r]++]));
  }
  return part;
}

}  // namespace relight::baker

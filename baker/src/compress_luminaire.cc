// A luminaire's bases compressed into its bake entry (compress_luminaire.h).
#include "compress_luminaire.h"

#include <algorithm>

#include "compress_basis.h"
#include "compression_looks.h"
#include "parallel_for.h"

namespace relight::baker {
namespace {

// Looks the compression error is measured at, per luminaire (compression_looks.h).
constexpr int kCompressionLooks = 16;
constexpr uint32_t kCompressionSeed = 13;

}  // namespace

void CompressLuminaireBases(const Luminaire& lum, size_t index, int degree,
                            const std::vector<ReceiverSetInput>& sets, const BakeOptions& options,
                            BakeLuminaire* out, BakeReport* report) {
  std::vector<CompressionLook> looks;
  if (options.compress_error > 0) looks = CompressionLooks(lum, degree, kCompressionLooks, kCompressionSeed);
  std::vector<Eigen::VectorXd> coef;
  for (const CompressionLook& look : looks) coef.push_back(look.coef);
  for (size_t s = 0; s < sets.size(); ++s) {
    const auto& b = *sets[s].basis;
    BakeLightReceivers& rec = out->receivers[s];
    report->basis_float32_bytes += 4 * 3 * static_cast<uint64_t>(b[0].rows() * b[0].cols());
    ++report->bases;
    if (looks.empty()) {
      report->basis_bytes += rec.compressed.present() ? rec.compressed.memory_bytes()
                                                      : 2 * rec.basis.size() + 8 * rec.basis_scale.size();
      continue;
    }
    std::vector<Eigen::MatrixXd> direct;
    if (!sets[s].direction.empty()) {  // each look on its own: a venue has 10^5 receivers
      direct.resize(looks.size());
      ParallelFor(looks.size(), options.threads, [&](size_t l, int) {
        direct[l] = DirectAtLook(lum.lid, looks[l].frame, sets[s].direction, sets[s].g_m2, sets[s].rho);
      });
    }
    std::vector<CompressionPoint> curve;
    BakeCompressedBasis cpca;
    const CompressionStats st =
        CompressBasis(b, coef, direct, options.compress_error, options.threads, &cpca,
                      options.compress_curve ? &curve : nullptr, options.compress_8bit_weights);
    for (CompressionPoint& p : curve) {
      p.luminaire = index;
      p.set = s;
      report->compress_curve.push_back(p);
    }
    if (!st.compressed) {  // kept as it is: counted as it stands
      report->basis_bytes += rec.compressed.present() ? rec.compressed.memory_bytes()
                                                      : 2 * rec.basis.size() + 8 * rec.basis_scale.size();
      continue;
    }
    rec.compressed = std::move(cpca);
    report->basis_bytes += st.bytes;
    rec.basis.clear();
    rec.basis.shrink_to_fit();
    rec.basis_scale.clear();
    ++report->bases_compressed;
    if (st.weight_bits == 8) ++report->bases_8bit;
    report->compress_max_error = std::max(report->compress_max_error, st.max_error);
    // Mean over compressed bases (each counted once).
    report->compress_mean_error +=
        (st.mean_error - report->compress_mean_error) / static_cast<double>(report->bases_compressed);
  }
}

}  // namespace relight::baker

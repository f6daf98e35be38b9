// The inner pass of the bases' compression search (compress_basis.cc): a
// look's residual over a cluster loses one principal component, and its
// largest and summed |value| are taken, for every component count tried.
// Kept apart so it can be compiled for wider vector units than the baseline
// x86-64 and picked at run time; the lanes and the order they are summed in
// are fixed, so every path gives the same bits (bakes stay reproducible).
#pragma once

#include <cstddef>

namespace relight::baker {

struct AbsStats {
  double max = 0, sum = 0;
};

// v[i] -= a w[i] for i < n (w null: v is left as it is), then the largest
// and the summed |v[i]|.
AbsStats SubtractAndMeasure(double* v, const double* w, double a, size_t n);

}  // namespace relight::baker

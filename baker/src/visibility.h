// Visibility between two points through the scene's patches, with Embree 3
// (one static scene of every render triangle, robust flag on).
//
// Callers offset both end points off their surfaces along the surface normal
// by epsilon_m() (Offset()), and the ray skips epsilon_m() at both ends, so a
// patch never shadows itself or its neighbour along a shared edge, nor a
// luminaire mounted flush on a surface.
// Thread safety: Visible() is const and may run on many threads at once
// (each call uses its own RTCIntersectContext).
#pragma once

#include <memory>

#include "mesher.h"

namespace relight::baker {

class Visibility {
 public:
  // threads: Embree's build threads (0 = all cores).
  Visibility(const Mesh& mesh, int threads);
  ~Visibility();
  Visibility(const Visibility&) = delete;
  Visibility& operator=(const Visibility&) = delete;

  // True when the segment from `from` to `to`, less epsilon_m() at each end,
  // hits no triangle.
  bool Visible(const Vec3& from, const Vec3& to) const;
  // How many of the n segments from[i] -> to[i] are visible, as Visible()
  // decides each; cast as packets of 16 (coherent rays between two small
  // patches or nodes traverse the same boxes).
  int CountVisible(const Vec3* from, const Vec3* to, int n) const;
  // p moved off its surface along the unit normal n.
  Vec3 Offset(const Vec3& p, const Vec3& n) const;
  double epsilon_m() const { return epsilon_m_; }

 private:
  struct Embree;
  std::unique_ptr<Embree> embree_;
  double epsilon_m_;
};

// Counts the visible ones among segments added one by one, cast 16 at a time
// (Visibility::CountVisible).
class VisibleCounter {
 public:
  explicit VisibleCounter(const Visibility& vis) : vis_(vis) {}
  void Add(const Vec3& from, const Vec3& to) {
    from_[pending_] = from;
    to_[pending_] = to;
    if (++pending_ == kBatch) Flush();
  }
  int visible() {
    Flush();
    return visible_;
  }

 private:
  static constexpr int kBatch = 16;
  void Flush() {
    visible_ += vis_.CountVisible(from_, to_, pending_);
    pending_ = 0;
  }
  const Visibility& vis_;
  Vec3 from_[kBatch], to_[kBatch];
  int pending_ = 0, visible_ = 0;
};

}  // namespace relight::baker

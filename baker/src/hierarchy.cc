#include "hierarchy.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <stdexcept>

#include "radiosity_vec.h"

namespace relight::baker {
namespace {

using namespace radiosity_vec;

// Grid coordinates on a surface's patch grid: quads (a, b) in cells, triangles
// (i, j) in barycentric steps. Every node corner is a grid vertex.
struct P2 {
  double x = 0, y = 0;
};
using Poly2 = std::vector<P2>;

struct LeafPos {
  uint32_t patch;
  P2 at;  // the leaf's centroid in grid coordinates (never on a grid line)
};

// Grid lines run in two directions on a quad (x, y) and three on a triangle
// (x, y, x + y); a node splits along one of them.
double Coord(int family, const P2& p) { return family == 0 ? p.x : family == 1 ? p.y : p.x + p.y; }

// The part of `poly` with sign * (Coord(family) - m) >= 0 (Sutherland-Hodgman).
// Grid coordinates are small integers, so every value here is exact.
Poly2 ClipHalf(const Poly2& poly, int family, double m, double sign) {
  Poly2 out;
  for (size_t k = 0; k < poly.size(); ++k) {
    const P2& a = poly[k];
    const P2& b = poly[(k + 1) % poly.size()];
    const double sa = sign * (Coord(family, a) - m);
    const double sb = sign * (Coord(family, b) - m);
    if (sa >= 0) out.push_back(a);
    if ((sa > 0 && sb < 0) || (sa < 0 && sb > 0)) {
      const double t = sa / (sa - sb);
      out.push_back({a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)});
    }
  }
  // Drop repeated and collinear corners (a cut through a corner leaves them).
  for (bool changed = true; changed && out.size() >= 3;) {
    changed = false;
    Poly2 kept;
    for (size_t k = 0; k < out.size(); ++k) {
      const P2& p = kept.empty() ? out.back() : kept.back();
      const P2& q = out[k];
      const P2& r = out[(k + 1) % out.size()];
      const double cross = (q.x - p.x) * (r.y - q.y) - (q.y - p.y) * (r.x - q.x);
      if (cross == 0 && !changed) {
        changed = true;  // one at a time: its neighbours' test changes
      } else {
        kept.push_back(q);
      }
    }
    out.swap(kept);
  }
  return out;
}

class SurfaceTreeBuilder {
 public:
  SurfaceTreeBuilder(const Mesh& mesh, uint32_t surface, Hierarchy* h)
      : mesh_(mesh), grid_(mesh.surface_grids[surface]), surface_(surface), h_(h) {}

  void Build() {
    Poly2 whole;
    std::vector<LeafPos> leaves;
    const int nu = grid_.nu, nv = grid_.nv;
    if (!grid_.triangle) {
      families_ = 2;
      whole = Poly2{{0, 0}, {double(nu), 0}, {double(nu), double(nv)}, {0, double(nv)}};
      for (int b = 0; b < nv; ++b)
        for (int a = 0; a < nu; ++a)
          leaves.push_back(
              {grid_.first_patch + static_cast<uint32_t>(b * nu + a), {a + 0.5, b + 0.5}});
      const Vec3& c0 = Vertex({0, 0});
      spacing_[0] = Length(Vertex({double(nu), 0}) - c0) / nu;
      spacing_[1] = Length(Vertex({0, double(nv)}) - c0) / nv;
    } else {
      families_ = 3;
      const int k = nu;
      whole = Poly2{{0, 0}, {double(k), 0}, {0, double(k)}};
      uint32_t patch = grid_.first_patch;
      row_start_.assign(static_cast<size_t>(k) + 1, 0);
      uint32_t v = grid_.first_vertex;
      for (int j = 0; j <= k; ++j) {
        row_start_[j] = v;
        v += static_cast<uint32_t>(k + 1 - j);
      }
      for (int j = 0; j < k; ++j) {
        for (int i = 0; i + j < k; ++i) {
          leaves.push_back({patch++, {i + 1.0 / 3.0, j + 1.0 / 3.0}});
          if (i + j + 1 < k) leaves.push_back({patch++, {i + 2.0 / 3.0, j + 2.0 / 3.0}});
        }
      }
      // Perpendicular distance between neighbouring grid lines of each family.
      const Vec3 c0 = Vertex({0, 0}), c1 = Vertex({double(k), 0}), c2 = Vertex({0, double(k)});
      const double twice_area = Length(Cross(c1 - c0, c2 - c0));
      spacing_[0] = twice_area / (Length(c2 - c0) * k);
      spacing_[1] = twice_area / (Length(c1 - c0) * k);
      spacing_[2] = twice_area / (Length(c2 - c1) * k);
    }
    std::deque<Pending> queue;
    queue.push_back({AddNode(whole, leaves, kNoNode, 0), std::move(whole), std::move(leaves)});
    while (!queue.empty()) {
      Pending cur = std::move(queue.front());
      queue.pop_front();
      if (cur.leaves.size() == 1) continue;
      std::vector<std::pair<Poly2, std::vector<LeafPos>>> parts;
      for (auto& half : Split(cur.poly, cur.leaves)) {
        if (half.second.size() == 1) {
          parts.push_back(std::move(half));
        } else {
          for (auto& quarter : Split(half.first, half.second)) parts.push_back(std::move(quarter));
        }
      }
      const uint32_t first = static_cast<uint32_t>(h_->nodes.size());
      h_->nodes[cur.node].first_child = first;
      h_->nodes[cur.node].child_count = static_cast<uint32_t>(parts.size());
      const uint32_t depth = h_->nodes[cur.node].depth + 1;
      for (auto& part : parts) {
        const uint32_t id = AddNode(part.first, part.second, cur.node, depth);
        queue.push_back({id, std::move(part.first), std::move(part.second)});
      }
    }
  }

 private:
  struct Pending {
    uint32_t node;
    Poly2 poly;
    std::vector<LeafPos> leaves;
  };

  uint32_t VertexIndex(const P2& p) const {
    const int a = static_cast<int>(std::lround(p.x));
    const int b = static_cast<int>(std::lround(p.y));
    if (!grid_.triangle) return grid_.first_vertex + static_cast<uint32_t>(b * (grid_.nu + 1) + a);
    return row_start_[b] + static_cast<uint32_t>(a);
  }
  const Vec3& Vertex(const P2& p) const { return mesh_.positions[VertexIndex(p)]; }

  // Halves a region along the grid direction in which it is longest (in
  // metres). Both halves hold leaves: the cut is a grid line strictly inside.
  std::vector<std::pair<Poly2, std::vector<LeafPos>>> Split(const Poly2& poly,
                                                            const std::vector<LeafPos>& leaves) {
    int best = -1;
    double best_length = 0, cut = 0;
    for (int f = 0; f < families_; ++f) {
      double lo = Coord(f, poly[0]), hi = lo;
      for (const P2& p : poly) {
        lo = std::min(lo, Coord(f, p));
        hi = std::max(hi, Coord(f, p));
      }
      if (hi - lo < 1.5) continue;
      const double length = (hi - lo) * spacing_[f];
      if (length > best_length) {
        best = f;
        best_length = length;
        cut = std::floor(0.5 * (lo + hi));
      }
    }
    std::vector<std::pair<Poly2, std::vector<LeafPos>>> out;
    if (best < 0) {
      // Not expected for a grid region of several leaves; every leaf a child is still correct.
      for (const LeafPos& l : leaves) out.push_back({LeafPoly(l), {l}});
      return out;
    }
    for (double sign : {-1.0, 1.0}) {
      std::vector<LeafPos> side;
      for (const LeafPos& l : leaves)
        if (sign * (Coord(best, l.at) - cut) > 0) side.push_back(l);
      out.push_back({ClipHalf(poly, best, cut, sign), std::move(side)});
    }
    return out;
  }

  Poly2 LeafPoly(const LeafPos& l) const {
    const double a = std::floor(l.at.x), b = std::floor(l.at.y);
    if (!grid_.triangle) return {{a, b}, {a + 1, b}, {a + 1, b + 1}, {a, b + 1}};
    const bool up = l.at.x - a < 0.5;
    if (up) return {{a, b}, {a + 1, b}, {a, b + 1}};
    return {{a + 1, b}, {a + 1, b + 1}, {a, b + 1}};
  }

  uint32_t AddNode(const Poly2& poly, const std::vector<LeafPos>& leaves, uint32_t parent,
                   uint32_t depth) {
    HierarchyNode n;
    n.surface = surface_;
    n.parent = parent;
    n.depth = depth;
    if (leaves.size() == 1) {
      const Patch& p = mesh_.patches[leaves[0].patch];
      n.patch = leaves[0].patch;
      n.corner_count = p.corner_count;
      for (int k = 0; k < p.corner_count; ++k) n.corner_vertices[k] = p.vertices[k];
    } else {
      if (poly.size() < 3 || poly.size() > static_cast<size_t>(kMaxNodeCorners)) {
        throw std::logic_error("hierarchy: a node polygon has " + std::to_string(poly.size()) +
                               " corners");
      }
      n.corner_count = static_cast<int>(poly.size());
      for (size_t k = 0; k < poly.size(); ++k) n.corner_vertices[k] = VertexIndex(poly[k]);
    }
    for (int k = 0; k < n.corner_count; ++k) n.corners[k] = mesh_.positions[n.corner_vertices[k]];
    Vec3 weighted{0, 0, 0};
    for (const LeafPos& l : leaves) {
      const Patch& p = mesh_.patches[l.patch];
      n.area_m2 += p.area_m2;
      weighted += p.area_m2 * p.centre;
    }
    n.centre = (1.0 / n.area_m2) * weighted;
    n.normal = mesh_.patches[leaves[0].patch].normal;
    for (int a = 0; a < n.corner_count; ++a)
      for (int b = a + 1; b < n.corner_count; ++b)
        n.diameter_m = std::max(n.diameter_m, Length(n.corners[a] - n.corners[b]));
    const uint32_t id = static_cast<uint32_t>(h_->nodes.size());
    h_->nodes.push_back(n);
    if (n.patch != kNoNode) h_->leaf_of_patch[n.patch] = id;
    return id;
  }

  const Mesh& mesh_;
  const SurfaceGrid& grid_;
  uint32_t surface_;
  Hierarchy* h_;
  int families_ = 2;
  double spacing_[3] = {1, 1, 1};
  std::vector<uint32_t> row_start_;
};

// Centroids of the m^2 congruent sub-triangles of (a, b, c), each weighted by its area.
void TriangleSamples(const Vec3& a, const Vec3& b, const Vec3& c, int m,
                     std::vector<PatchSample>* out) {
  const double w = 0.5 * Length(Cross(b - a, c - a)) / (m * m);
  const double inv = 1.0 / m;
  for (int j = 0; j < m; ++j) {
    for (int i = 0; i + j < m; ++i) {
      const auto add = [&](double s, double t) {
        out->push_back({a + (s * inv) * (b - a) + (t * inv) * (c - a), w});
      };
      add(i + 1.0 / 3.0, j + 1.0 / 3.0);
      if (i + j + 1 < m) add(i + 2.0 / 3.0, j + 2.0 / 3.0);
    }
  }
}

}  // namespace

Hierarchy BuildHierarchy(const Mesh& mesh) {
  if (mesh.surface_grids.size() != mesh.surface_centroids.size()) {
    throw std::logic_error("hierarchy: the mesh has no patch grid per surface");
  }
  Hierarchy h;
  h.leaf_of_patch.assign(mesh.patch_count(), kNoNode);
  // About 4/3 nodes per leaf for a quadtree.
  h.nodes.reserve(mesh.patch_count() + mesh.patch_count() / 2 + mesh.surface_grids.size());
  for (uint32_t s = 0; s < mesh.surface_grids.size(); ++s) {
    h.surface_begin.push_back(static_cast<uint32_t>(h.nodes.size()));
    SurfaceTreeBuilder(mesh, s, &h).Build();
    const HierarchyNode& root = h.nodes[h.surface_begin.back()];
    SurfaceFrame f;
    f.origin = root.corners[0];
    f.u = Normalized(root.corners[1] - root.corners[0]);
    f.v = Cross(root.normal, f.u);
    h.frames.push_back(f);
  }
  h.surface_begin.push_back(static_cast<uint32_t>(h.nodes.size()));
  return h;
}

std::array<double, 2> Hierarchy::PlaneCoords(uint32_t surface, const Vec3& x) const {
  const SurfaceFrame& f = frames[surface];
  return {Dot(x - f.origin, f.u), Dot(x - f.origin, f.v)};
}

std::vector<PatchSample> SamplePolygon(const Vec3* corners, int count, bool fine) {
  std::vector<PatchSample> out;
  if (count == 4) {
    // Planar bilinear cells: the Jacobian at a cell midpoint times the cell's
    // parameter area is that cell's exact area (as SamplePatch).
    const int k = fine ? 4 : 2;
    const Vec3 &p0 = corners[0], &p1 = corners[1], &p2 = corners[2], &p3 = corners[3];
    for (int b = 0; b < k; ++b) {
      const double v = (b + 0.5) / k;
      for (int a = 0; a < k; ++a) {
        const double u = (a + 0.5) / k;
        const Vec3 du = (1 - v) * (p1 - p0) + v * (p2 - p3);
        const Vec3 dv = (1 - u) * (p3 - p0) + u * (p2 - p1);
        out.push_back({(1 - u) * (1 - v) * p0 + u * (1 - v) * p1 + u * v * p2 + (1 - u) * v * p3,
                       Length(Cross(du, dv))});
      }
    }
  } else if (count == 3) {
    TriangleSamples(corners[0], corners[1], corners[2], fine ? 4 : 2, &out);
  } else {
    for (int k = 1; k + 1 < count; ++k)
      TriangleSamples(corners[0], corners[k], corners[k + 1], fine ? 2 : 1, &out);
  }
  double total = 0;
  for (const PatchSample& s : out) total += s.weight;
  for (PatchSample& s : out) s.weight /= total;
  return out;
}

NodeSamples::NodeSamples(const Hierarchy& hierarchy, const PatchSampleSets& patch_samples)
    : hierarchy_(hierarchy), patch_samples_(patch_samples) {
  const size_t n = hierarchy.nodes.size();
  coarse_.resize(n);
  fine_.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const HierarchyNode& node = hierarchy.nodes[i];
    if (node.leaf()) continue;
    coarse_[i] = SamplePolygon(node.corners.data(), node.corner_count, false);
    fine_[i] = SamplePolygon(node.corners.data(), node.corner_count, true);
  }
}

const std::vector<PatchSample>& NodeSamples::coarse(uint32_t node) const {
  const HierarchyNode& n = hierarchy_.nodes[node];
  return n.leaf() ? patch_samples_.coarse[n.patch] : coarse_[node];
}

const std::vector<PatchSample>& NodeSamples::fine(uint32_t node) const {
  const HierarchyNode& n = hierarchy_.nodes[node];
  return n.leaf() ? patch_samples_.fine[n.patch] : fine_[node];
}

}  // namespace relight::baker

#include "mesher.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "radiosity_vec.h"

namespace relight::baker {
namespace {

using namespace radiosity_vec;

// Newell's method: robust for any planar polygon, length = 2 x area.
Vec3 NewellNormal(const std::vector<Vec3>& c) {
  Vec3 n{0, 0, 0};
  for (size_t k = 0; k < c.size(); ++k) n += Cross(c[k], c[(k + 1) % c.size()]);
  return n;
}

// In double: a huge surface or a tiny patch size gives counts far past int
// (converting those would be undefined); CheckBudget bounds them first.
double Divisions(double length_m, double patch_size_m) {
  return std::max(1.0, std::ceil(length_m / patch_size_m - 1e-9));
}

class MeshBuilder {
 public:
  MeshBuilder(const Scene& scene, size_t max_patches, Mesh* mesh)
      : scene_(scene), max_patches_(max_patches), mesh_(mesh) {}

  void AddSurface(uint32_t index) {
    const Surface& s = scene_.surfaces[index];
    const Vec3 newell = NewellNormal(s.corners);
    const double area2 = Length(newell);
    double diameter = 0;
    for (const Vec3& a : s.corners)
      for (const Vec3& b : s.corners) diameter = std::max(diameter, Length(a - b));
    if (!(area2 > 1e-12 * diameter * diameter) || !(diameter > 0)) {
      throw SceneError(scene_.path, s.line, "surface '" + s.name + "' has no area");
    }
    normal_ = (1.0 / area2) * newell;
    for (const Vec3& c : s.corners) {
      if (std::abs(Dot(c - s.corners[0], normal_)) > 1e-4 * diameter) {
        throw SceneError(scene_.path, s.line, "surface '" + s.name + "' is not planar");
      }
    }
    surface_ = index;
    rho_ = s.reflectance;
    Vec3 centroid{0, 0, 0};
    for (const Vec3& c : s.corners) centroid += c;
    mesh_->surface_centroids.push_back((1.0 / static_cast<double>(s.corners.size())) * centroid);
    if (s.corners.size() == 4) {
      AddQuad(s.corners);
    } else if (s.corners.size() == 3) {
      AddTriangle(s.corners);
    } else {
      throw SceneError(scene_.path, 0,
                       "surface '" + s.name + "' has " + std::to_string(s.corners.size()) +
                           " corners, expected 3 or 4");
    }
  }

 private:
  uint32_t AddVertex(const Vec3& p) {
    mesh_->positions.push_back(p);
    mesh_->vertex_normals.push_back(normal_);
    mesh_->vertex_reflectance.push_back(rho_);
    mesh_->vertex_surface.push_back(surface_);
    return static_cast<uint32_t>(mesh_->positions.size() - 1);
  }

  void AddRenderTriangle(uint32_t a, uint32_t b, uint32_t c) {
    mesh_->triangles.insert(mesh_->triangles.end(), {a, b, c});
    mesh_->triangle_surface.push_back(surface_);
  }

  void AddPatch(const uint32_t* v, int count) {
    Patch p;
    p.corner_count = count;
    std::copy(v, v + count, p.vertices.begin());
    p.normal = normal_;
    p.reflectance = rho_;
    p.surface = surface_;
    const auto& pos = mesh_->positions;
    // Fan of triangles from corner 0: area and area centroid.
    Vec3 weighted{0, 0, 0};
    for (int k = 1; k + 1 < count; ++k) {
      const Vec3& a = pos[v[0]];
      const Vec3& b = pos[v[k]];
      const Vec3& c = pos[v[k + 1]];
      const double area = 0.5 * Length(Cross(b - a, c - a));
      p.area_m2 += area;
      weighted += (area / 3.0) * (a + b + c);
    }
    p.centre = (1.0 / p.area_m2) * weighted;
    for (int a = 0; a < count; ++a)
      for (int b = a + 1; b < count; ++b)
        p.diameter_m = std::max(p.diameter_m, Length(pos[v[a]] - pos[v[b]]));
    mesh_->patches.push_back(p);
    AddRenderTriangle(v[0], v[1], v[2]);
    if (count == 4) AddRenderTriangle(v[0], v[2], v[3]);
  }

  // Bilinear nu x nv grid; cells keep the corners' CCW order.
  void AddQuad(const std::vector<Vec3>& c) {
    const double ps = scene_.patch_size_m;
    const double du = Divisions(std::max(Length(c[1] - c[0]), Length(c[2] - c[3])), ps);
    const double dv = Divisions(std::max(Length(c[3] - c[0]), Length(c[2] - c[1])), ps);
    CheckBudget(du * dv);
    // Both are now at most max_patches_ (<= kMaxHierarchicalPatches): exact in int.
    const int nu = static_cast<int>(du), nv = static_cast<int>(dv);
    const uint32_t base = static_cast<uint32_t>(mesh_->positions.size());
    mesh_->surface_grids.push_back(
        {static_cast<uint32_t>(mesh_->patches.size()), base, nu, nv, false});
    for (int b = 0; b <= nv; ++b) {
      const double v = static_cast<double>(b) / nv;
      for (int a = 0; a <= nu; ++a) {
        const double u = static_cast<double>(a) / nu;
        AddVertex((1 - u) * (1 - v) * c[0] + u * (1 - v) * c[1] + u * v * c[2] +
                  (1 - u) * v * c[3]);
      }
    }
    const auto at = [&](int a, int b) { return base + static_cast<uint32_t>(b * (nu + 1) + a); };
    for (int b = 0; b < nv; ++b) {
      for (int a = 0; a < nu; ++a) {
        const uint32_t v[4] = {at(a, b), at(a + 1, b), at(a + 1, b + 1), at(a, b + 1)};
        AddPatch(v, 4);
      }
    }
  }

  // Barycentric grid of k^2 sub-triangles: point (i, j) = c0 + i/k (c1-c0) + j/k (c2-c0).
  void AddTriangle(const std::vector<Vec3>& c) {
    const double longest =
        std::max({Length(c[1] - c[0]), Length(c[2] - c[1]), Length(c[0] - c[2])});
    const double dk = Divisions(longest, scene_.patch_size_m);
    CheckBudget(dk * dk);
    const int k = static_cast<int>(dk);  // at most sqrt(max_patches_)
    const uint32_t base = static_cast<uint32_t>(mesh_->positions.size());
    mesh_->surface_grids.push_back(
        {static_cast<uint32_t>(mesh_->patches.size()), base, k, k, true});
    std::vector<uint32_t> row_start(static_cast<size_t>(k) + 1);
    uint32_t next = base;
    for (int j = 0; j <= k; ++j) {
      row_start[j] = next;
      for (int i = 0; i + j <= k; ++i) {
        AddVertex(c[0] + (static_cast<double>(i) / k) * (c[1] - c[0]) +
                  (static_cast<double>(j) / k) * (c[2] - c[0]));
        ++next;
      }
    }
    const auto at = [&](int i, int j) { return row_start[j] + static_cast<uint32_t>(i); };
    for (int j = 0; j < k; ++j) {
      for (int i = 0; i + j < k; ++i) {
        const uint32_t up[3] = {at(i, j), at(i + 1, j), at(i, j + 1)};
        AddPatch(up, 3);
        if (i + j + 1 < k) {
          const uint32_t down[3] = {at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)};
          AddPatch(down, 3);
        }
      }
    }
  }

  // `more` in double, before any count is converted to an integer; NaN or
  // infinity (a surface spanning past 1e308 m) fails too.
  void CheckBudget(double more) {
    const double total = static_cast<double>(mesh_->patches.size()) + more;
    if (!(total <= static_cast<double>(max_patches_))) {
      const bool dense = max_patches_ <= kMaxDensePatches;
      const Surface& s = scene_.surfaces[surface_];
      char count[32], size[32];
      std::snprintf(count, sizeof count, "%.4g", more);
      std::snprintf(size, sizeof size, "%g", scene_.patch_size_m);
      throw SceneError(scene_.path, s.line,
                       "surface '" + s.name + "': the mesh would be too large: patch_size " +
                           size + " m cuts it into " + count +
                           " patches, " + std::to_string(mesh_->patches.size()) +
                           " before it, more than the limit of " +
                           std::to_string(max_patches_) + " patches" +
                           (dense ? " (dense form factors would not fit in memory; the "
                                    "hierarchical solver has no such limit)"
                                  : "") +
                           "; raise patch_size");
    }
  }

  const Scene& scene_;
  size_t max_patches_;
  Mesh* mesh_;
  Vec3 normal_{};
  Rgb rho_{};
  uint32_t surface_ = 0;
};

void BuildVertexAdjacency(Mesh* mesh) {
  const size_t nv = mesh->vertex_count();
  std::vector<uint32_t> counts(nv + 1, 0);
  for (const Patch& p : mesh->patches)
    for (int k = 0; k < p.corner_count; ++k) ++counts[p.vertices[k] + 1];
  for (size_t v = 0; v < nv; ++v) counts[v + 1] += counts[v];
  mesh->vertex_patch_offsets = counts;
  mesh->vertex_patch_ids.assign(counts[nv], 0);
  std::vector<uint32_t> fill(counts.begin(), counts.end() - 1);
  for (uint32_t i = 0; i < mesh->patches.size(); ++i) {
    const Patch& p = mesh->patches[i];
    for (int k = 0; k < p.corner_count; ++k) mesh->vertex_patch_ids[fill[p.vertices[k]]++] = i;
  }
}

}  // namespace

Mesh BuildMesh(const Scene& scene, size_t max_patches) {
  if (!(scene.patch_size_m > 0) || !std::isfinite(scene.patch_size_m)) {
    throw SceneError(scene.path, 0, "patch_size must be a positive length in metres");
  }
  if (scene.surfaces.empty()) throw SceneError(scene.path, 0, "the scene has no surfaces");
  Mesh mesh;
  MeshBuilder builder(scene, max_patches, &mesh);
  for (uint32_t s = 0; s < scene.surfaces.size(); ++s) builder.AddSurface(s);
  BuildVertexAdjacency(&mesh);
  Vec3 lo{std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
          std::numeric_limits<double>::max()};
  Vec3 hi = -1.0 * lo;
  for (const Vec3& p : mesh.positions) {
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], p[a]);
      hi[a] = std::max(hi[a], p[a]);
    }
  }
  mesh.scene_diagonal_m = Length(hi - lo);
  return mesh;
}

std::vector<PatchSample> SamplePatch(const Mesh& mesh, const Patch& patch, int k) {
  std::vector<PatchSample> out;
  out.reserve(static_cast<size_t>(k) * static_cast<size_t>(k));
  const auto& pos = mesh.positions;
  const Vec3& p0 = pos[patch.vertices[0]];
  const Vec3& p1 = pos[patch.vertices[1]];
  const Vec3& p2 = pos[patch.vertices[2]];
  const double inv_k = 1.0 / k;
  if (patch.corner_count == 3) {
    // Centroids of k^2 congruent sub-triangles: equal weights.
    const double w = inv_k * inv_k;
    for (int j = 0; j < k; ++j) {
      for (int i = 0; i + j < k; ++i) {
        const auto add = [&](double s, double t) {
          out.push_back({p0 + (s * inv_k) * (p1 - p0) + (t * inv_k) * (p2 - p0), w});
        };
        add(i + 1.0 / 3.0, j + 1.0 / 3.0);
        if (i + j + 1 < k) add(i + 2.0 / 3.0, j + 2.0 / 3.0);
      }
    }
    return out;
  }
  // Planar bilinear cell: the Jacobian is affine in (u, v), so its value at a
  // cell midpoint times the cell's parameter area is that cell's exact area.
  const Vec3& p3 = pos[patch.vertices[3]];
  double total = 0;
  for (int b = 0; b < k; ++b) {
    const double v = (b + 0.5) * inv_k;
    for (int a = 0; a < k; ++a) {
      const double u = (a + 0.5) * inv_k;
      const Vec3 du = (1 - v) * (p1 - p0) + v * (p2 - p3);
      const Vec3 dv = (1 - u) * (p3 - p0) + u * (p2 - p1);
      const double jac = Length(Cross(du, dv));
      out.push_back(
          {(1 - u) * (1 - v) * p0 + u * (1 - v) * p1 + u * v * p2 + (1 - u) * v * p3, jac});
      total += jac;
    }
  }
  for (PatchSample& s : out) s.weight /= total;
  return out;
}

}  // namespace relight::baker

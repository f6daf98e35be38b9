#include "visibility.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "radiosity_vec.h"

namespace relight::baker {
namespace {

using namespace radiosity_vec;

// Embree works in float32: 1e-5 of the scene's size is ~100 ulps of the
// largest coordinate, well above its rounding, well below a visible shadow.
constexpr double kRelativeEpsilon = 1e-5;

void ThrowOnError(RTCDevice device, const char* what) {
  const RTCError err = rtcGetDeviceError(device);
  if (err != RTC_ERROR_NONE) {
    throw std::runtime_error(std::string("embree: ") + what + " failed (error " +
                             std::to_string(static_cast<int>(err)) + ")");
  }
}

}  // namespace

struct Visibility::Embree {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  ~Embree() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

Visibility::Visibility(const Mesh& mesh, int threads)
    : embree_(std::make_unique<Embree>()),
      epsilon_m_(std::max(1e-6, kRelativeEpsilon * mesh.scene_diagonal_m)) {
  const std::string config = threads > 0 ? "threads=" + std::to_string(threads) : "";
  embree_->device = rtcNewDevice(config.c_str());
  if (!embree_->device) throw std::runtime_error("embree: cannot create a device");
  embree_->scene = rtcNewScene(embree_->device);
  rtcSetSceneFlags(embree_->scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(embree_->scene, RTC_BUILD_QUALITY_HIGH);

  RTCGeometry geom = rtcNewGeometry(embree_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
      geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh.vertex_count()));
  const size_t triangle_count = mesh.triangles.size() / 3;
  auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
      geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), triangle_count));
  ThrowOnError(embree_->device, "allocating the geometry");
  for (size_t v = 0; v < mesh.vertex_count(); ++v)
    for (int a = 0; a < 3; ++a) vertices[3 * v + a] = static_cast<float>(mesh.positions[v][a]);
  std::copy(mesh.triangles.begin(), mesh.triangles.end(), indices);
  rtcCommitGeometry(geom);
  rtcAttachGeometry(embree_->scene, geom);
  rtcReleaseGeometry(geom);
  rtcCommitScene(embree_->scene);
  ThrowOnError(embree_->device, "building the scene");
}

Visibility::~Visibility() = default;

bool Visibility::Visible(const Vec3& from, const Vec3& to) const {
  const Vec3 d = to - from;
  const double len = Length(d);
  if (len <= 2.0 * epsilon_m_) return true;
  const Vec3 dir = (1.0 / len) * d;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay ray{};
  ray.org_x = static_cast<float>(from[0]);
  ray.org_y = static_cast<float>(from[1]);
  ray.org_z = static_cast<float>(from[2]);
  ray.dir_x = static_cast<float>(dir[0]);
  ray.dir_y = static_cast<float>(dir[1]);
  ray.dir_z = static_cast<float>(dir[2]);
  // Both ends skip epsilon: a luminaire mounted flush on a ceiling must not
  // shadow itself on the ceiling's triangles.
  ray.tnear = static_cast<float>(epsilon_m_);
  ray.tfar = static_cast<float>(len - epsilon_m_);
  ray.mask = std::numeric_limits<unsigned>::max();
  ray.flags = 0;
  rtcOccluded1(embree_->scene, &context, &ray);
  // Embree marks an occluded ray by setting tfar to -inf.
  return ray.tfar >= 0.0f;
}

int Visibility::CountVisible(const Vec3* from, const Vec3* to, int n) const {
  int visible = 0;
  for (int first = 0; first < n; first += 16) {
    const int count = std::min(16, n - first);
    alignas(64) RTCRay16 rays;
    alignas(64) int valid[16];
    for (int i = 0; i < 16; ++i) {
      // Every lane defined (Embree reads all 16): an unused one is a unit
      // ray of zero length, and not valid.
      valid[i] = 0;
      rays.org_x[i] = rays.org_y[i] = rays.org_z[i] = 0;
      rays.dir_x[i] = rays.dir_y[i] = 0;
      rays.dir_z[i] = 1;
      rays.tnear[i] = rays.tfar[i] = rays.time[i] = 0;
      rays.mask[i] = std::numeric_limits<unsigned>::max();
      rays.id[i] = rays.flags[i] = 0;
      if (i >= count) continue;
      const Vec3 d = to[first + i] - from[first + i];
      const double len = Length(d);
      if (len <= 2.0 * epsilon_m_) {  // as Visible()
        ++visible;
        continue;
      }
      const Vec3 dir = (1.0 / len) * d;
      valid[i] = -1;
      rays.org_x[i] = static_cast<float>(from[first + i][0]);
      rays.org_y[i] = static_cast<float>(from[first + i][1]);
      rays.org_z[i] = static_cast<float>(from[first + i][2]);
      rays.dir_x[i] = static_cast<float>(dir[0]);
      rays.dir_y[i] = static_cast<float>(dir[1]);
      rays.dir_z[i] = static_cast<float>(dir[2]);
      rays.tnear[i] = static_cast<float>(epsilon_m_);
      rays.tfar[i] = static_cast<float>(len - epsilon_m_);
    }
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    rtcOccluded16(valid, embree_->scene, &context, &rays);
    for (int i = 0; i < count; ++i)
      if (valid[i] != 0 && rays.tfar[i] >= 0.0f) ++visible;
  }
  return visible;
}

Vec3 Visibility::Offset(const Vec3& p, const Vec3& n) const { return p + epsilon_m_ * n; }

}  // namespace relight::baker

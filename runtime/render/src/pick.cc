#include "relight/render/pick.h"

#include <cmath>
#include <vector>

namespace relight {

Status PickPixel(OsMesaFrame* frame, const BakeMesh& mesh, int x, int y, PickResult* out) {
  if (x < 0 || y < 0 || x >= frame->width() || y >= frame->height()) {
    return Status(StatusCode::kInvalidArgument,
                  StrFormat("pick: pixel %d,%d is outside the %dx%d frame", x, y, frame->width(),
                            frame->height()));
  }
  std::vector<uint32_t> ids(static_cast<size_t>(frame->width()) * frame->height());
  RELIGHT_RETURN_IF_ERROR(frame->DrawTriangleIds(ids.data()));
  const uint32_t id = ids[static_cast<size_t>(y) * frame->width() + x];
  if (id == 0xFFFFFFFFu || id >= mesh.triangle_count()) {
    return Status(StatusCode::kNotFound, StrFormat("pick: pixel %d,%d shows no surface", x, y));
  }
  PickResult r;
  r.triangle = id;
  r.surface = mesh.triangle_surface[id];
  RELIGHT_RETURN_IF_ERROR(frame->UnprojectPixel(x, y, r.world_m));
  for (int i = 0; i < 3; ++i) {
    r.world_q16[i] = static_cast<int32_t>(std::lround(static_cast<double>(r.world_m[i]) * 65536.0));
  }
  *out = r;
  return Status::Ok();
}

}  // namespace relight

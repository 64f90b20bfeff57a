#include "render/camera.hpp"

#include <algorithm>

namespace apiclab::render {

void orbit_axes(const View& v, Vec3& right, Vec3& up, Vec3& back) {
  // Two horizontal axes and the vertical one, so that yaw = 0 looks along a horizontal axis.
  Vec3 h1, h2, vertical;
  h1[(v.up_axis + 1) % 3] = 1;
  h2[(v.up_axis + 2) % 3] = 1;
  vertical[v.up_axis] = 1;
  if (v.up_axis == 2) h2 = h2 * -1.0f;    // z up: x right, looking along +y
  if (v.up_axis == 1) std::swap(h1, h2);  // y up: x right, looking along -z
  const float yaw = radians(v.yaw), pitch = radians(v.pitch);
  back = (h1 * std::sin(yaw) + h2 * std::cos(yaw)) * std::cos(pitch) + vertical * std::sin(pitch);
  right = normalize(cross(vertical, back));
  up = cross(back, right);
}

View frame_view(View v, const Box3& box, float aspect, float margin) {
  const Vec3 size = box.size(), c = box.center();
  if (v.dim == 2) {
    v.center = {c.x, c.y};
    float half = std::max(size.y / 2, size.x / 2 / aspect);
    v.half_height = std::max(half, 1e-6f) / (1 - 2 * margin);
    return v;
  }
  // Smallest distance at which all eight corners lie inside the frustum (with margin)...
  Vec3 right, up, back;
  orbit_axes(v, right, up, back);
  const float tan_y = std::tan(radians(v.fov_y) / 2) * (1 - 2 * margin);
  const float tan_x = tan_y * aspect;
  float distance = 0;
  for (int i = 0; i < 8; ++i) {
    Vec3 corner{i & 1 ? box.max.x : box.min.x, i & 2 ? box.max.y : box.min.y,
                i & 4 ? box.max.z : box.min.z};
    Vec3 d = corner - c;
    float depth = dot(d, back);  // towards the eye
    distance = std::max(
        {distance, depth + std::abs(dot(d, right)) / tan_x, depth + std::abs(dot(d, up)) / tan_y});
  }
  v.target = c;
  v.distance = std::max(distance, 1e-6f);
  // ...then, as perspective makes the picture lopsided, centre the projected box and let it
  // fill the frame: a few fixed-point steps.
  for (int iteration = 0; iteration < 4; ++iteration) {
    const Camera cam = make_camera(v, aspect, box);
    float lo[2] = {1e30f, 1e30f}, hi[2] = {-1e30f, -1e30f};
    for (int i = 0; i < 8; ++i) {
      Vec4 p = cam.projection *
               (cam.view * Vec4{i & 1 ? box.max.x : box.min.x, i & 2 ? box.max.y : box.min.y,
                                i & 4 ? box.max.z : box.min.z, 1});
      lo[0] = std::min(lo[0], p.x / p.w), hi[0] = std::max(hi[0], p.x / p.w);
      lo[1] = std::min(lo[1], p.y / p.w), hi[1] = std::max(hi[1], p.y / p.w);
    }
    const float half_tan_y = std::tan(radians(v.fov_y) / 2);
    v.target = v.target + right * ((lo[0] + hi[0]) / 2 * half_tan_y * aspect * v.distance) +
               up * ((lo[1] + hi[1]) / 2 * half_tan_y * v.distance);
    const float fill = std::max(hi[0] - lo[0], hi[1] - lo[1]) / 2 / (1 - 2 * margin);
    v.distance *= std::clamp(fill, 0.5f, 2.0f);
  }
  return v;
}

Camera make_camera(const View& v, float aspect, const Box3& scene) {
  Camera cam;
  const float radius = std::max(length(scene.size()) / 2, 1e-6f);
  if (v.dim == 2) {
    const float hh = v.half_height, hw = hh * aspect;
    cam.projection = ortho(v.center.x - hw, v.center.x + hw, v.center.y - hh, v.center.y + hh,
                           -1 - radius, 1 + radius);
    cam.eye = {v.center.x, v.center.y, 1};
    return cam;
  }
  Vec3 right, up, back;
  orbit_axes(v, right, up, back);
  cam.perspective = true;
  cam.eye = v.target + back * v.distance;
  cam.view = look_at(cam.eye, v.target, up);
  const float to_center = length(scene.center() - cam.eye);
  const float near = std::max(to_center - 1.5f * radius, v.distance * 0.01f);
  const float far = to_center + 1.5f * radius;
  cam.projection = perspective(radians(v.fov_y), aspect, near, far);
  return cam;
}

}  // namespace apiclab::render

// Cameras: orthographic for 2D scenes, an orbit camera for 3D ones, both framed
// automatically on the scene's domain box.
#pragma once
#include "render/math.hpp"

namespace apiclab::render {

struct Box3 {
  Vec3 min, max;
  Vec3 center() const { return (min + max) * 0.5f; }
  Vec3 size() const { return max - min; }
};

// What a viewer sees; the GUI edits these numbers (pan, zoom, orbit).
struct View {
  int dim = 2;
  // 2D: the point at the centre of the viewport and half the visible height.
  Vec2 center;
  float half_height = 1;
  // 3D: an orbit around `target`, angles in degrees, `up_axis` (0, 1, 2) pointing up.
  Vec3 target;
  float yaw = 35, pitch = 22, distance = 1, fov_y = 30;
  int up_axis = 1;
};

// Frames `box` in a viewport of aspect width / height, leaving `margin` (fraction) free.
// 3D keeps the view's angles and up axis and picks target and distance.
View frame_view(View view, const Box3& box, float aspect, float margin = 0.04f);
inline View frame_view(int dim, const Box3& box, float aspect, int up_axis = 1) {
  View v;
  v.dim = dim;
  v.up_axis = up_axis;
  return frame_view(v, box, aspect);
}

struct Camera {
  Mat4 view, projection;
  bool perspective = false;
  Vec3 eye;  // world position (3D)
};
// `scene` bounds the near and far planes.
Camera make_camera(const View& view, float aspect, const Box3& scene);

// The camera's axes in world space for the orbit angles: right, up, and from target to eye.
void orbit_axes(const View& view, Vec3& right, Vec3& up, Vec3& back);

}  // namespace apiclab::render

// Scene geometry computed on the CPU, testable without GL: where a collider plane cuts the
// domain box.
#pragma once
#include <vector>

#include "render/camera.hpp"

namespace apiclab::render {

// Corners of the plane n·(x − p) = 0 inside the box, in order around the polygon
// (2 points in 2D, 3 to 6 in 3D); empty when the plane misses the box.
std::vector<Vec3> plane_in_box(Vec3 p, Vec3 n, const Box3& box, int dim);

}  // namespace apiclab::render

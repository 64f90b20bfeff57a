// Small vector and matrix types for the renderer (column-major like GLSL), float only.
#pragma once
#include <algorithm>
#include <cmath>

namespace apiclab::render {

struct Vec2 {
  float x = 0, y = 0;
};
struct Vec3 {
  float x = 0, y = 0, z = 0;
  float& operator[](int i) { return i == 0 ? x : i == 1 ? y : z; }
  float operator[](int i) const { return i == 0 ? x : i == 1 ? y : z; }
};
inline Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3 operator*(Vec3 a, float s) { return {a.x * s, a.y * s, a.z * s}; }
inline Vec3 operator*(float s, Vec3 a) { return a * s; }
inline float dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3 cross(Vec3 a, Vec3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline float length(Vec3 a) { return std::sqrt(dot(a, a)); }
inline Vec3 normalize(Vec3 a) {
  float l = length(a);
  return l > 0 ? a * (1 / l) : a;
}

struct Vec4 {
  float x = 0, y = 0, z = 0, w = 0;
};

// Column-major 4x4: m[column * 4 + row], as glUniformMatrix4fv expects with transpose = false.
struct Mat4 {
  float m[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  float& operator()(int row, int col) { return m[col * 4 + row]; }
  float operator()(int row, int col) const { return m[col * 4 + row]; }
};
inline Mat4 operator*(const Mat4& a, const Mat4& b) {
  Mat4 r;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      float s = 0;
      for (int k = 0; k < 4; ++k) s += a(i, k) * b(k, j);
      r(i, j) = s;
    }
  return r;
}
inline Vec4 operator*(const Mat4& a, Vec4 v) {
  float in[4] = {v.x, v.y, v.z, v.w}, out[4];
  for (int i = 0; i < 4; ++i)
    out[i] = a(i, 0) * in[0] + a(i, 1) * in[1] + a(i, 2) * in[2] + a(i, 3) * in[3];
  return {out[0], out[1], out[2], out[3]};
}

inline Mat4 ortho(float left, float right, float bottom, float top, float near, float far) {
  Mat4 r;
  r(0, 0) = 2 / (right - left);
  r(1, 1) = 2 / (top - bottom);
  r(2, 2) = -2 / (far - near);
  r(0, 3) = -(right + left) / (right - left);
  r(1, 3) = -(top + bottom) / (top - bottom);
  r(2, 3) = -(far + near) / (far - near);
  return r;
}

inline Mat4 perspective(float fov_y_radians, float aspect, float near, float far) {
  Mat4 r;
  float f = 1 / std::tan(fov_y_radians / 2);
  r(0, 0) = f / aspect;
  r(1, 1) = f;
  r(2, 2) = (far + near) / (near - far);
  r(2, 3) = 2 * far * near / (near - far);
  r(3, 2) = -1;
  r(3, 3) = 0;
  return r;
}

inline Mat4 look_at(Vec3 eye, Vec3 target, Vec3 up) {
  Vec3 f = normalize(target - eye), s = normalize(cross(f, up)), u = cross(s, f);
  Mat4 r;
  r(0, 0) = s.x, r(0, 1) = s.y, r(0, 2) = s.z, r(0, 3) = -dot(s, eye);
  r(1, 0) = u.x, r(1, 1) = u.y, r(1, 2) = u.z, r(1, 3) = -dot(u, eye);
  r(2, 0) = -f.x, r(2, 1) = -f.y, r(2, 2) = -f.z, r(2, 3) = dot(f, eye);
  return r;
}

constexpr float kPi = 3.14159265358979f;
inline float radians(float degrees) { return degrees * kPi / 180; }

}  // namespace apiclab::render

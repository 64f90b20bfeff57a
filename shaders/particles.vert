#version 330 core
// One particle: a point sprite (one vertex, fast on llvmpipe) or, when a particle is larger
// than the largest point the driver draws, a camera-facing instanced quad. disc.frag or
// sphere.frag fills it.
layout(location = 0) in vec2 a_corner;  // quads: (-1,-1) .. (1,1)
layout(location = 1) in vec3 a_center;
layout(location = 2) in float a_radius;
layout(location = 3) in vec4 a_color;

uniform mat4 u_view;
uniform mat4 u_projection;
uniform bool u_perspective;
uniform bool u_points;
uniform float u_viewport_height;  // pixels
uniform float u_min_radius_px;    // tiny particles stay visible
uniform float u_rim;              // 2D: strength of the darker rim
uniform int u_flatten_axis;       // shadows: particles moved onto the floor along this axis
uniform float u_flatten_to;
uniform float u_radius_scale;     // shadows: wider than the particles

out vec2 v_offset;       // quads: position in the quad in units of the drawn radius
flat out vec3 v_center;  // view space
flat out float v_radius;
flat out float v_pad;    // half the sprite's side in units of the radius
flat out float v_rim;
flat out float v_height;  // shadows: how far above the floor the particle is
flat out vec4 v_color;

void main() {
  vec3 world = a_center;
  v_height = 0.0;
  if (u_flatten_axis >= 0) {
    v_height = world[u_flatten_axis] - u_flatten_to;
    world[u_flatten_axis] = u_flatten_to;
  }
  vec4 center = u_view * vec4(world, 1.0);
  float depth = u_perspective ? -center.z : 1.0;
  float pixels_per_unit = u_projection[1][1] * 0.5 * u_viewport_height / depth;
  float radius_px = max(a_radius * u_radius_scale * pixels_per_unit, 1e-6);
  // Discs of a few pixels grow a little, so a dense block reads as solid, not as moire.
  float grow = mix(1.25, 1.0, clamp((radius_px - 1.5) / 3.0, 0.0, 1.0));
  float radius = a_radius * u_radius_scale * grow * max(1.0, u_min_radius_px / (grow * radius_px));
  radius_px = max(grow * radius_px, u_min_radius_px);
  // Room for the antialiased edge (coverage ends half a pixel out) and for the perspective
  // silhouette, which is a little wider than the sphere's radius.
  float pad = 1.0 + 0.6 / radius_px + (u_perspective ? 0.25 * radius / depth + 0.02 : 0.0);
  v_center = center.xyz;
  v_radius = radius;
  v_pad = pad;
  v_rim = u_rim * clamp((radius_px - 2.0) / 4.0, 0.0, 1.0);
  v_color = a_color;
  if (u_points) {
    v_offset = vec2(0.0);
    gl_PointSize = 2.0 * pad * radius_px;
    gl_Position = u_projection * center;
  } else {
    v_offset = a_corner * pad;
    gl_Position = u_projection * vec4(center.xyz + vec3(v_offset * radius, 0.0), 1.0);
  }
}

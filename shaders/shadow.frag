#version 330 core
// A soft contact shadow on the floor under each 3D particle, fading with height, so that
// heights read at a glance. Drawn with GL_MIN blending: overlapping shadows do not stack.
in vec2 v_offset;
flat in vec3 v_center;  // the particle's foot on the floor, view space
flat in float v_radius;
flat in float v_pad;
flat in float v_height;

uniform bool u_points;
uniform bool u_perspective;
uniform vec3 u_floor_normal;  // view space
uniform float u_shadow_reach;  // height at which a shadow has faded away
uniform vec3 u_floor_color;
out vec4 frag_color;

void main() {
  vec2 offset = u_points ? (gl_PointCoord * 2.0 - 1.0) * vec2(1.0, -1.0) * v_pad : v_offset;
  vec3 q = v_center + vec3(offset * v_radius, 0.0);
  vec3 origin = u_perspective ? vec3(0.0) : vec3(q.xy, 0.0);
  vec3 dir = u_perspective ? normalize(q) : vec3(0.0, 0.0, -1.0);
  float facing = dot(dir, u_floor_normal);
  if (abs(facing) < 1e-6) discard;
  vec3 hit = origin + dir * (dot(v_center - origin, u_floor_normal) / facing);
  float d = length(hit - v_center) / v_radius;
  float fade = clamp(1.0 - v_height / u_shadow_reach, 0.0, 1.0);
  float strength = 0.3 * fade * (1.0 - smoothstep(0.2, 1.0, d));
  if (strength <= 0.003) discard;
  frag_color = vec4(u_floor_color * (1.0 - strength), 1.0);
}

#version 330 core
// Line segments and arrows with widths in pixels (core profile has no wide lines): each
// instance expands a 9-vertex template, a shaft quad and a head triangle, in screen space.
layout(location = 0) in vec3 a_template;  // (along 0..1, side -1..1, part: 0 shaft, 1 head)
layout(location = 1) in vec3 a_from;
layout(location = 2) in vec3 a_to;
layout(location = 3) in vec4 a_color;
layout(location = 4) in vec3 a_shape;  // width px, head length px (0: plain line), lift

uniform mat4 u_view;
uniform mat4 u_projection;
uniform vec2 u_viewport;  // pixels
flat out vec4 v_color;

vec4 lifted(vec3 world, float lift) {
  // Moved towards the eye by `lift`, so arrows start on a sphere's surface, not inside it.
  vec4 p = u_view * vec4(world, 1.0);
  p.xyz += (u_projection[3][3] == 0.0 ? normalize(-p.xyz) : vec3(0.0, 0.0, 1.0)) * lift;
  return u_projection * p;
}

void main() {
  vec4 ca = lifted(a_from, a_shape.z), cb = lifted(a_to, a_shape.z);
  vec3 na = ca.xyz / ca.w, nb = cb.xyz / cb.w;
  vec2 half_viewport = 0.5 * u_viewport;
  vec2 sa = na.xy * half_viewport, sb = nb.xy * half_viewport;
  vec2 d = sb - sa;
  float len = length(d);
  vec2 dir = len > 1e-4 ? d / len : vec2(1.0, 0.0);
  vec2 normal = vec2(-dir.y, dir.x);
  float width = a_shape.x;
  float head = min(a_shape.y, 0.45 * len);
  float cap = a_shape.y > 0.0 ? 0.0 : 0.5 * width;  // square caps join box corners
  float along;
  vec2 p;
  if (a_template.z < 0.5) {
    along = mix(-cap, len - 0.8 * head + cap, a_template.x);
    p = sa + dir * along + normal * a_template.y * 0.5 * width;
  } else {
    along = mix(len - head, len, a_template.x);
    p = sa + dir * along + normal * a_template.y * max(0.42 * head, 0.5 * width);
  }
  float z = mix(na.z, nb.z, len > 1e-4 ? clamp(along / len, 0.0, 1.0) : 0.0);
  gl_Position = vec4(p / half_viewport, z, 1.0);
  v_color = a_color;
}

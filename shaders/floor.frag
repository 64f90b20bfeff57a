#version 330 core
// The floor colour darkened by a tent-filtered lookup in the shadow map.
in vec3 v_world;
in vec4 v_color;
uniform sampler2D u_shadow;
uniform vec3 u_origin;  // floor corner where the map's (0, 0) lies
uniform vec3 u_axis_u;  // world to map coordinates: u = dot(x - origin, axis_u)
uniform vec3 u_axis_v;
uniform float u_texel;
out vec4 frag_color;

void main() {
  vec2 uv = vec2(dot(v_world - u_origin, u_axis_u), dot(v_world - u_origin, u_axis_v));
  float shadow = 0.0;
  for (int i = -1; i <= 1; ++i)
    for (int j = -1; j <= 1; ++j)
      shadow += float((2 - abs(i)) * (2 - abs(j))) *
                texture(u_shadow, uv + vec2(i, j) * 1.5 * u_texel).r;
  frag_color = vec4(v_color.rgb * (1.0 - 0.3 * shadow / 16.0), v_color.a);
}

#version 330 core
// The floor's shadow map, seen from straight above: each 3D particle leaves a soft dot whose
// darkness fades with its height; GL_MAX blending keeps overlapping dots from stacking.
in vec2 v_offset;
flat in float v_pad;
flat in float v_height;
uniform bool u_points;
uniform float u_shadow_reach;  // height at which a shadow has faded away
out vec4 frag_color;

void main() {
  vec2 offset = u_points ? (gl_PointCoord * 2.0 - 1.0) * v_pad : v_offset;
  float fade = clamp(1.0 - v_height / u_shadow_reach, 0.0, 1.0);
  frag_color = vec4(fade * (1.0 - smoothstep(0.6, 1.0 + 0.5 * (v_pad - 1.0), length(offset))));
}

#version 330 core
// A flat 2D disc with an antialiased edge and a slightly darker rim, so that touching
// particles still read as particles.
in vec2 v_offset;
flat in float v_pad;
flat in float v_rim;
flat in vec4 v_color;
uniform bool u_points;
out vec4 frag_color;

void main() {
  vec2 offset = u_points ? (gl_PointCoord * 2.0 - 1.0) * vec2(1.0, -1.0) * v_pad : v_offset;
  float d = length(offset);
  float aa = max(fwidth(d), 1e-4);
  float coverage = clamp((1.0 - d) / aa + 0.5, 0.0, 1.0);
  if (coverage <= 0.0) discard;
  float rim = smoothstep(0.80 - aa, 1.0 - aa, d) * v_rim;
  frag_color = vec4(mix(v_color.rgb, v_color.rgb * 0.68, rim), v_color.a * coverage);
}

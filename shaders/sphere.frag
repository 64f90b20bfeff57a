#version 330 core
// A ray-traced sphere impostor: exact silhouette, normal and depth, so spheres intersect
// correctly; shaded by a key light, a fill light and a soft specular highlight.
in vec2 v_offset;
flat in vec3 v_center;
flat in float v_radius;
flat in float v_pad;
flat in vec4 v_color;

uniform mat4 u_projection;
uniform bool u_perspective;
uniform bool u_points;
out vec4 frag_color;

void main() {
  // The fragment on the camera-facing square through the sphere's centre.
  vec2 offset = u_points ? (gl_PointCoord * 2.0 - 1.0) * vec2(1.0, -1.0) * v_pad : v_offset;
  vec3 v_point = v_center + vec3(offset * v_radius, 0.0);
  vec3 origin = u_perspective ? vec3(0.0) : vec3(v_point.xy, 0.0);
  vec3 dir = u_perspective ? normalize(v_point) : vec3(0.0, 0.0, -1.0);
  vec3 oc = v_center - origin;
  float b = dot(oc, dir);
  float miss2 = max(dot(oc, oc) - b * b, 0.0);
  float d = sqrt(miss2) / v_radius;  // 1 on the silhouette
  float aa = max(fwidth(d), 1e-4);
  float coverage = clamp((1.0 - d) / aa + 0.5, 0.0, 1.0);
  if (coverage <= 0.0) discard;

  float t = b - sqrt(max(v_radius * v_radius - miss2, 0.0));
  vec3 p = origin + t * dir;
  vec3 n = normalize(p - v_center);
  vec3 to_eye = -dir;
  vec3 key = normalize(vec3(-0.45, 0.70, 0.55));
  vec3 fill = normalize(vec3(0.6, -0.2, 0.75));
  float diffuse = max(dot(n, key), 0.0);
  float fill_light = max(dot(n, fill), 0.0);
  float specular = pow(max(dot(n, normalize(key + to_eye)), 0.0), 40.0);
  vec3 c = v_color.rgb * (0.30 + 0.62 * diffuse + 0.18 * fill_light) + vec3(0.20 * specular);

  vec4 clip = u_projection * vec4(p, 1.0);
  gl_FragDepth = clamp(clip.z / clip.w * 0.5 + 0.5, 0.0, 1.0);
  frag_color = vec4(c, coverage);
}

#version 330 core
// The floor of a 3D domain, shaded by the shadow map.
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec4 a_color;
uniform mat4 u_matrix;
out vec3 v_world;
out vec4 v_color;
void main() {
  v_world = a_position;
  v_color = a_color;
  gl_Position = u_matrix * vec4(a_position, 1.0);
}

#version 330 core
// Element edges drawn over the surface. The lines lie ON the surface, so they are pulled
// towards the viewer by a small depth bias (NDC units, u_depth_bias) in addition to the
// polygon offset that pushes the surface back; otherwise they z-fight at grazing angles.
layout(location = 0) in vec3 a_position;
uniform mat4 u_view;
uniform mat4 u_proj;
uniform float u_depth_bias;
void main() {
  gl_Position = u_proj * u_view * vec4(a_position, 1.0);
  gl_Position.z -= u_depth_bias * gl_Position.w;
}

#version 330 core
// Capsule surface: world-space position, unit normal and colour-field value per vertex.
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in float a_value;
uniform mat4 u_view;   // rigid: rotation + translation, so mat3(u_view) transforms normals
uniform mat4 u_proj;
uniform vec2 u_range;  // field value mapped to colour-map 0 and 1
// The outline's smooth lines (render/silhouette.h): moved u_inset pixels towards the inside of
// the surface, along the screen direction of the normal, so that a one-pixel line covers the
// background pixels beside the edge as the surface would (box-filter coverage). 0 for the surface.
uniform float u_inset;
uniform vec2 u_viewport;  // pixels
out vec3 v_pos_eye;
out vec3 v_nrm_eye;
out float v_t;
void main() {
  vec4 p = u_view * vec4(a_position, 1.0);
  v_pos_eye = p.xyz;
  v_nrm_eye = mat3(u_view) * a_normal;
  v_t = (a_value - u_range.x) / (u_range.y - u_range.x);
  gl_Position = u_proj * p;
  vec2 d = v_nrm_eye.xy;
  if (u_inset != 0.0 && dot(d, d) > 0.0)
    gl_Position.xy -= normalize(d) * (2.0 * u_inset / u_viewport) * gl_Position.w;
}

#version 330 core
// Capsule surface: world-space position, unit normal and colour-field value per vertex; lit per
// vertex (Blinn-Phong with two white directional lights fixed to the camera, both in the camera's
// vertical plane x_eye = 0, so a left-right mirror-symmetric scene stays symmetric; white light
// and an equal-channel specular term leave the hue of the base colour unchanged). Per vertex on
// the upsampled grid (NB=25 per element: triangles of a few pixels) the colours are those of
// per-pixel lighting to within a few levels, at about half the fragment cost on a software
// rasteriser. Both sides are lit; the fragment shader picks the side it sees. The lighting is
// soft (ambient 0.6, a faint highlight) so that the colour of a point reads back on the colour
// bar: within 6 % of the range for viridis and 2 % for coolwarm where the surface faces the
// viewer within 53 degrees (tests/render/test_images.cpp, ColoursMapBackToTheirValues...).
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in float a_value;
uniform mat4 u_view;   // rigid: rotation + translation, so mat3(u_view) transforms normals
uniform mat4 u_proj;
uniform vec2 u_range;  // field value mapped to colour-map 0 and 1
uniform sampler2D u_colormap;  // N x 1 texture of the colour map (sRGB values)
uniform float u_colormap_size;
uniform int u_plain;           // 1: use u_plain_color instead of the colour map
uniform vec3 u_plain_color;
uniform bool u_ortho;
// The outline's smooth lines (render/silhouette.h): moved u_inset pixels towards the inside of
// the surface, along the screen direction of the normal, so that a one-pixel line covers the
// background pixels beside the edge as the surface would (box-filter coverage). 0 for the surface.
uniform float u_inset;
uniform vec2 u_viewport;  // pixels
out vec3 v_front;  // lit colour seen from the side the normal points to
out vec3 v_back;   // ... and from the other side

const vec3 key_dir = normalize(vec3(0.0, 0.55, 1.0));
const vec3 fill_dir = normalize(vec3(0.0, -0.7, 0.6));
const float ambient = 0.6, key = 0.38, fill = 0.1, spec = 0.04, shininess = 48.0;

vec3 lit(vec3 base, vec3 n, vec3 v) {
  float d = ambient + key * max(dot(n, key_dir), 0.0) + fill * max(dot(n, fill_dir), 0.0);
  float s = spec * pow(max(dot(n, normalize(key_dir + v)), 0.0), shininess);
  return min(base * d + vec3(s), vec3(1.0));
}

void main() {
  vec4 p = u_view * vec4(a_position, 1.0);
  vec3 n = normalize(mat3(u_view) * a_normal);
  vec3 base;
  if (u_plain == 1) {
    base = u_plain_color;
  } else {
    float t = clamp((a_value - u_range.x) / (u_range.y - u_range.x), 0.0, 1.0);
    float u = (0.5 + t * (u_colormap_size - 1.0)) / u_colormap_size;  // texel centres
    base = textureLod(u_colormap, vec2(u, 0.5), 0.0).rgb;
  }
  vec3 v = u_ortho ? vec3(0.0, 0.0, 1.0) : normalize(-p.xyz);
  v_front = lit(base, n, v);
  v_back = lit(base, -n, v);
  gl_Position = u_proj * p;
  vec2 d = n.xy;
  if (u_inset != 0.0 && dot(d, d) > 0.0)
    gl_Position.xy -= normalize(d) * (2.0 * u_inset / u_viewport) * gl_Position.w;
}

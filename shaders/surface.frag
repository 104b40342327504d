#version 330 core
// Blinn-Phong with two white directional lights fixed to the camera. Both lights lie in the
// camera's vertical plane (x_eye = 0): a left-right mirror-symmetric scene stays symmetric.
// White light and an equal-channel specular term leave the hue of the base colour unchanged.
in vec3 v_pos_eye;
in vec3 v_nrm_eye;
in float v_t;
uniform sampler2D u_colormap;  // N x 1 texture of the colour map (sRGB values)
uniform float u_colormap_size;
uniform int u_plain;           // 1: use u_plain_color instead of the colour map
uniform vec3 u_plain_color;
uniform bool u_ortho;
uniform float u_alpha;  // 1 for the surface; the outline's smooth lines (renderer.cpp) set their own
out vec4 frag_color;

const vec3 key_dir = normalize(vec3(0.0, 0.55, 1.0));
const vec3 fill_dir = normalize(vec3(0.0, -0.7, 0.6));
const float ambient = 0.28, key = 0.62, fill = 0.22, spec = 0.16, shininess = 48.0;

void main() {
  vec3 n = normalize(v_nrm_eye);
  if (!gl_FrontFacing) n = -n;
  vec3 v = u_ortho ? vec3(0.0, 0.0, 1.0) : normalize(-v_pos_eye);
  vec3 base;
  if (u_plain == 1) {
    base = u_plain_color;
  } else {
    float t = clamp(v_t, 0.0, 1.0);
    float u = (0.5 + t * (u_colormap_size - 1.0)) / u_colormap_size;  // texel centres
    base = texture(u_colormap, vec2(u, 0.5)).rgb;
  }
  float d = ambient + key * max(dot(n, key_dir), 0.0) + fill * max(dot(n, fill_dir), 0.0);
  float s = spec * pow(max(dot(n, normalize(key_dir + v)), 0.0), shininess);
  vec3 c = base * d + vec3(s);
  frag_color = vec4(min(c, vec3(1.0)), u_alpha);
}

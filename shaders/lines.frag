#version 330 core
uniform vec3 u_color;
uniform float u_alpha;  // < 1 with smooth (blended) lines: the same ink as a multisampled line
out vec4 frag_color;
void main() { frag_color = vec4(u_color, u_alpha); }

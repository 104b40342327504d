#version 330 core
// The colours lit per vertex by surface.vert, the side seen picked per fragment.
in vec3 v_front;
in vec3 v_back;
uniform float u_alpha;  // 1 for the surface; the outline's smooth lines (renderer.cpp) set their own
out vec4 frag_color;
void main() { frag_color = vec4(gl_FrontFacing ? v_front : v_back, u_alpha); }

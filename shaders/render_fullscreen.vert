// One triangle that covers the viewport (no vertex data): vertices 0, 1, 2 -> (-1,-1), (3,-1), (-1,3).
void main() {
  vec2 p = vec2((gl_VertexID & 1) * 4 - 1, (gl_VertexID >> 1) * 4 - 1);
  gl_Position = vec4(p, 1.0, 1.0);
}

// Buffer-texture self-test (tests/core/gl_compute_test.cpp): copies texels fetched through the views
// GpuBuffer::bindTexture makes (RGBA32F at unit 0, R32UI at unit 1) into storage buffers, so the test
// can compare them with what was uploaded.
layout(local_size_x = 64) in;
layout(binding = 0) uniform samplerBuffer floatTexels;
layout(binding = 1) uniform usamplerBuffer wordTexels;
layout(std430, binding = 0) writeonly buffer FloatsOut { vec4 floatsOut[]; };
layout(std430, binding = 1) writeonly buffer WordsOut { uint wordsOut[]; };
uniform uint uCount;

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= uCount) return;
  floatsOut[i] = texelFetch(floatTexels, int(i));
  wordsOut[i] = texelFetch(wordTexels, int(i)).x;
}

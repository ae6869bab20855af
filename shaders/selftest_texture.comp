// Buffer-texture self-test (tests/core/gl_compute_test.cpp): copies texels fetched through the views
// GpuBuffer::bindTexture makes (RGBA32F and R32UI) into storage buffers, so the test can compare them
// with what was uploaded.
layout(local_size_x = 64) in;
layout(binding = SPHFX_TEX_SELFTEST_FLOATS) uniform samplerBuffer floatTexels;
layout(binding = SPHFX_TEX_SELFTEST_WORDS) uniform usamplerBuffer wordTexels;
layout(std430, binding = SPHFX_SSBO_SELFTEST_FLOATS_OUT) writeonly buffer FloatsOut { vec4 floatsOut[]; };
layout(std430, binding = SPHFX_SSBO_SELFTEST_WORDS_OUT) writeonly buffer WordsOut { uint wordsOut[]; };
uniform uint uCount;

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= uCount) return;
  floatsOut[i] = texelFetch(floatTexels, int(i));
  wordsOut[i] = texelFetch(wordTexels, int(i)).x;
}

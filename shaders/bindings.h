/* Binding points shared by C++ and GLSL: the one declaration of every buffer binding.
 * C++ includes this file (sphfx/gpu/gpu_layout.h); every GLSL program gets it prepended
 * (sphfx/gpu/shader_program.h). Keep it preprocessor-only so that both languages accept it.
 * tests/core/shader_contract_test.cpp checks every linked program's bindings against these names. */
#ifndef SPHFX_BINDINGS_H
#define SPHFX_BINDINGS_H

/* Uniform blocks */
#define SPHFX_UBO_SELFTEST 0
#define SPHFX_UBO_SIM_PARAMS 1
#define SPHFX_UBO_RENDER_PARAMS 2

/* Shader storage blocks: self-test (sphfx info --selftest, tests) */
#define SPHFX_SSBO_SELFTEST_DATA 0
#define SPHFX_SSBO_SELFTEST_COUNTERS 1
/* Buffer-texture self-test (selftest_texture.comp): the views read, the storage blocks written */
#define SPHFX_TEX_SELFTEST_FLOATS 0
#define SPHFX_TEX_SELFTEST_WORDS 1
#define SPHFX_SSBO_SELFTEST_FLOATS_OUT 0
#define SPHFX_SSBO_SELFTEST_WORDS_OUT 1

/* Each stage declares its own binding points in its own file, included here so that C++ and GLSL both
 * see every binding through this one header. Binding numbers may overlap between stages (different
 * programs), never within one. */
#include "sim_bindings.h"
#include "render_bindings.h"

#endif

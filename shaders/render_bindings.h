/* Binding points of the render stage. Preprocessor-only; included by bindings.h.
 * The frame's uniform block uses SPHFX_UBO_RENDER_PARAMS (bindings.h). */
#ifndef SPHFX_RENDER_BINDINGS_H
#define SPHFX_RENDER_BINDINGS_H

/* Particles mode: one vec4 per particle (xyz position, w colour scalar), pulled by gl_VertexID. */
#define SPHFX_SSBO_RENDER_PARTICLES 2

/* Texture units of the water pass. */
#define SPHFX_TEX_RENDER_BACKGROUND 0
#define SPHFX_TEX_RENDER_OPAQUE_DEPTH 1
#define SPHFX_TEX_RENDER_BACK_DEPTH 2

#endif

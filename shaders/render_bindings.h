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

/* Point-sprite impostors: the depth buffer read by compute passes, the per-pixel nearest depth (r32ui
 * image), the max-depth tiles of the occlusion cull, the visible list and its indirect draw command. */
#define SPHFX_TEX_RENDER_SCENE_DEPTH 0
#define SPHFX_IMAGE_RENDER_NEAREST 0
#define SPHFX_IMAGE_RENDER_DEPTH_MAX 1
#define SPHFX_SSBO_RENDER_VISIBLE 3
#define SPHFX_SSBO_RENDER_DRAW 4
#define SPHFX_RENDER_CULL_TILE 4

/* Passes of render_points.frag (SPHFX_IMPOSTOR_PASS). */
#define SPHFX_IMPOSTOR_OCCLUDE 1
#define SPHFX_IMPOSTOR_NEAREST 2
#define SPHFX_IMPOSTOR_SHADE 3

#endif

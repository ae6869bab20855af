/* Binding points of the render stage. Preprocessor-only; included by bindings.h. */
#ifndef SPHFX_RENDER_BINDINGS_H
#define SPHFX_RENDER_BINDINGS_H
#endif

/* Binding points of the simulation stage (shader storage 0-15, uniform blocks 1 and 3-7).
 * Preprocessor-only; included by bindings.h. */
#ifndef SPHFX_SIM_BINDINGS_H
#define SPHFX_SIM_BINDINGS_H
#endif

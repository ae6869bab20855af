// Shared by every program (prepended after bindings.h and the scene's #defines).

const float SPHFX_PI = 3.14159265358979323846;

// Index of this invocation along x for 1D dispatches. A macro, not a function: common.glsl is also
// prepended to vertex and fragment shaders, where gl_GlobalInvocationID does not exist.
#define sphfxGlobalIndex() (gl_GlobalInvocationID.x)

// Linear index of a cell in a grid of `dims` cells (x fastest). Cells are clamped into the grid, so
// positions on or beyond the border land in the border cells.
uint sphfxCellIndex(ivec3 cell, ivec3 dims) {
  ivec3 c = clamp(cell, ivec3(0), dims - 1);
  return uint(c.x + dims.x * (c.y + dims.y * c.z));
}

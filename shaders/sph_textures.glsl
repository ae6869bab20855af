// Read-only views of the simulation buffers as buffer textures (units in sim_bindings.h), for the
// loops over neighbours and grid candidates: llvmpipe (Mesa 22) loads storage-buffer data at a
// per-invocation offset lane by lane, with a bounds check and a branch per component, while a texel
// fetch is one vector gather. Writes go through the storage blocks; a pass that writes a buffer is
// followed by GL_TEXTURE_FETCH_BARRIER_BIT (storageBarrier()). C++ binds the views with
// GpuBuffer::bindTexture.
layout(binding = SPHFX_TEX_SIM_POS) uniform samplerBuffer simPosTex;
layout(binding = SPHFX_TEX_SIM_VEL) uniform samplerBuffer simVelTex;
layout(binding = SPHFX_TEX_SIM_DENSITY) uniform samplerBuffer simDensityTex;
layout(binding = SPHFX_TEX_SIM_CELL_START) uniform usamplerBuffer simCellStartTex;
layout(binding = SPHFX_TEX_SIM_BOUNDARY_POS) uniform samplerBuffer simBoundaryPosTex;
layout(binding = SPHFX_TEX_SIM_BOUNDARY_VEL) uniform samplerBuffer simBoundaryVelTex;
layout(binding = SPHFX_TEX_SIM_BOUNDARY_CELL_START) uniform usamplerBuffer simBoundaryCellStartTex;

vec4 sphFetchPos(uint j) { return texelFetch(simPosTex, int(j)); }
vec4 sphFetchVel(uint j) { return texelFetch(simVelTex, int(j)); }
// x: density, y: pressure / density^2
vec2 sphFetchDensity(uint j) { return texelFetch(simDensityTex, int(j)).xy; }
uint sphFetchCellStart(uint c) { return texelFetch(simCellStartTex, int(c)).x; }
vec4 sphFetchBoundaryPos(uint b) { return texelFetch(simBoundaryPosTex, int(b)); }
vec4 sphFetchBoundaryVel(uint b) { return texelFetch(simBoundaryVelTex, int(b)); }
uint sphFetchBoundaryCellStart(uint c) { return texelFetch(simBoundaryCellStartTex, int(c)).x; }

#pragma once
/// @file gpu_layouts.h
/// @brief C++ mirrors of the render stage's GLSL blocks (shaders/render_params.glsl,
/// shaders/render_particles.vert, shaders/render_points.vert), described for the layout tests.

#include <vector>

#include "sphfx/gpu/gpu_layout.h"

namespace sphfx::render {

/// std140 mirror of the RenderParams uniform block: one per frame.
struct RenderParams {
  float viewProj[16];
  float view[16];
  float invViewProj[16];
  float eye[4];         ///< xyz camera position; w: 1 orthographic, 0 perspective
  float camRight[4];    ///< xyz; w: near plane
  float camUp[4];       ///< xyz; w: far plane
  float camForward[4];  ///< xyz; w: particle radius
  float light[4];       ///< xyz unit vector toward the key light; w: intensity
  float viewport[4];    ///< width, height, 1/width, 1/height
  float ramp[4];        ///< height min, height max, speed scale, mode (0 height, 1 speed)
  float domainMin[4];
  float domainMax[4];
  float projection[4];  ///< projection matrix entries [0], [5], [10], [14] (column-major)
};

/// std430 element of the RenderParticles storage block: xyz position, w colour scalar (speed).
struct RenderParticle {
  float position[3];
  float scalar;
};

/// The render stage's blocks, for checkGpuLayouts() (tests/core/gpu_layout_check.h). Does not throw.
std::vector<GpuBlockLayout> renderGpuLayouts();

}  // namespace sphfx::render

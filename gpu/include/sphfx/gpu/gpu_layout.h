#pragma once
/// @file gpu_layout.h
/// @brief C++ mirrors of GLSL blocks, with a description of each that tests compare with what the GL
/// linker reports (offsets, sizes, binding points). Binding numbers come from shaders/bindings.h, the
/// single declaration both languages read.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "bindings.h"

namespace sphfx {

/// One member of a block: its GLSL name, and offset/size on the C++ side.
struct GpuMember {
  std::string name;
  size_t offset;
  size_t size;
};

/// A uniform or shader storage block shared by C++ and GLSL.
struct GpuBlockLayout {
  std::string block;       ///< GLSL block name
  bool uniform;            ///< uniform block (std140) or shader storage block (std430)
  uint32_t binding;        ///< from bindings.h
  size_t size;             ///< sizeof the C++ struct
  std::string shaderFile;  ///< an embedded file that declares the block (the test compiles it)
  std::vector<GpuMember> members;
};

#define SPHFX_GPU_MEMBER(Struct, member, glslName)             \
  ::sphfx::GpuMember {                                         \
    glslName, offsetof(Struct, member), sizeof(Struct::member) \
  }

/// std140 mirror of the self-test uniform block (shaders/selftest_layout.glsl).
struct SelfTestParams {
  float scale;
  uint32_t count;
  float pad_[2];  // std140 aligns vec4 to 16 bytes
  float offset[4];
};

/// The core's shared blocks. Stage libraries publish theirs the same way.
std::vector<GpuBlockLayout> coreGpuLayouts();

}  // namespace sphfx

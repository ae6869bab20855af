#pragma once
// Checks C++ mirrors of GLSL blocks against what the GL linker reports: binding point, block size and
// every member's offset. Stage tests call checkGpuLayouts() with their own block lists.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "sphfx/gpu/gl.h"
#include "sphfx/gpu/gpu_layout.h"
#include "sphfx/gpu/shader_program.h"

namespace sphfx::test {

inline ShaderProgram buildLayoutProgram(const ShaderTable& stage, const std::string& files) {
  // "a.vert+b.frag" for graphics programs, one file for compute.
  const auto plus = files.find('+');
  if (plus == std::string::npos) return ShaderProgram::compute(stage, files);
  return ShaderProgram::graphics(stage, files.substr(0, plus), files.substr(plus + 1));
}

inline GLint resourceProperty(GLuint program, GLenum interface, GLuint index, GLenum property) {
  GLint value = -1;
  glGetProgramResourceiv(program, interface, index, 1, &property, 1, nullptr, &value);
  return value;
}

/// `stage`: the table of the library whose programs declare the blocks.
inline void checkGpuLayouts(const ShaderTable& stage, const std::vector<GpuBlockLayout>& layouts) {
  for (const GpuBlockLayout& layout : layouts) {
    SCOPED_TRACE(layout.block + " in " + layout.shaderFile);
    const ShaderProgram program = buildLayoutProgram(stage, layout.shaderFile);
    const GLenum blockInterface = layout.uniform ? GL_UNIFORM_BLOCK : GL_SHADER_STORAGE_BLOCK;
    const GLenum memberInterface = layout.uniform ? GL_UNIFORM : GL_BUFFER_VARIABLE;
    const GLuint block = glGetProgramResourceIndex(program.id(), blockInterface, layout.block.c_str());
    ASSERT_NE(block, GL_INVALID_INDEX) << "block not active in the program";
    EXPECT_EQ(resourceProperty(program.id(), blockInterface, block, GL_BUFFER_BINDING),
              GLint(layout.binding));
    if (layout.size != 0) {
      EXPECT_EQ(resourceProperty(program.id(), blockInterface, block, GL_BUFFER_DATA_SIZE),
                GLint(layout.size));
    }
    for (const GpuMember& m : layout.members) {
      const GLuint member = glGetProgramResourceIndex(program.id(), memberInterface, m.name.c_str());
      ASSERT_NE(member, GL_INVALID_INDEX) << m.name << " is not a member the GL reports";
      EXPECT_EQ(resourceProperty(program.id(), memberInterface, member, GL_OFFSET), GLint(m.offset))
          << m.name;
      EXPECT_EQ(resourceProperty(program.id(), memberInterface, member, GL_BLOCK_INDEX), GLint(block))
          << m.name;
    }
  }
}

}  // namespace sphfx::test

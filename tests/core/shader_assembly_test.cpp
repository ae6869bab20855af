// Program assembly order: #version, the scene's #defines, bindings.h, common.glsl, the stage file with
// its includes resolved once each.
#include <gtest/gtest.h>

#include "sphfx/core/error.h"
#include "sphfx/core/shader_program.h"
#include "sphfx/core/shader_sources.h"

using namespace sphfx;

TEST(ShaderAssembly, OrderAndDefines) {
  ShaderDefines d;
  d.set("HAS_COLLIDERS").set("PARTICLE_COUNT", 1000u).set("REST_DENSITY", 1000.0f).set("SCALE", 0.5f);
  const AssembledShader s = assembleShader("selftest.comp", d);
  ASSERT_EQ(s.text.rfind("#version 430 core\n", 0), 0u);
  const auto defines = s.text.find("#define HAS_COLLIDERS 1\n");
  const auto bindings = s.text.find("#define SPHFX_BINDINGS_H");
  const auto common = s.text.find("uint sphfxCellIndex");
  const auto layout = s.text.find("uniform SelfTestParams");
  const auto main = s.text.find("void main()");
  EXPECT_NE(s.text.find("#define PARTICLE_COUNT 1000u\n"), std::string::npos);
  EXPECT_NE(s.text.find("#define REST_DENSITY 1000.0\n"), std::string::npos);
  EXPECT_NE(s.text.find("#define SCALE 0.5\n"), std::string::npos);
  EXPECT_LT(defines, bindings);
  EXPECT_LT(bindings, common);
  EXPECT_LT(common, layout);
  EXPECT_LT(layout, main);
  EXPECT_EQ(s.files, (std::vector<std::string>{"bindings.h", "sim_bindings.h", "render_bindings.h",
                                               "common.glsl", "selftest.comp", "selftest_layout.glsl"}));
  EXPECT_EQ(s.text.find("#include"), std::string::npos);
}

TEST(ShaderAssembly, EveryShaderFileIsEmbedded) {
  std::vector<std::string> names;
  for (const auto& e : embeddedShaderTable()) names.emplace_back(e.name);
  EXPECT_NE(std::find(names.begin(), names.end(), "common.glsl"), names.end());
  EXPECT_NE(std::find(names.begin(), names.end(), "bindings.h"), names.end());
  EXPECT_THROW(shaderSource("missing.comp"), GLError);
}

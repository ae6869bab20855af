// Program assembly order: #version, the scene's #defines, bindings.h, common.glsl, the stage file with
// its includes resolved once each.
#include <gtest/gtest.h>

#include "sphfx/core/error.h"
#include "sphfx/gpu/shader_program.h"
#include "sphfx/gpu/shader_sources.h"

using namespace sphfx;

TEST(ShaderAssembly, OrderAndDefines) {
  ShaderDefines d;
  d.set("HAS_COLLIDERS").set("PARTICLE_COUNT", 1000u).set("REST_DENSITY", 1000.0f).set("SCALE", 0.5f);
  const AssembledShader s = assembleShader(gpuShaderTable(), "selftest.comp", d);
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

TEST(ShaderAssembly, TheGpuLayerEmbedsTheSharedIncludesOnly) {
  std::vector<std::string> names;
  for (const auto& e : gpuShaderTable()) names.emplace_back(e.name);
  for (const char* shared :
       {"bindings.h", "sim_bindings.h", "render_bindings.h", "common.glsl", "selftest.comp"})
    EXPECT_NE(std::find(names.begin(), names.end(), shared), names.end()) << shared;
  for (const auto& n : names) {
    EXPECT_NE(n.rfind("sim_", 0) == 0 && n != "sim_bindings.h", true) << n << " belongs to the sim stage";
    EXPECT_NE(n.rfind("render_", 0) == 0 && n != "render_bindings.h", true)
        << n << " belongs to the renderer";
  }
  EXPECT_THROW(shaderSource(gpuShaderTable(), "missing.comp"), GLError);
}

TEST(ShaderAssembly, AStageFileIsFoundInItsStageTableFirst) {
  const ShaderTable stage = {{"stage_main.comp", "#include \"stage_part.glsl\"\nvoid main() {}\n"},
                             {"stage_part.glsl", "// stage part\n"}};
  const AssembledShader s = assembleShader(stage, "stage_main.comp", {});
  EXPECT_EQ(s.files, (std::vector<std::string>{"bindings.h", "sim_bindings.h", "render_bindings.h",
                                               "common.glsl", "stage_main.comp", "stage_part.glsl"}));
  EXPECT_THROW(assembleShader(gpuShaderTable(), "stage_main.comp", {}), GLError);
}

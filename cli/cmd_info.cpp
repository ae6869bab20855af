#include <fmt/format.h>

#include <cstdio>

#include "commands.h"
#include "sphfx/core/error.h"
#include "sphfx/gpu/selftest.h"

namespace sphfx::cli {

namespace {

void printInfo(const GLContext& ctx) {
  const GLInfo& i = ctx.info();
  std::printf("backends tried:\n");
  for (const auto& a : ctx.attempts())
    std::printf("  %-16s %s%s%s\n", toString(a.backend).c_str(), a.succeeded ? "ok" : "failed",
                a.detail.empty() ? "" : ": ", a.detail.c_str());
  std::printf("backend:          %s\n", toString(ctx.backend()).c_str());
  std::printf("vendor:           %s\n", i.vendor.c_str());
  std::printf("renderer:         %s%s\n", i.renderer.c_str(), i.softwareRenderer() ? " (software)" : "");
  std::printf("version:          %s (GL %d.%d core)\n", i.version.c_str(), i.major, i.minor);
  std::printf("GLSL:             %s\n", i.glslVersion.c_str());
  std::printf("compute:          %d invocations/group, group size %d x %d x %d, group count %d x %d x %d\n",
              i.maxComputeWorkGroupInvocations, i.maxComputeWorkGroupSize[0], i.maxComputeWorkGroupSize[1],
              i.maxComputeWorkGroupSize[2], i.maxComputeWorkGroupCount[0], i.maxComputeWorkGroupCount[1],
              i.maxComputeWorkGroupCount[2]);
  std::printf("shared memory:    %d bytes\n", i.maxComputeSharedMemory);
  std::printf("storage buffers:  %d bindings, %lld MiB max block\n", i.maxShaderStorageBindings,
              static_cast<long long>(static_cast<unsigned>(i.maxShaderStorageBlockSize)) >> 20);
  std::printf("textures:         %d px max, %d MSAA samples max\n", i.maxTextureSize, i.maxSamples);
}

}  // namespace

void addInfoCommand(CLI::App& app) {
  CLI::App* cmd = app.add_subcommand("info", "Print the OpenGL backends tried and the one chosen");
  auto gl = addGLOptions(cmd);
  auto selftest = std::make_shared<bool>(false);
  cmd->add_flag("--selftest", *selftest,
                "Also run a compute self-test (SSBOs, atomics, includes) and compare with the CPU");
  cmd->callback([gl, selftest] {
    auto ctx = GLContext::create(*gl);
    printInfo(*ctx);
    if (*selftest) {
      const std::string failure = verifyComputeSelfTest();
      if (!failure.empty()) throw GLError("compute self-test failed: " + failure);
      std::printf("compute self-test: passed\n");
    }
  });
}

}  // namespace sphfx::cli

// Every registered pressure solver has an implementation, and it is the one its name says.
#include <gtest/gtest.h>

#include "dispatch_gate.h"
#include "gpu_types.h"
#include "sim_test_util.h"
#include "simulator.h"
#include "sphfx/core/methods.h"

using namespace sphfx;

TEST(SolverRegistry, EveryRegisteredSolverIsBuilt) {
  auto ctx = test::makeContext();
  for (const auto& entry : pressureSolverRegistry()) {
    SCOPED_TRACE(entry.name);
    Scene scene = test::sceneFromJson(R"({"fluid": {"spacing": 0.05, "blocks": [{"min": [0,0,0],
                                          "max": [0.3,0.3,0.3]}]}})");
    scene.solver.method = entry.id;
    sim::DispatchGate gate(uint32_t(countInitialParticles(scene)));
    const ShaderDefines defines = sim::simShaderDefines(scene);
    const sim::BoundaryAkinci2012 boundary(scene, {}, gate, sim::GridSpec::forScene(scene), defines);
    const auto solver = sim::makePressureSolver(scene, gate, defines, boundary);
    ASSERT_NE(solver, nullptr);
    EXPECT_EQ(entry.name, solver->name());
  }
}

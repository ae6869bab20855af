// The shader contract: every program the project builds (every compute shader and every vertex +
// fragment pair the renderer links, with the #define variants of the shipped and test scenes) takes
// every binding from bindings.h. For each linked program the test asks the GL for its active storage
// blocks, uniform blocks, samplers and images and checks that no two of one kind share a binding, that
// each one's binding is the SPHFX_* constant the tables below name for it, and that every block with a
// C++ mirror (gpu_layout.h and the stages' layouts, DfsphControl) has the mirror's offsets, array strides
// and size. A shader file that no program below builds fails the test, as does a block or a sampler
// missing from the tables.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <regex>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "bindings.h"
#include "dfsph_solver.h"
#include "gpu_layout_check.h"
#include "gpu_layouts.h"
#include "gpu_types.h"
#include "render_shaders.h"
#include "sim_shaders.h"
#include "sphfx/core/scene.h"
#include "sphfx/gpu/gl.h"
#include "sphfx/gpu/gl_context.h"
#include "sphfx/gpu/gpu_layout.h"
#include "sphfx/gpu/shader_program.h"
#include "sphfx/gpu/shader_sources.h"

namespace sphfx {
namespace {

// One binding name of bindings.h: its text, for the message, and its value.
struct Constant {
  const char* name;
  int value;
};
#define SPHFX_CONSTANT(c) \
  Constant {              \
#c, c                 \
  }

// Active storage and uniform blocks, by GLSL block name. A block name means one binding in every program.
const std::map<std::string, Constant>& blockBindings() {
  static const std::map<std::string, Constant> m = {
      // core
      {"SelfTestParams", SPHFX_CONSTANT(SPHFX_UBO_SELFTEST)},
      {"SelfTestData", SPHFX_CONSTANT(SPHFX_SSBO_SELFTEST_DATA)},
      {"SelfTestCounters", SPHFX_CONSTANT(SPHFX_SSBO_SELFTEST_COUNTERS)},
      {"FloatsOut", SPHFX_CONSTANT(SPHFX_SSBO_SELFTEST_FLOATS_OUT)},
      {"WordsOut", SPHFX_CONSTANT(SPHFX_SSBO_SELFTEST_WORDS_OUT)},
      // simulation
      {"SimParams", SPHFX_CONSTANT(SPHFX_UBO_SIM_PARAMS)},
      {"SimUnsortedPos", SPHFX_CONSTANT(SPHFX_SSBO_SIM_UNSORTED_POS)},
      {"SimUnsortedVel", SPHFX_CONSTANT(SPHFX_SSBO_SIM_UNSORTED_VEL)},
      {"SimOutPos", SPHFX_CONSTANT(SPHFX_SSBO_SIM_UNSORTED_POS)},
      {"SimOutVel", SPHFX_CONSTANT(SPHFX_SSBO_SIM_UNSORTED_VEL)},
      {"SimPos", SPHFX_CONSTANT(SPHFX_SSBO_SIM_POS)},
      {"SimVel", SPHFX_CONSTANT(SPHFX_SSBO_SIM_VEL)},
      {"SimDensity", SPHFX_CONSTANT(SPHFX_SSBO_SIM_DENSITY)},
      {"SimAccel", SPHFX_CONSTANT(SPHFX_SSBO_SIM_ACCEL)},
      {"SimStateBlock", SPHFX_CONSTANT(SPHFX_SSBO_SIM_STATE)},
      {"SimCellStart", SPHFX_CONSTANT(SPHFX_SSBO_SIM_CELL_START)},
      {"SimBoundaryPos", SPHFX_CONSTANT(SPHFX_SSBO_SIM_BOUNDARY_POS)},
      {"SimBoundaryVel", SPHFX_CONSTANT(SPHFX_SSBO_SIM_BOUNDARY_VEL)},
      {"SimBoundaryStart", SPHFX_CONSTANT(SPHFX_SSBO_SIM_BOUNDARY_CELL_START)},
      {"SimColliders", SPHFX_CONSTANT(SPHFX_SSBO_SIM_COLLIDERS)},
      {"SimColliderKeys", SPHFX_CONSTANT(SPHFX_SSBO_SIM_COLLIDER_KEYS)},
      {"SimColliderField", SPHFX_CONSTANT(SPHFX_SSBO_SIM_COLLIDER_FIELD)},
      {"SimBoundaryRest", SPHFX_CONSTANT(SPHFX_SSBO_SIM_BOUNDARY_REST)},
      {"SimBoundaryBody", SPHFX_CONSTANT(SPHFX_SSBO_SIM_BOUNDARY_BODY)},
      {"SimDispatch", SPHFX_CONSTANT(SPHFX_SSBO_SIM_DISPATCH)},
      {"SimNeighbors", SPHFX_CONSTANT(SPHFX_SSBO_SIM_NEIGHBORS)},
      {"SimBoundaryPressure", SPHFX_CONSTANT(SPHFX_SSBO_SIM_BOUNDARY_PRESSURE)},
      {"SimBoundaryWallShare", SPHFX_CONSTANT(SPHFX_SSBO_SIM_BOUNDARY_WALL_SHARE)},
      {"DfsphParticle", SPHFX_CONSTANT(SPHFX_SSBO_SIM_DFSPH_PARTICLE)},
      {"DfsphIncrement", SPHFX_CONSTANT(SPHFX_SSBO_SIM_DFSPH_INCREMENT)},
      {"DfsphWet", SPHFX_CONSTANT(SPHFX_SSBO_SIM_DFSPH_WET)},
      {"DfsphWarm", SPHFX_CONSTANT(SPHFX_SSBO_SIM_DFSPH_WARM)},
      {"DfsphPressureImpulse", SPHFX_CONSTANT(SPHFX_SSBO_SIM_DFSPH_PRESSURE_IMPULSE)},
      {"DfsphPartial", SPHFX_CONSTANT(SPHFX_SSBO_SIM_DFSPH_PARTIAL)},
      {"DfsphControl", SPHFX_CONSTANT(SPHFX_SSBO_SIM_DFSPH_CONTROL)},
      {"DfsphNeighbors", SPHFX_CONSTANT(SPHFX_SSBO_SIM_DFSPH_NEIGHBORS)},
      {"DfsphBoundary", SPHFX_CONSTANT(SPHFX_SSBO_SIM_DFSPH_BOUNDARY)},
      {"DfsphCount", SPHFX_CONSTANT(SPHFX_SSBO_SIM_DFSPH_COUNT)},
      {"GridSrcPos", SPHFX_CONSTANT(SPHFX_SSBO_SIM_GRID_SRC_POS)},
      {"GridSrcVel", SPHFX_CONSTANT(SPHFX_SSBO_SIM_GRID_SRC_VEL)},
      {"GridDstPos", SPHFX_CONSTANT(SPHFX_SSBO_SIM_GRID_DST_POS)},
      {"GridDstVel", SPHFX_CONSTANT(SPHFX_SSBO_SIM_GRID_DST_VEL)},
      {"GridCellCount", SPHFX_CONSTANT(SPHFX_SSBO_SIM_CELL_START)},
      {"GridCellStart", SPHFX_CONSTANT(SPHFX_SSBO_SIM_CELL_START)},
      {"GridCellRank", SPHFX_CONSTANT(SPHFX_SSBO_SIM_GRID_CELL_RANK)},
      {"GridSorted", SPHFX_CONSTANT(SPHFX_SSBO_SIM_GRID_SORTED)},
      {"GridRowStart", SPHFX_CONSTANT(SPHFX_SSBO_SIM_GRID_ROW_START)},
      {"GridNeighbors", SPHFX_CONSTANT(SPHFX_SSBO_SIM_GRID_NEIGHBORS)},
      {"ScanData", SPHFX_CONSTANT(SPHFX_SSBO_SIM_SCAN_DATA)},
      {"ScanSums", SPHFX_CONSTANT(SPHFX_SSBO_SIM_SCAN_SUMS)},
      {"SimDynamic", SPHFX_CONSTANT(SPHFX_SSBO_SIM_DYNAMIC)},
      {"SimEmitters", SPHFX_CONSTANT(SPHFX_SSBO_SIM_EMITTERS)},
      {"SimEmitterPoints", SPHFX_CONSTANT(SPHFX_SSBO_SIM_EMITTER_POINTS)},
      {"SimKillBoxes", SPHFX_CONSTANT(SPHFX_SSBO_SIM_KILL_BOXES)},
      // render
      {"RenderParams", SPHFX_CONSTANT(SPHFX_UBO_RENDER_PARAMS)},
      {"RenderParticles", SPHFX_CONSTANT(SPHFX_SSBO_RENDER_PARTICLES)},
      {"RenderVisible", SPHFX_CONSTANT(SPHFX_SSBO_RENDER_VISIBLE)},
      {"RenderDraw", SPHFX_CONSTANT(SPHFX_SSBO_RENDER_DRAW)},
  };
  return m;
}

// Active sampler and image uniforms, by name: their texture or image unit.
const std::map<std::string, Constant>& unitBindings() {
  static const std::map<std::string, Constant> m = {
      {"floatTexels", SPHFX_CONSTANT(SPHFX_TEX_SELFTEST_FLOATS)},
      {"wordTexels", SPHFX_CONSTANT(SPHFX_TEX_SELFTEST_WORDS)},
      {"simPosTex", SPHFX_CONSTANT(SPHFX_TEX_SIM_POS)},
      {"simVelTex", SPHFX_CONSTANT(SPHFX_TEX_SIM_VEL)},
      {"simDensityTex", SPHFX_CONSTANT(SPHFX_TEX_SIM_DENSITY)},
      {"simCellStartTex", SPHFX_CONSTANT(SPHFX_TEX_SIM_CELL_START)},
      {"simBoundaryPosTex", SPHFX_CONSTANT(SPHFX_TEX_SIM_BOUNDARY_POS)},
      {"simBoundaryVelTex", SPHFX_CONSTANT(SPHFX_TEX_SIM_BOUNDARY_VEL)},
      {"simBoundaryCellStartTex", SPHFX_CONSTANT(SPHFX_TEX_SIM_BOUNDARY_CELL_START)},
      {"dfNbrTex", SPHFX_CONSTANT(SPHFX_TEX_SIM_DFSPH_NEIGHBORS)},
      {"dfIncrementTex", SPHFX_CONSTANT(SPHFX_TEX_SIM_DFSPH_INCREMENT)},
      {"dfParticleTex", SPHFX_CONSTANT(SPHFX_TEX_SIM_DFSPH_PARTICLE)},
      {"dfCountTex", SPHFX_CONSTANT(SPHFX_TEX_SIM_DFSPH_COUNT)},
      {"dfBoundaryTex", SPHFX_CONSTANT(SPHFX_TEX_SIM_DFSPH_BOUNDARY)},
      {"uBackground", SPHFX_CONSTANT(SPHFX_TEX_RENDER_BACKGROUND)},
      {"uOpaqueDepth", SPHFX_CONSTANT(SPHFX_TEX_RENDER_OPAQUE_DEPTH)},
      {"uBackDepth", SPHFX_CONSTANT(SPHFX_TEX_RENDER_BACK_DEPTH)},
      {"sceneDepth", SPHFX_CONSTANT(SPHFX_TEX_RENDER_SCENE_DEPTH)},
      {"nearestDepth", SPHFX_CONSTANT(SPHFX_IMAGE_RENDER_NEAREST)},
      {"depthMax", SPHFX_CONSTANT(SPHFX_IMAGE_RENDER_DEPTH_MAX)},
  };
  return m;
}

// The C++ mirrors, by block name: the stages' published layouts, and DfsphControl (dfsph_solver.h).
struct Mirror {
  GpuBlockLayout layout;
  size_t elementStride;  ///< of a runtime-sized array of structs (members "a[0].x"), else 0
};

std::map<std::string, Mirror> mirrors() {
  std::map<std::string, Mirror> m;
  const auto add = [&](const std::vector<GpuBlockLayout>& layouts) {
    for (const GpuBlockLayout& l : layouts) m.emplace(l.block, Mirror{l, 0});
  };
  add(coreGpuLayouts());
  add(sim::simGpuLayouts());
  add(render::renderGpuLayouts());
  m.at("SimColliders").elementStride = sizeof(sim::ColliderGpu);
  using C = sim::DfsphControl;
  GpuBlockLayout control{"DfsphControl", false, SPHFX_SSBO_SIM_DFSPH_CONTROL, sizeof(C), "", {}};
  control.members = {SPHFX_GPU_MEMBER(C, iteration, "dfIteration"),
                     SPHFX_GPU_MEMBER(C, open, "dfOpen"),
                     SPHFX_GPU_MEMBER(C, solves, "dfSolves[0]"),
                     SPHFX_GPU_MEMBER(C, iterSum, "dfIterSum[0]"),
                     SPHFX_GPU_MEMBER(C, iterMax, "dfIterMax[0]"),
                     SPHFX_GPU_MEMBER(C, errorSum, "dfErrorSum[0]"),
                     SPHFX_GPU_MEMBER(C, errorMax, "dfErrorMax[0]"),
                     SPHFX_GPU_MEMBER(C, lastError, "dfLastError"),
                     SPHFX_GPU_MEMBER(C, unconverged, "dfUnconverged[0]"),
                     SPHFX_GPU_MEMBER(C, args, "dfArgs[0]"),
                     SPHFX_GPU_MEMBER(C, pad, "dfPad[0]")};
  m.emplace("DfsphControl", Mirror{control, 0});
  return m;
}

// One program as the project builds it: "x.comp" or "a.vert+b.frag", with its defines.
struct ProgramSpec {
  std::string files;
  ShaderDefines defines;
  std::string variant;  ///< where the defines come from, for messages
};

// workgroupReduce: the hardware GPUs' reductions (SIM_WORKGROUP_REDUCE, sim::workgroupReduce()).
void addSimPrograms(const Scene& scene, const std::string& variant, std::vector<ProgramSpec>& out,
                    bool workgroupReduce = false) {
  ShaderDefines d = sim::simShaderDefines(scene);
  if (workgroupReduce) d.set("SIM_WORKGROUP_REDUCE");
  const auto add = [&](const std::string& file, const ShaderDefines& defines) {
    out.push_back({file, defines, variant});
  };
  // neighbor_grid.cpp (fluid and boundary grids share the scene's split), parallel_scan.cpp
  ShaderDefines split;
  if (sim::gridSplitX(scene) > 1) split.set("SIM_GRID_SPLIT_X", sim::gridSplitX(scene));
  add("sim_grid_cells.comp", split);
  add("sim_grid_scatter.comp", {});
  if (scene.changesParticleCount()) {  // the fluid grid with a live count; emitters (simulator.cpp)
    ShaderDefines live = split;
    live.set("SIM_DYNAMIC_COUNT");
    add("sim_grid_cells.comp", live);
    add("sim_grid_scatter.comp", ShaderDefines().set("SIM_DYNAMIC_COUNT"));
    add("sim_grid_live.comp", {});
  }
  if (!scene.emitters.empty()) {
    add("sim_emit.comp", d);
    add("sim_emit_commit.comp", d);
  }
  add("sim_grid_sort.comp", split);
  add("sim_scan_blocks.comp", {});
  add("sim_scan_add.comp", {});
  // simulator.cpp, symplectic_euler.cpp, boundary_akinci2012.cpp; sim_grid_neighbors.comp: diagnostics
  for (const char* file : {"sim_timestep.comp", "sim_integrate.comp", "sim_health.comp",
                           "sim_boundary_update.comp", "sim_grid_neighbors.comp"})
    add(file, d);
  if (scene.solver.method == Solver::WCSPH) {  // wcsph_solver.cpp
    ShaderDefines masks = d;
    masks.set("SIM_NEIGHBOR_MASKS");
    add("sim_density.comp", masks);
    add("sim_boundary_pressure.comp", d);
    if (scene.colliders.empty())
      add("sim_boundary_pressure.comp", ShaderDefines(d).set("BOUNDARY_WALL_SHARE"));
    add("sim_force.comp", masks);
    return;
  }
  // dfsph_solver.cpp: the factor and non-pressure passes, and the four programs of each solve (makeSolve);
  // with constraint walls the samples' passes
  const ShaderDefines w = sim::DFSPHSolver::wallDefines(scene, d).set(
      "DFSPH_RESIDUAL_SLOTS", sim::DFSPHSolver::residualSlots(d, 1000));
  add("sim_dfsph_factor.comp", sim::DFSPHSolver::factorDefines(scene, w));
  add("sim_dfsph_nonpressure.comp", sim::DFSPHSolver::nonPressureDefines(scene.solver.dfsph, w));
  if (sim::DFSPHSolver::cachesMeanPressure(scene))
    add("sim_dfsph_pressure_mean.comp", sim::DFSPHSolver::factorDefines(scene, w));
  if (scene.solver.dfsph.walls == DfsphWalls::Constraints) {
    add("sim_dfsph_boundary_factor.comp", sim::DFSPHSolver::factorDefines(scene, w));
    add("sim_dfsph_boundary_factor.comp",
        sim::DFSPHSolver::factorDefines(scene, w).set("DFSPH_BOUNDARY_REST_SHARE"));
    const ShaderDefines samples = sim::DFSPHSolver::sampleSolveDefines(scene, w);
    add("sim_dfsph_boundary_source.comp", samples);
    add("sim_dfsph_boundary_source.comp", ShaderDefines(samples).set("DFSPH_BOUNDARY_APPLY"));
  }
  for (const bool divergence : {false, true}) {
    const ShaderDefines s =
        sim::DFSPHSolver::solveDefines(scene.solver.dfsph, scene.solver.kernelSupport, w, divergence, 1u, 0u);
    for (const char* file :
         {"sim_dfsph_begin.comp", "sim_dfsph_source.comp", "sim_dfsph_reduce.comp", "sim_dfsph_apply.comp"})
      add(file, s);
  }
}

// Every program: the scenes' simulation variants, the renderer's (renderer.cpp) and the self-tests'.
std::vector<ProgramSpec> allPrograms() {
  std::vector<ProgramSpec> programs;
  const std::filesystem::path root = SPHFX_SOURCE_DIR;
  std::vector<std::filesystem::path> scenes;
  for (const auto& dir : {root / "scenes", root / "tests" / "scenes" / "good"})
    for (const auto& entry : std::filesystem::directory_iterator(dir))
      if (entry.path().extension() == ".json") scenes.push_back(entry.path());
  std::sort(scenes.begin(), scenes.end());
  for (const auto& path : scenes)
    addSimPrograms(loadScene(path.string()), path.filename().string(), programs);
  // Periodic boundaries (WCSPH only), in the tests' scenes: the seam's walk.
  const std::string dam = (root / "scenes" / "dam_break.json").string();
  addSimPrograms(loadScene(dam, {"domain.periodic=[\"x\", \"z\"]"}), "dam_break periodic x z", programs);
  addSimPrograms(loadScene(dam, {"domain.periodic=[\"z\"]"}), "dam_break periodic z", programs);
  addSimPrograms(loadScene(dam, {"solver.wcsph.kernel=muller2003"}), "dam_break muller2003 kernel", programs);
  addSimPrograms(loadScene(dam, {"solver.method=dfsph", "solver.dfsph.walls=constraints"}),
                 "dam_break dfsph constraint walls", programs);
  addSimPrograms(loadScene(dam), "dam_break workgroup reduce", programs, true);
  addSimPrograms(loadScene(dam, {"solver.method=dfsph"}), "dam_break dfsph workgroup reduce", programs, true);
  addSimPrograms(loadScene((root / "scenes" / "hydrostatic.json").string(), {"solver.method=dfsph"}),
                 "hydrostatic dfsph (pressure cached)", programs);

  const auto add = [&](const std::string& files, const ShaderDefines& defines = {}) {
    programs.push_back({files, defines, "renderer"});
  };
  add("render_fullscreen.vert+render_sky.frag");
  add("render_mesh.vert+render_solid.frag");
  add("render_mesh.vert+render_depth.frag");
  add("render_mesh.vert+render_water.frag");
  add("render_particles.vert+render_particles.frag");
  for (const int pass : {SPHFX_IMPOSTOR_OCCLUDE, SPHFX_IMPOSTOR_NEAREST, SPHFX_IMPOSTOR_SHADE})
    add("render_points.vert+render_points.frag", ShaderDefines().set("SPHFX_IMPOSTOR_PASS", pass));
  add("render_nearest_init.comp");
  add("render_depth_max.comp");
  add("render_points_cull.comp");
  programs.push_back({"selftest.comp", {}, "selftest"});
  programs.push_back({"selftest_texture.comp", {}, "selftest"});

  // Programs with the same assembled text are the same program: check each once.
  std::set<std::string> seen;
  std::vector<ProgramSpec> unique;
  for (ProgramSpec& p : programs)
    if (seen.insert(p.files + "\n" + p.defines.text()).second) unique.push_back(std::move(p));
  return unique;
}

/// The library that embeds a stage file: sim (sim_, sph_), render (render_), else the GPU layer.
const ShaderTable& tableOf(const std::string& file) {
  if (file.rfind("sim_", 0) == 0 || file.rfind("sph_", 0) == 0) return simShaderTable();
  if (file.rfind("render_", 0) == 0) return renderShaderTable();
  return gpuShaderTable();
}

/// Every embedded file of every library.
std::vector<EmbeddedShader> allEmbedded() {
  std::vector<EmbeddedShader> all;
  for (const ShaderTable* t : {&gpuShaderTable(), &simShaderTable(), &renderShaderTable()})
    all.insert(all.end(), t->begin(), t->end());
  return all;
}

ShaderProgram build(const ProgramSpec& p) {
  const auto plus = p.files.find('+');
  const ShaderTable& stage = tableOf(p.files);
  if (plus == std::string::npos) return ShaderProgram::compute(stage, p.files, p.defines);
  return ShaderProgram::graphics(stage, p.files.substr(0, plus), p.files.substr(plus + 1), p.defines);
}

std::string resourceName(GLuint program, GLenum interface, GLuint index) {
  GLint length = 0;
  const GLenum property = GL_NAME_LENGTH;
  glGetProgramResourceiv(program, interface, index, 1, &property, 1, nullptr, &length);
  std::string name(size_t(std::max(length, 1)), '\0');
  glGetProgramResourceName(program, interface, index, GLsizei(name.size()), nullptr, name.data());
  name.resize(name.find('\0') == std::string::npos ? name.size() : name.find('\0'));
  return name;
}

GLint activeResources(GLuint program, GLenum interface) {
  GLint count = 0;
  glGetProgramInterfaceiv(program, interface, GL_ACTIVE_RESOURCES, &count);
  return count;
}

bool startsWith(std::string_view s, std::string_view prefix) {
  return s.substr(0, prefix.size()) == prefix;
}

// Checks one block against its C++ mirror: data size, and each member's offset and array stride.
void checkMirror(GLuint program, GLenum blockInterface, GLuint block, const Mirror& mirror) {
  const GpuBlockLayout& l = mirror.layout;
  const GLenum memberInterface = l.uniform ? GL_UNIFORM : GL_BUFFER_VARIABLE;
  EXPECT_EQ(blockInterface == GL_UNIFORM_BLOCK, l.uniform) << l.block << ": uniform or storage block";
  EXPECT_EQ(test::resourceProperty(program, blockInterface, block, GL_BUFFER_BINDING), GLint(l.binding))
      << l.block << ": the C++ layout's binding";
  if (l.size != 0) {
    EXPECT_EQ(test::resourceProperty(program, blockInterface, block, GL_BUFFER_DATA_SIZE), GLint(l.size))
        << l.block << ": buffer data size against the C++ size";
  }
  for (const GpuMember& m : l.members) {
    const GLuint member = glGetProgramResourceIndex(program, memberInterface, m.name.c_str());
    if (member == GL_INVALID_INDEX) {
      ADD_FAILURE() << l.block << ": member " << m.name << " is not reported by the GL";
      continue;
    }
    EXPECT_EQ(test::resourceProperty(program, memberInterface, member, GL_BLOCK_INDEX), GLint(block))
        << m.name;
    EXPECT_EQ(test::resourceProperty(program, memberInterface, member, GL_OFFSET), GLint(m.offset))
        << l.block << ": offset of " << m.name;
    // An array member: its stride times its length (one element for a runtime-sized array) is the C++
    // member's size.
    const GLint stride = test::resourceProperty(program, memberInterface, member, GL_ARRAY_STRIDE);
    const GLint length = test::resourceProperty(program, memberInterface, member, GL_ARRAY_SIZE);
    if (stride > 0) {
      EXPECT_EQ(size_t(stride) * size_t(std::max(length, 1)), m.size) << l.block << ": stride of " << m.name;
    }
    if (m.name.find("[0].") != std::string::npos) {
      ASSERT_FALSE(l.uniform);
      EXPECT_EQ(test::resourceProperty(program, memberInterface, member, GL_TOP_LEVEL_ARRAY_STRIDE),
                GLint(mirror.elementStride))
          << l.block << ": element stride of the array holding " << m.name;
    }
  }
}

bool isImage(GLenum type) {
  switch (type) {
    case GL_IMAGE_2D:
    case GL_INT_IMAGE_2D:
    case GL_UNSIGNED_INT_IMAGE_2D:
    case GL_IMAGE_BUFFER:
    case GL_IMAGE_3D:
      return true;
    default:
      return false;
  }
}

bool isSampler(GLenum type) {
  switch (type) {
    case GL_SAMPLER_2D:
    case GL_SAMPLER_3D:
    case GL_SAMPLER_BUFFER:
    case GL_INT_SAMPLER_BUFFER:
    case GL_UNSIGNED_INT_SAMPLER_BUFFER:
    case GL_SAMPLER_2D_SHADOW:
    case GL_SAMPLER_2D_MULTISAMPLE:
    case GL_UNSIGNED_INT_SAMPLER_2D:
      return true;
    default:
      return false;
  }
}

// Checks one linked program; adds the blocks it checked against a mirror to `mirrored`.
size_t checkProgram(GLuint program, const std::map<std::string, Mirror>& mirrorTable,
                    std::set<std::string>& mirrored) {
  size_t checked = 0;
  for (const GLenum interface : {GL_SHADER_STORAGE_BLOCK, GL_UNIFORM_BLOCK}) {
    const char* prefix = interface == GL_UNIFORM_BLOCK ? "SPHFX_UBO_" : "SPHFX_SSBO_";
    std::map<GLint, std::string> byBinding;
    for (GLint b = 0; b < activeResources(program, interface); ++b) {
      const std::string name = resourceName(program, interface, GLuint(b));
      ++checked;
      const GLint binding = test::resourceProperty(program, interface, GLuint(b), GL_BUFFER_BINDING);
      const auto [other, fresh] = byBinding.emplace(binding, name);
      EXPECT_TRUE(fresh) << "blocks " << other->second << " and " << name << " share binding " << binding;
      const auto constant = blockBindings().find(name);
      if (constant == blockBindings().end()) {
        ADD_FAILURE() << "block " << name << " (binding " << binding
                      << ") has no SPHFX_* constant in this test's blockBindings()";
        continue;
      }
      EXPECT_TRUE(startsWith(constant->second.name, prefix)) << name << ": " << constant->second.name;
      EXPECT_EQ(binding, constant->second.value)
          << "block " << name << " is not at " << constant->second.name;
      if (const auto mirror = mirrorTable.find(name); mirror != mirrorTable.end()) {
        checkMirror(program, interface, GLuint(b), mirror->second);
        mirrored.insert(name);
      }
    }
  }
  // Samplers and images: units of one kind must differ, and be the named constant.
  std::map<GLint, std::string> samplerUnits, imageUnits;
  for (GLint u = 0; u < activeResources(program, GL_UNIFORM); ++u) {
    const GLenum type = GLenum(test::resourceProperty(program, GL_UNIFORM, GLuint(u), GL_TYPE));
    if (!isSampler(type) && !isImage(type)) continue;
    const std::string name = resourceName(program, GL_UNIFORM, GLuint(u));
    ++checked;
    const GLint location = test::resourceProperty(program, GL_UNIFORM, GLuint(u), GL_LOCATION);
    GLint unit = -1;
    glGetUniformiv(program, location, &unit);
    auto& units = isImage(type) ? imageUnits : samplerUnits;
    const auto [other, fresh] = units.emplace(unit, name);
    EXPECT_TRUE(fresh) << other->second << " and " << name << " share unit " << unit;
    const auto constant = unitBindings().find(name);
    if (constant == unitBindings().end()) {
      ADD_FAILURE() << "sampler or image " << name << " (unit " << unit
                    << ") has no SPHFX_* constant in this test's unitBindings()";
      continue;
    }
    EXPECT_TRUE(startsWith(constant->second.name, isImage(type) ? "SPHFX_IMAGE_" : "SPHFX_TEX_"))
        << name << ": " << constant->second.name;
    EXPECT_EQ(unit, constant->second.value) << name << " is not at " << constant->second.name;
  }
  return checked;
}

std::unique_ptr<GLContext> makeContext() {
  const char* name = std::getenv("SPHFX_GL");
  return GLContext::create({parseGLBackend(name ? name : "auto"), false});
}

}  // namespace

// No GLSL layout names a binding by number: every one is a constant of bindings.h.
TEST(ShaderContract, NoNumberedBindingsInGlsl) {
  const std::regex numbered(R"(binding\s*=\s*[0-9])");
  for (const EmbeddedShader& s : allEmbedded()) {
    const std::string source(s.source);
    EXPECT_FALSE(std::regex_search(source, numbered)) << s.name << " has a binding given as a number";
  }
}

TEST(ShaderContract, EveryProgramTakesItsBindingsFromBindingsH) {
  auto ctx = makeContext();
  const std::vector<ProgramSpec> programs = allPrograms();
  const std::map<std::string, Mirror> mirrorTable = mirrors();
  std::set<std::string> built, mirrored;
  size_t checks = 0;
  for (const ProgramSpec& p : programs) {
    SCOPED_TRACE(p.files + " (" + p.variant + ")");
    const auto plus = p.files.find('+');
    built.insert(p.files.substr(0, plus));
    if (plus != std::string::npos) built.insert(p.files.substr(plus + 1));
    const ShaderProgram program = build(p);
    checks += checkProgram(program.id(), mirrorTable, mirrored);
  }
  std::printf("%zu programs, %zu blocks, samplers and images checked\n", programs.size(), checks);
  EXPECT_GT(checks, programs.size());
  // Every stage file is some program's, so a new shader that this test does not build fails it.
  for (const EmbeddedShader& s : allEmbedded()) {
    const std::string name(s.name);
    const std::string ext = std::filesystem::path(name).extension().string();
    if (ext != ".comp" && ext != ".vert" && ext != ".frag") continue;
    EXPECT_TRUE(built.count(name)) << name << " is not built by this test: add its programs to allPrograms()";
  }
  for (const auto& [name, mirror] : mirrorTable)
    EXPECT_TRUE(mirrored.count(name)) << "the C++ mirror of " << name << " matched no active block";
}

}  // namespace sphfx

#include "sphfx/core/scene.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>

#include "sphfx/core/error.h"
#include "sphfx/core/log.h"

namespace sphfx {

using schema::Json;
using schema::makeSchema;
using schema::Object;
using schema::Range;
using schema::SchemaError;

namespace {

const std::vector<std::pair<std::string, Shape>> kShapes = {{"box", Shape::Box}, {"sphere", Shape::Sphere}};
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr size_t kUnbounded = std::numeric_limits<size_t>::max();
constexpr size_t kMaxParticles = 200'000'000;

std::string vecText(const Vec3d& v) {
  return fmt::format("[{}, {}, {}]", v[0], v[1], v[2]);
}

/// Boxes need min/max, spheres need center/radius; a key of the other shape is an error rather than
/// silently ignored.
template <class T>
void checkShape(const T& value, const Json& raw, const std::string& path) {
  const bool box = value.shape == Shape::Box;
  const std::vector<std::string> needed =
      box ? std::vector<std::string>{"min", "max"} : std::vector<std::string>{"center", "radius"};
  const std::vector<std::string> unused =
      box ? std::vector<std::string>{"center", "radius"} : std::vector<std::string>{"min", "max"};
  const std::string shapeName = box ? "box" : "sphere";
  for (const auto& key : needed)
    if (!raw.contains(key)) throw SchemaError(path, "a " + shapeName + " needs \"" + key + "\"");
  for (const auto& key : unused)
    if (raw.contains(key))
      throw SchemaError(schema::childPath(path, key), "not used by shape \"" + shapeName + "\"");
  if (box)
    for (int a = 0; a < 3; ++a)
      if (!(value.min[a] < value.max[a]))
        throw SchemaError(schema::childPath(path, "max"), "expected max > min on every axis, got min " +
                                                              vecText(value.min) + ", max " +
                                                              vecText(value.max));
  if (!box && !(value.radius > 0))
    throw SchemaError(schema::childPath(path, "radius"), "expected a radius > 0");
}

template <class T>
bool isBox(const T& v) {
  return v.shape == Shape::Box;
}
template <class T>
bool isSphere(const T& v) {
  return v.shape == Shape::Sphere;
}

std::shared_ptr<const Object<Domain>> domainSchema() {
  return makeSchema<Domain>([](Object<Domain>& o) {
    o.vec3("min", &Domain::min, {0, 0, 0}, "m", Range::any(), "Lower corner of the domain box (solid walls).")
        .vec3("max", &Domain::max, {1, 1, 1}, "m", Range::any(),
              "Upper corner of the domain box (solid walls).")
        .choiceList(
            "periodic", &Domain::periodic, std::vector<PeriodicAxis>{},
            {{"x", PeriodicAxis::X}, {"y", PeriodicAxis::Y}, {"z", PeriodicAxis::Z}},
            "Axes along which the domain wraps around (periodic boundaries): no walls on those faces, "
            "particles leaving through max re-enter at min. Both solvers, no colliders; each periodic "
            "extent must be at least 3 kernel radii, and a fluid block spanning it must hold a whole "
            "number of lattice spacings (no gap or overlap at the seam). A periodic y needs gravity's "
            "y component 0 (with no floor the fluid would fall forever).")
        .choiceList("open", &Domain::open, std::vector<DomainFace>{},
                    {{"x-", DomainFace::XMin},
                     {"x+", DomainFace::XMax},
                     {"y-", DomainFace::YMin},
                     {"y+", DomainFace::YMax},
                     {"z-", DomainFace::ZMin},
                     {"z+", DomainFace::ZMax}},
                    "Open faces (outflow): no wall and no clamp there; a particle that leaves the domain "
                    "through an open face is removed. Not on a periodic axis.")
        .check([](const Domain& d, const Json&, const std::string& path) {
          for (int a = 0; a < 3; ++a)
            if (!(d.min[a] < d.max[a]))
              throw SchemaError(
                  schema::childPath(path, "max"),
                  "expected max > min on every axis, got min " + vecText(d.min) + ", max " + vecText(d.max));
        });
  });
}

std::shared_ptr<const Object<TaylorGreenVortex>> taylorGreenSchema() {
  return makeSchema<TaylorGreenVortex>([](Object<TaylorGreenVortex>& o) {
    o.number("amplitude", &TaylorGreenVortex::amplitude, 0.01, "m/s", Range{0, 1e4, true, false},
             "Velocity amplitude U of the vortex at the first frame.");
  });
}

std::shared_ptr<const Object<FluidBlock>> fluidBlockSchema() {
  return makeSchema<FluidBlock>([](Object<FluidBlock>& o) {
    o.choice("shape", &FluidBlock::shape, Shape::Box, kShapes, "Shape of the block.")
        .vec3("min", &FluidBlock::min, {0, 0, 0}, "m", Range::any(), "Lower corner.")
        .onlyWhen(isBox<FluidBlock>, "box")
        .vec3("max", &FluidBlock::max, {0, 0, 0}, "m", Range::any(), "Upper corner.")
        .onlyWhen(isBox<FluidBlock>, "box")
        .vec3("center", &FluidBlock::center, {0, 0, 0}, "m", Range::any(), "Centre.")
        .onlyWhen(isSphere<FluidBlock>, "sphere")
        .number("radius", &FluidBlock::radius, 0, "m", Range::nonNegative(), "Radius.")
        .onlyWhen(isSphere<FluidBlock>, "sphere")
        .vec3("velocity", &FluidBlock::velocity, {0, 0, 0}, "m/s", Range::closed(-1e4, 1e4),
              "Initial velocity of the block's particles.")
        .optionalChild("taylor_green", &FluidBlock::taylorGreen, taylorGreenSchema(),
                       "A Taylor-Green vortex in the x-z plane added to velocity: u = U sin(2 pi x / Lx) "
                       "cos(2 pi z / Lz), w = -U (Lz / Lx) cos(2 pi x / Lx) sin(2 pi z / Lz), x and z from "
                       "domain.min, one wavelength per period (needs domain.periodic x and z).")
        .check(checkShape<FluidBlock>);
  });
}

std::shared_ptr<const Object<Fluid>> fluidSchema() {
  return makeSchema<Fluid>([](Object<Fluid>& o) {
    o.number("spacing", &Fluid::spacing, 0.02, "m", Range{0, 10, true, false},
             "Rest particle spacing; sets the resolution and the particle mass (rest_density * spacing^3).")
        .number("packing", &Fluid::packing, 1.0, "", Range::closed(0.5, 2),
                "Initial lattice spacing as a fraction of spacing: below 1 starts compressed (dense-start "
                "stability tests), above 1 sparse.")
        .number("rest_density", &Fluid::restDensity, 1000, "kg/m^3", Range{0, 1e5, true, false},
                "Rest density of the fluid.")
        .choice("viscosity_model", &Fluid::viscosityModel, ViscosityModel::Artificial,
                {{"none", ViscosityModel::None},
                 {"laplacian", ViscosityModel::Laplacian},
                 {"artificial", ViscosityModel::Artificial}},
                "Viscosity term: none, the seed's Laplacian form (uses viscosity), or Monaghan's artificial "
                "viscosity (uses artificial_viscosity).")
        .number("viscosity", &Fluid::viscosity, 1e-6, "m^2/s", Range::closed(0, 100),
                "Kinematic viscosity for the laplacian model (water: 1e-6).")
        .onlyWhen([](const Fluid& f) { return f.viscosityModel == ViscosityModel::Laplacian; },
                  "laplacian model")
        .number(
            "artificial_viscosity", &Fluid::artificialViscosity, 0.02, "", Range::closed(0, 10),
            "Monaghan alpha for the artificial model: nu = 2 alpha h c / (rho_i + rho_j) between particles "
            "(the walls use wall_viscosity_speed in place of alpha c). In CFL mode the step is capped at 2 / "
            "the term's largest decay rate on the resting lattice, proportional to alpha c / h "
            "(docs/simulation.md, Time step).")
        .onlyWhen([](const Fluid& f) { return f.viscosityModel == ViscosityModel::Artificial; },
                  "artificial model")
        .number(
            "wall_viscosity_factor", &Fluid::wallViscosityFactor, 1.0, "", Range::closed(0, 10),
            "Multiplies the viscosity term between the fluid and the walls and colliders (DualSPHysics' "
            "ViscoBoundFactor): 1 treats a wall sample as fluid at the wall's velocity (no slip), 0 "
            "makes the walls free-slip (SPlisHSPlasH's default boundary viscosity) and compiles no wall "
            "viscosity; free slip leads Martin & Moyce's front further (docs/validation.md, Sensitivity).")
        .onlyWhen([](const Fluid& f) { return f.viscosityModel != ViscosityModel::None; },
                  "laplacian or artificial model")
        .number("wall_viscosity_speed", &Fluid::wallViscositySpeed, 0.6, "m/s", Range::closed(0, 1000),
                "The artificial model's alpha c at the walls and colliders: their Monaghan term uses this "
                "speed times wall_viscosity_factor where the fluid's uses artificial_viscosity times the "
                "speed of sound, so that the walls' drag, which sets how fast a surge runs along the floor, "
                "stays put when alpha or c are tuned (docs/validation.md, Sensitivity). The default is "
                "their defaults' product, 0.02 x 30 m/s.")
        .onlyWhen([](const Fluid& f) { return f.viscosityModel == ViscosityModel::Artificial; },
                  "artificial model")
        .choice(
            "wall_drag", &Fluid::wallDrag, WallDrag::Viscous,
            {{"viscous", WallDrag::Viscous}, {"friction", WallDrag::Friction}},
            "What the walls' and colliders' Monaghan term acts on: viscous, the whole velocity relative "
            "to the wall (no slip; its drag reaches into the fluid by the artificial viscosity, alpha h c "
            "/ 8, so a surge thinned to a few spacings lags), or friction, the approach alone (it pushes "
            "along the walls' normal and never pulls), with a skin friction wall_friction on the "
            "sliding, which holds a long run-out's front (docs/validation.md, Dam-break front over a "
            "long tank).")
        .onlyWhen([](const Fluid& f) { return f.viscosityModel == ViscosityModel::Artificial; },
                  "artificial model")
        .number("wall_friction", &Fluid::wallFriction, 0.005, "", Range::closed(0, 1),
                "Skin-friction coefficient c_f of wall_drag friction: the walls' shear stress is c_f rho "
                "|u_t| u_t / 2 at the sliding speed u_t, shared among the particles within h of the wall "
                "by the gradient of the walls' kernel sum. 0.005 is a smooth flat plate's turbulent "
                "0.074 Re^-0.2 at Re = 7e5 (0.0074 at 1e5, 0.0047 at 1e6).")
        .onlyWhen(
            [](const Fluid& f) {
              return f.viscosityModel == ViscosityModel::Artificial && f.wallDrag == WallDrag::Friction;
            },
            "artificial model, wall_drag friction")
        .number("wall_contact", &Fluid::wallContact, 0.6, "", Range::closed(0, 1),
                "Keeps spray and thin sheets off the walls and colliders: a particle with fewer neighbours "
                "(fluid and samples within h) than this share of a full lattice neighbourhood, where the "
                "density no longer holds it off, may not come nearer to the domain's walls once the walls' "
                "kernel sum over it passes that of a resting particle half a spacing from a flat wall; "
                "every particle may not come nearer than half a spacing to a collider's surface (by its "
                "distance, which holds over convex edges too). The step takes away the part of its "
                "velocity that would take it nearer (never adding energy). The bulk, which has full "
                "neighbourhoods, never meets it at the walls: a resting tank without colliders runs bit for "
                "bit as without it. 0 leaves it out (particles then reach the last-resort clamp at 0.05 "
                "spacings, docs/validation.md).")
        .list("blocks", &Fluid::blocks, fluidBlockSchema(), 0, kUnbounded,
              "Blocks of fluid at the first frame (boxes or spheres, must not overlap); may be empty when "
              "the scene has emitters.");
  });
}

bool isTait(const WcsphSettings& w) {
  return w.eos == EquationOfState::Tait;
}

std::shared_ptr<const Object<WcsphSettings>> wcsphSchema() {
  return makeSchema<WcsphSettings>([](Object<WcsphSettings>& o) {
    o.choice("eos", &WcsphSettings::eos, EquationOfState::Tait,
             {{"linear", EquationOfState::Linear}, {"tait", EquationOfState::Tait}},
             "Equation of state: the seed's p = k (rho - rho0) (uses stiffness), or Tait, p = B ((rho / "
             "rho0)^gamma - 1) with B = rho0 c^2 / gamma (uses solver.speed_of_sound and gamma).")
        .choice("kernel", &WcsphSettings::kernel, SphKernel::WendlandC2,
                {{"wendland_c2", SphKernel::WendlandC2}, {"muller2003", SphKernel::Muller2003}},
                "Smoothing kernel of the density sum and the pressure gradient: Wendland C2 (one "
                "kernel for both, so the pressure force is the gradient of the density estimate and "
                "the scheme conserves energy; no pairing instability), or Mueller et al. 2003's poly6 "
                "density with the spiky gradient (the seed's pair, not energy-consistent).")
        .number("stiffness", &WcsphSettings::stiffness, 1000, "m^2/s^2", Range{0, 1e9, true, false},
                "Linear EOS stiffness k; the speed of sound is then sqrt(k).")
        .onlyWhen([](const WcsphSettings& w) { return !isTait(w); }, "linear eos")
        .number("gamma", &WcsphSettings::gamma, 7, "", Range::closed(1, 10), "Tait exponent (7 for water).")
        .onlyWhen(isTait, "tait eos")
        .number("force_factor", &WcsphSettings::forceFactor, 0.25, "", Range{0, 10, true, false},
                "CFL mode: factor on Monaghan's force limit sqrt(h / |a|max); lower it if strong body "
                "forces or collisions blow a run up.");
  });
}

std::shared_ptr<const Object<DfsphSettings>> dfsphSchema() {
  return makeSchema<DfsphSettings>([](Object<DfsphSettings>& o) {
    o.number("max_density_error", &DfsphSettings::maxDensityError, 0.001, "", Range{0, 0.1, true, false},
             "Average density error tolerance of the constant-density solve, as a fraction of rest "
             "density; lower it for less compression at the cost of iterations. In CFL mode the steps "
             "that time.dt_max or the artificial viscosity's bound set below depth_step_factor's cap solve "
             "to this times (step / cap)^2, so that one step's fall keeps its ratio to the tolerance "
             "(docs/simulation.md, Time step).")
        .number("max_divergence_error", &DfsphSettings::maxDivergenceError, 0.001, "",
                Range{0, 0.1, true, false},
                "Average divergence error tolerance: mean |D rho/Dt| / rest density times dt, the relative "
                "density change per step (SPlisHSPlasH's default 0.1 %).")
        .integer("min_iterations", &DfsphSettings::minIterations, 2, "", Range::closed(1, 1000),
                 "Minimum iterations of the constant-density solve per step.")
        .integer("max_iterations", &DfsphSettings::maxIterations, 200, "", Range::closed(1, 100000),
                 "Maximum iterations of each solve per step; a solve that reaches it ends with its error "
                 "above the tolerance (the frame statistics show it). Raise it when they do.")
        .integer("min_divergence_iterations", &DfsphSettings::minDivergenceIterations, 1, "",
                 Range::closed(1, 1000),
                 "Minimum iterations of the divergence solve per step (after its warm start).")
        .number("jacobi_omega", &DfsphSettings::jacobiOmega, 0.5, "", Range{0, 1, true, false},
                "Relaxation of the projected Jacobi updates (IISPH's 0.5) at kernel_support 2 with the "
                "spiky gradient; larger values converge faster where they converge at all (the dam break "
                "from rest with jacobi_momentum 0 stops at 0.7). The solves scale it by the lattice's "
                "Jacobi spectral bound, 2.81 there over the bound of the scene's support and kernel (spiky "
                "6.72 at support 3: 0.5 becomes 0.21; wendland_c2 2.61 at 2: 0.54), so that every support "
                "and kernel keeps the same margin.")
        .number("jacobi_momentum", &DfsphSettings::jacobiMomentum, 0.5, "", Range{0, 1, false, true},
                "Share of a particle's previous stiffness increment added to the next (heavy-ball Jacobi, "
                "Polyak 1964); 0 is plain relaxed Jacobi, which needs about 1.5 times the iterations (the "
                "dam break's first frame from rest).")
        .number("density_warm_share", &DfsphSettings::densityWarmShare, 0.5, "", Range::closed(0, 1),
                "Share of the last step's stiffness the constant-density solve starts from (warm start), "
                "in the substeps density_warm_steps names. A warm start needs fewer iterations in fast "
                "flow, but at rest it lets the solve stop at its tolerance holding part of the last "
                "pressure: at 0.5 in every substep a 12,000-particle tank at depth_step_factor 0.2 ends 2 s "
                "at 100 times the kinetic energy of a cold start (docs/validation.md). 0 starts every "
                "solve cold.")
        .choice("density_warm_steps", &DfsphSettings::densityWarmSteps, DfsphWarmSteps::FlowLimited,
                {{"all", DfsphWarmSteps::All}, {"flow_limited", DfsphWarmSteps::FlowLimited}},
                "The substeps whose constant-density solve starts warm: \"all\"; or \"flow_limited\", "
                "only those after a substep whose step the flow set (CFL mode: the speed, fall or viscous "
                "limit below time.dt_max, depth_step_factor's cap and the artificial viscosity's bound). "
                "Water at rest, which the cap steps, "
                "then starts every solve cold and gives the same caches as density_warm_share 0, while "
                "fast flow keeps the warm start's fewer iterations. The first substep of each frame and "
                "every fixed step start cold.")
        .onlyWhen([](const DfsphSettings& d) { return d.densityWarmShare > 0; }, "density_warm_share > 0")
        .number("divergence_warm_share", &DfsphSettings::divergenceWarmShare, 0.5, "", Range::closed(0, 1),
                "The same for the divergence solve (SPlisHSPlasH's 0.5); the full share keeps re-applying a "
                "stale impulse and a resting tank does not settle.")
        .choice("walls", &DfsphSettings::walls, DfsphWalls::Constraints,
                {{"push", DfsphWalls::Push}, {"constraints", DfsphWalls::Constraints}},
                "The walls in the constant-density solve: \"push\", the wall samples push a particle "
                "with density_wall_push times its own stiffness plus the hydrostatic rise (Akinci 2012, "
                "Adami 2012); \"constraints\", each wall sample keeps a density constraint of its own "
                "(the fluid near it at most its share on the resting lattice) whose stiffness pushes "
                "the fluid along the constraint's gradient: the walls do no work, so a closed tank "
                "does not gain energy; it costs a pass over the samples per iteration. With colliders "
                "the samples' shares are recomputed every substep and their solve starts cold. A resumed "
                "run is not bit-identical to an uninterrupted one (the samples' stiffness is not in the "
                "restart file).")
        .choice("density_kernel", &DfsphSettings::densityKernel, DfsphDensityKernel::WendlandC2,
                {{"poly6", DfsphDensityKernel::Poly6},
                 {"spiky", DfsphDensityKernel::Spiky},
                 {"wendland_c2", DfsphDensityKernel::WendlandC2}},
                "Kernel of the fluid's density sum: \"wendland_c2\", Wendland C2 for the density, every "
                "gradient of the solves and the walls (WCSPH's kernel), with the particle mass scaled so "
                "that the resting lattice sums to the rest density: a deep resting column keeps its cubic "
                "lattice; \"spiky\", the same with the spiky kernel, whose sum is lower on closer "
                "packings, so a deep resting column's lattice gives way to one (docs/design.md); or "
                "\"poly6\" (Mueller et al. 2003), while every gradient of the solves is the spiky kernel's, "
                "so a solve's predicted density change is not the change of the sum it corrects. "
                "\"wendland_c2\" and \"spiky\" need walls \"constraints\" (push walls with the spiky "
                "density burst in the first frame).")
        .number("density_wall_push", &DfsphSettings::densityWallPush, 1.5, "", Range::closed(1, 1.75),
                "Weight of the wall samples in the constant-density solve: above 1 walls push back harder "
                "than fluid, which keeps particles out of them. Above 1 the solve is not symmetric: in a "
                "domain 6 particles across the first frame gains 0.7 % of g H at 1.75, 12.5 % at 1.9, "
                "and 2.5 diverges (docs/design.md).")
        .onlyWhen([](const DfsphSettings& d) { return d.walls == DfsphWalls::Push; }, "push walls")
        .number("free_surface_fraction", &DfsphSettings::freeSurfaceFraction, 0.6, "", Range::closed(0, 1),
                "A particle with fewer neighbours than this share of a full lattice neighbourhood is at "
                "the free surface and gets no divergence correction (SPlisHSPlasH: 20 of 32).")
        .number("fall_factor", &DfsphSettings::fallFactor, 0.15, "", Range{0, 10, true, false},
                "CFL mode: the non-pressure acceleration's displacement per step, |a|max dt^2 <= factor * "
                "spacing. It bounds the first steps from rest; 0.4 allows 16.7 ms at spacing 0.01.")
        .number("depth_step_factor", &DfsphSettings::depthStepFactor, 0.4, "", Range::closed(0, 10),
                "CFL mode: caps the step at this factor times spacing / sqrt(|g| H), H the domain's extent "
                "along gravity over its walled axes (sqrt(g H): the speed of gravity waves in the deepest "
                "column the domain holds; gravity along periodic axes alone has no cap); 0 leaves the cap "
                "out. A resting column of depth H grows once the step passes about spacing / sqrt(g H), at "
                "any spacing; 0.4 settles the 0.3 m tank at spacing 0.01 and 0.005 (docs/validation.md, "
                "Known limits). Fixed steps leave it out.")
        .check([](const DfsphSettings& d, const Json&, const std::string& path) {
          const int least = std::max(d.minIterations, d.minDivergenceIterations);
          if (least > d.maxIterations)
            throw SchemaError(schema::childPath(path, "max_iterations"),
                              fmt::format("expected max_iterations >= min_iterations and "
                                          "min_divergence_iterations ({}), got {}",
                                          least, d.maxIterations));
        });
  });
}

std::string onlyWithMethod(const std::string& name) {
  return "only when the method is \"" + name + "\"";
}

std::shared_ptr<const Object<SolverSettings>> solverSchema() {
  return makeSchema<SolverSettings>([](Object<SolverSettings>& o) {
    const auto& solvers = pressureSolverRegistry();
    o.choice("method", &SolverSettings::method, Solver::DFSPH, methodChoices(solvers),
             "Pressure solver. " + methodDescriptions(solvers) +
                 ". The default is the one whose front error against wall time is lower on the shipped "
                 "scenes (docs/performance.md).")
        .number("kernel_support", &SolverSettings::kernelSupport, 2.0, "spacings", Range::closed(1.2, 4),
                "Kernel support radius h as a multiple of the particle spacing.")
        .number("speed_of_sound", &SolverSettings::speedOfSound, 30, "m/s", Range{0, 1e5, true, false},
                "Numerical speed of sound c: WCSPH's Tait EOS and acoustic time-step limit (about 10x the "
                "fastest flow keeps the density error near 1 %), and the c of Monaghan's artificial "
                "viscosity under either solver. With WCSPH's linear eos, c is sqrt(stiffness) instead.")
        .child("wcsph", &SolverSettings::wcsph, wcsphSchema(), "WCSPH's parameters.")
        .onlyWhen([](const SolverSettings& s) { return s.method == Solver::WCSPH; },
                  onlyWithMethod(methodEntry(solvers, Solver::WCSPH).name))
        .child("dfsph", &SolverSettings::dfsph, dfsphSchema(), "DFSPH's parameters.")
        .onlyWhen([](const SolverSettings& s) { return s.method == Solver::DFSPH; },
                  onlyWithMethod(methodEntry(solvers, Solver::DFSPH).name));
  });
}

bool isFixed(const TimeSettings& t) {
  return t.mode == TimeStepMode::Fixed;
}
bool isCfl(const TimeSettings& t) {
  return t.mode == TimeStepMode::Cfl;
}

std::shared_ptr<const Object<TimeSettings>> timeSchema() {
  return makeSchema<TimeSettings>([](Object<TimeSettings>& o) {
    o.number("fps", &TimeSettings::fps, 24, "1/s", Range{0, 1000, true, false},
             "Frames per second of the cache.")
        .integer("start_frame", &TimeSettings::startFrame, 1, "frame", Range::closed(-1e6, 1e7),
                 "First frame (simulated time 0); film shots often start at 1001.")
        .integer("end_frame", &TimeSettings::endFrame, 48, "frame", Range::closed(-1e6, 1e7),
                 "Last frame, inclusive.")
        .choice("dt_mode", &TimeSettings::mode, TimeStepMode::Cfl,
                {{"fixed", TimeStepMode::Fixed}, {"cfl", TimeStepMode::Cfl}},
                "Time step control: fixed dt, or CFL-adaptive between dt_min and dt_max.")
        .number("dt", &TimeSettings::dt, 0.0007, "s", Range{0, 1, true, false}, "Fixed mode: the time step.")
        .onlyWhen(isFixed, "fixed mode")
        .number("cfl_factor", &TimeSettings::cflFactor, 0.4, "", Range{0, 10, true, false},
                "CFL mode: factor on the acoustic limit h / (c + |v|max) (WCSPH), or on the displacement per "
                "step, |v|max dt + |a|max dt^2 <= factor * spacing with a the non-pressure acceleration "
                "(DFSPH, Bender & Koschier 2015).")
        .onlyWhen(isCfl, "cfl mode")
        .number("viscous_factor", &TimeSettings::viscousFactor, 0.125, "", Range{0, 10, true, false},
                "CFL mode: factor on the viscous limit h^2 / nu.")
        .onlyWhen(isCfl, "cfl mode")
        .number("dt_min", &TimeSettings::dtMin, 1e-6, "s", Range{0, 1, true, false},
                "CFL mode: smallest step; needing less stops the run with an error.")
        .onlyWhen(isCfl, "cfl mode")
        .number("dt_max", &TimeSettings::dtMax, 0.005, "s", Range{0, 1, true, false},
                "CFL mode: largest step.")
        .onlyWhen(isCfl, "cfl mode")
        .check([](const TimeSettings& t, const Json&, const std::string& path) {
          if (t.endFrame < t.startFrame)
            throw SchemaError(
                schema::childPath(path, "end_frame"),
                fmt::format("expected end_frame >= start_frame ({}), got {}", t.startFrame, t.endFrame));
          if (t.endFrame - t.startFrame > 1'000'000)
            throw SchemaError(schema::childPath(path, "end_frame"), "expected at most 1000000 frames");
          if (isCfl(t) && t.dtMin > t.dtMax)
            throw SchemaError(schema::childPath(path, "dt_min"),
                              fmt::format("expected dt_min <= dt_max ({}), got {}", t.dtMax, t.dtMin));
        });
  });
}

std::shared_ptr<const Object<Keyframe>> keyframeSchema() {
  return makeSchema<Keyframe>([](Object<Keyframe>& o) {
    o.number("time", &Keyframe::time, 0, "s", Range::any(), "Time of the key (frame start_frame is 0 s).")
        .vec3("offset", &Keyframe::offset, {0, 0, 0}, "m", Range::any(),
              "Translation from the rest placement.")
        .vec3("rotation", &Keyframe::rotation, {0, 0, 0}, "deg", Range::closed(-1e6, 1e6),
              "Rotation from the rest placement about the collider's pivot (a box's or sphere's centre, a "
              "mesh's or vdb's translation: the file's origin): degrees about x, then y, then z (fixed "
              "axes). Interpolated as quaternions along the shortest arc: "
              "keys less than 180 degrees apart turn the way they read.");
  });
}

template <class K>
void checkIncreasingTimes(const std::vector<K>& keys, const std::string& path) {
  for (size_t i = 1; i < keys.size(); ++i)
    if (!(keys[i].time > keys[i - 1].time))
      throw SchemaError(
          schema::childPath(schema::childPath(path, "keyframes"), i) + "/time",
          fmt::format("expected times in increasing order, got {} after {}", keys[i].time, keys[i - 1].time));
}

const std::vector<std::pair<std::string, Shape>> kColliderShapes = {
    {"box", Shape::Box}, {"sphere", Shape::Sphere}, {"mesh", Shape::Mesh}, {"vdb", Shape::Vdb}};

bool isField(const Collider& c) {
  return c.isField();
}
bool isMesh(const Collider& c) {
  return c.shape == Shape::Mesh;
}
bool isVdb(const Collider& c) {
  return c.shape == Shape::Vdb;
}

// Box and sphere colliders as fluid blocks; mesh and vdb colliders need their file.
void checkCollider(const Collider& c, const Json& raw, const std::string& path) {
  if (!c.isField()) return checkShape(c, raw, path);
  const std::string shape = c.shape == Shape::Mesh ? "mesh" : "vdb";
  if (c.file.empty()) throw SchemaError(path, "a " + shape + " collider needs \"file\"");
}

std::shared_ptr<const Object<Collider>> colliderSchema() {
  return makeSchema<Collider>([](Object<Collider>& o) {
    o.text("name", &Collider::name, "", "Name shown in logs and renders.")
        .choice("shape", &Collider::shape, Shape::Box, kColliderShapes,
                "Shape of the collider: an analytic box or sphere, a triangle mesh file, or an OpenVDB "
                "level set.")
        .vec3("min", &Collider::min, {0, 0, 0}, "m", Range::any(), "Lower corner at rest.")
        .onlyWhen(isBox<Collider>, "box")
        .vec3("max", &Collider::max, {0, 0, 0}, "m", Range::any(), "Upper corner at rest.")
        .onlyWhen(isBox<Collider>, "box")
        .vec3("center", &Collider::center, {0, 0, 0}, "m", Range::any(), "Centre at rest.")
        .onlyWhen(isSphere<Collider>, "sphere")
        .number("radius", &Collider::radius, 0, "m", Range::nonNegative(), "Radius.")
        .onlyWhen(isSphere<Collider>, "sphere")
        .text("file", &Collider::file, "",
              "Geometry file, relative to the scene file: a triangle mesh (.obj, .ply, .stl; ASCII or "
              "binary) or an OpenVDB file (.vdb) holding a level set (negative inside).")
        .onlyWhen(isField, "mesh, vdb")
        .text("grid", &Collider::grid, "",
              "Name of the level-set grid in the file; empty: its first float grid.")
        .onlyWhen(isVdb, "vdb")
        .number("scale", &Collider::scale, 1, "", Range{0, 1e6, true, false},
                "Uniform scale of the geometry about the file's origin, applied first.")
        .onlyWhen(isField, "mesh, vdb")
        .vec3("rotation", &Collider::rotation, {0, 0, 0}, "deg", Range::closed(-360, 360),
              "Rest rotation about the file's origin after scaling: degrees about x, then y, then z.")
        .onlyWhen(isField, "mesh, vdb")
        .vec3("translation", &Collider::translation, {0, 0, 0}, "m", Range::any(),
              "Rest translation, applied last.")
        .onlyWhen(isField, "mesh, vdb")
        .number("thickness", &Collider::thickness, 0, "m", Range::closed(0, 1e3),
                "A mesh that is not closed (a terrain, a single plate) becomes a shell this thick "
                "around its triangles; 0: the mesh must be closed (watertight), else the scene is "
                "refused naming its open edges.")
        .onlyWhen(isMesh, "mesh")
        .list("keyframes", &Collider::keyframes, keyframeSchema(), 0, kUnbounded,
              "Keyframed rigid motion (translation and rotation), held outside the keys; empty: static. "
              "The fluid sees the wall velocity v + omega x r.")
        .check([](const Collider& c, const Json& raw, const std::string& path) {
          checkCollider(c, raw, path);
          checkIncreasingTimes(c.keyframes, path);
        });
  });
}

std::shared_ptr<const Object<Emitter>> emitterSchema() {
  return makeSchema<Emitter>([](Object<Emitter>& o) {
    o.text("name", &Emitter::name, "", "Name shown in errors and logs.")
        .choice("shape", &Emitter::shape, EmitterShape::Disc,
                {{"disc", EmitterShape::Disc}, {"box", EmitterShape::Box}, {"sphere", EmitterShape::Sphere}},
                "Shape of the emitter: a disc (a round nozzle) emitting along its normal, or a box or sphere "
                "(a volume source) that keeps its volume filled with fluid moving along direction.")
        .vec3("center", &Emitter::center, {0, 0, 0}, "m", Range::any(), "Centre of the disc or sphere.")
        .onlyWhen([](const Emitter& e) { return e.shape != EmitterShape::Box; }, "disc, sphere")
        .number("radius", &Emitter::radius, 0, "m", Range::nonNegative(),
                "Radius of the disc or sphere; its layer holds the lattice points (spacing fluid.spacing) "
                "within it.")
        .onlyWhen([](const Emitter& e) { return e.shape != EmitterShape::Box; }, "disc, sphere")
        .vec3("min", &Emitter::min, {0, 0, 0}, "m", Range::any(), "Lower corner of the box.")
        .onlyWhen([](const Emitter& e) { return e.shape == EmitterShape::Box; }, "box")
        .vec3("max", &Emitter::max, {0, 0, 0}, "m", Range::any(), "Upper corner of the box.")
        .onlyWhen([](const Emitter& e) { return e.shape == EmitterShape::Box; }, "box")
        .vec3("direction", &Emitter::direction, {0, -1, 0}, "", Range::any(),
              "Direction of the flow: the disc's normal, the volume source's flow (any length; normalised "
              "where used).")
        .number("velocity", &Emitter::speed, 1, "m/s", Range{0, 1e4, true, false},
                "Speed of the emitted fluid along direction: the particles enter with this velocity, and a "
                "new lattice layer enters each time the fluid has advanced one spacing, so the mass flow "
                "is rest_density x velocity x the disc's lattice area.")
        .number("start", &Emitter::start, 0, "s", Range::any(),
                "Time emission starts (frame start_frame is 0 s).")
        .number("end", &Emitter::end, 0, "s", Range::any(),
                "Time emission ends (required): the layers due in [start, end) are emitted. The GPU buffers "
                "are sized for every particle the emitter can add over this time.")
        .check([](const Emitter& e, const Json& raw, const std::string& path) {
          if (!raw.contains("end")) throw SchemaError(path, "an emitter needs \"end\"");
          if (e.shape == EmitterShape::Box) {
            for (const char* k : {"min", "max"})
              if (!raw.contains(k)) throw SchemaError(path, fmt::format("a box emitter needs \"{}\"", k));
            for (int a = 0; a < 3; ++a)
              if (!(e.min[a] < e.max[a]))
                throw SchemaError(schema::childPath(path, "max"),
                                  "expected max > min on every axis, got min " + vecText(e.min) + ", max " +
                                      vecText(e.max));
          } else {
            const char* shape = e.shape == EmitterShape::Disc ? "disc" : "sphere";
            if (!raw.contains("radius")) throw SchemaError(path, fmt::format("a {} needs \"radius\"", shape));
            if (!(e.radius > 0))
              throw SchemaError(schema::childPath(path, "radius"), "expected a radius > 0");
          }
          if (!(e.end > e.start))
            throw SchemaError(schema::childPath(path, "end"),
                              fmt::format("expected end > start ({} s), got {} s", e.start, e.end));
          const double n2 = e.direction[0] * e.direction[0] + e.direction[1] * e.direction[1] +
                            e.direction[2] * e.direction[2];
          if (!(n2 > 1e-12))
            throw SchemaError(schema::childPath(path, "direction"), "expected a non-zero direction");
        });
  });
}

std::shared_ptr<const Object<KillBox>> killBoxSchema() {
  return makeSchema<KillBox>([](Object<KillBox>& o) {
    o.vec3("min", &KillBox::min, {0, 0, 0}, "m", Range::any(), "Lower corner.")
        .vec3("max", &KillBox::max, {0, 0, 0}, "m", Range::any(), "Upper corner.")
        .check([](const KillBox& k, const Json& raw, const std::string& path) {
          for (const char* key : {"min", "max"})
            if (!raw.contains(key)) throw SchemaError(path, std::string("a kill box needs \"") + key + "\"");
          for (int a = 0; a < 3; ++a)
            if (!(k.min[a] < k.max[a]))
              throw SchemaError(
                  schema::childPath(path, "max"),
                  "expected max > min on every axis, got min " + vecText(k.min) + ", max " + vecText(k.max));
        });
  });
}

std::shared_ptr<const Object<Limits>> limitsSchema() {
  return makeSchema<Limits>([](Object<Limits>& o) {
    o.integer("max_particles", &Limits::maxParticles, int(kMaxParticles), "",
              Range::closed(1, double(kMaxParticles)),
              "Most particles the scene may hold at once: the initial ones plus everything its emitters "
              "can add. A scene above it is refused before it starts. Each particle takes about 170 bytes "
              "of GPU memory under WCSPH, so 10 million need about 1.7 GB.");
  });
}

std::shared_ptr<const Object<Health>> healthSchema() {
  return makeSchema<Health>([](Object<Health>& o) {
    o.number("max_density_ratio", &Health::maxDensityRatio, 3.0, "", Range{1, 1e6, true, false},
             "Stop the run if any particle's density exceeds this multiple of rest density.")
        .number("max_speed", &Health::maxSpeed, 1000, "m/s", Range{0, 1e8, true, false},
                "Stop the run if any particle moves faster than this.");
  });
}

std::shared_ptr<const Object<CacheSettings>> cacheSchema() {
  return makeSchema<CacheSettings>([](Object<CacheSettings>& o) {
    o.choiceList("attributes", &CacheSettings::attributes, std::vector<CacheAttribute>{},
                 {{"density", CacheAttribute::Density},
                  {"pressure", CacheAttribute::Pressure},
                  {"id", CacheAttribute::Id}},
                 "Optional per-particle attributes written besides P and v. Density and WCSPH's pressure "
                 "are those of the frame's end state; DFSPH's pressure is the frame's mean, the pressure "
                 "impulse its two solves applied over the frame divided by the frame's time.");
  });
}

std::shared_ptr<const Object<AnisotropicSurfaceSettings>> anisotropicSurfaceSchema() {
  return makeSchema<AnisotropicSurfaceSettings>([](Object<AnisotropicSurfaceSettings>& o) {
    o.number("lambda", &AnisotropicSurfaceSettings::lambda, 0.9, "", Range::closed(0, 1),
             "Laplacian smoothing of the kernel centres towards their neighbours' mean (Yu & Turk: 0.9 to "
             "1); lower keeps small features, higher gives a smoother surface.")
        .number("max_stretch", &AnisotropicSurfaceSettings::maxStretch, 4, "", Range::closed(1, 100),
                "k_r: largest ratio between a kernel's longest and shortest axes; higher makes thin sheets "
                "thinner and flatter.")
        .integer("isolated_below", &AnisotropicSurfaceSettings::isolatedBelow, 6, "", Range::closed(0, 1000),
                 "N_eps: a particle with fewer neighbours gets a small isotropic kernel (spray).")
        .number("isolated_scale", &AnisotropicSurfaceSettings::isolatedScale, 0.5, "",
                Range{0, 1, true, false}, "k_n: the support of such a kernel, relative to the full one.");
  });
}

std::shared_ptr<const Object<SurfaceSettings>> surfaceSchema() {
  return makeSchema<SurfaceSettings>([](Object<SurfaceSettings>& o) {
    const auto& methods = surfacingMethodRegistry();
    o.choice("method", &SurfaceSettings::method, SurfaceMethod::ZhuBridson, methodChoices(methods),
             "Particle-to-level-set method. " + methodDescriptions(methods) + ".")
        .number("voxel_factor", &SurfaceSettings::voxelFactor, 0.5, "spacings", Range::closed(0.05, 4),
                "Voxel size as a multiple of the particle spacing.")
        .number("radius_factor", &SurfaceSettings::radiusFactor, 1.0, "spacings", Range::closed(0.1, 8),
                "Particle radius as a multiple of the particle spacing.")
        .integer("smooth_iterations", &SurfaceSettings::smoothIterations, 2, "", Range::closed(0, 100),
                 "Level-set smoothing iterations after rasterizing.")
        .number("adaptivity", &SurfaceSettings::adaptivity, 0.0, "", Range::closed(0, 1),
                "Mesh adaptivity (0: uniform triangles).")
        .child("anisotropic", &SurfaceSettings::anisotropic, anisotropicSurfaceSchema(),
               "The anisotropic method's parameters.")
        .onlyWhen([](const SurfaceSettings& s) { return s.method == SurfaceMethod::Anisotropic; },
                  onlyWithMethod(methodEntry(surfacingMethodRegistry(), SurfaceMethod::Anisotropic).name));
  });
}

std::shared_ptr<const Object<CameraKey>> cameraKeySchema() {
  return makeSchema<CameraKey>([](Object<CameraKey>& o) {
    o.number("time", &CameraKey::time, 0, "s", Range::any(), "Time of the key.")
        .vec3("position", &CameraKey::position, {0, 0, 0}, "m", Range::any(), "Camera position.")
        .vec3("look_at", &CameraKey::lookAt, {0, 0, 0}, "m", Range::any(), "Point the camera looks at.");
  });
}

std::shared_ptr<const Object<Camera>> cameraSchema() {
  return makeSchema<Camera>([](Object<Camera>& o) {
    o.vec3("position", &Camera::position, {2, 1.5, 3}, "m", Range::any(), "Camera position.")
        .vec3("look_at", &Camera::lookAt, {0.5, 0.3, 0.5}, "m", Range::any(), "Point the camera looks at.")
        .number("fov", &Camera::fovDegrees, 40, "degrees", Range{0, 180, true, true},
                "Vertical field of view.")
        .list("keyframes", &Camera::keyframes, cameraKeySchema(), 0, kUnbounded,
              "Optional animation; when present it overrides position and look_at.")
        .check([](const Camera& c, const Json&, const std::string& path) {
          checkIncreasingTimes(c.keyframes, path);
          double d2 = 0;
          for (int a = 0; a < 3; ++a) d2 += (c.position[a] - c.lookAt[a]) * (c.position[a] - c.lookAt[a]);
          if (c.keyframes.empty() && d2 == 0)
            throw SchemaError(schema::childPath(path, "look_at"), "expected look_at to differ from position");
        });
  });
}

std::shared_ptr<const Object<RenderSettings>> renderSchema() {
  return makeSchema<RenderSettings>([](Object<RenderSettings>& o) {
    o.integer("width", &RenderSettings::width, 1280, "px", Range::closed(16, 16384), "Image width.")
        .integer("height", &RenderSettings::height, 720, "px", Range::closed(16, 16384), "Image height.")
        .integer("samples", &RenderSettings::samples, 4, "", Range::closed(1, 16), "MSAA samples per pixel.")
        .choice("source", &RenderSettings::source, RenderSource::Surface,
                {{"surface", RenderSource::Surface}, {"particles", RenderSource::Particles}},
                "What to render: the surfaced meshes or the particles as sphere impostors.")
        .choice("color_by", &RenderSettings::colorBy, ColorBy::Height,
                {{"height", ColorBy::Height}, {"speed", ColorBy::Speed}},
                "Particles mode: colour ramp input.")
        .choice("format", &RenderSettings::format, ImageFormat::Png,
                {{"png", ImageFormat::Png}, {"exr", ImageFormat::Exr}},
                "Image format: 8-bit sRGB PNG, or half RGBA + float Z EXR.")
        .optionalChild("camera", &RenderSettings::camera, cameraSchema(),
                       "Camera; absent: automatic framing of the domain.");
  });
}

bool insideDomain(const Domain& d, const Vec3d& lo, const Vec3d& hi) {
  for (int a = 0; a < 3; ++a)
    if (lo[a] < d.min[a] || hi[a] > d.max[a]) return false;
  return true;
}

void blockBounds(const FluidBlock& b, Vec3d& lo, Vec3d& hi) {
  for (int a = 0; a < 3; ++a) {
    lo[a] = b.shape == Shape::Box ? b.min[a] : b.center[a] - b.radius;
    hi[a] = b.shape == Shape::Box ? b.max[a] : b.center[a] + b.radius;
  }
}

/// Geometry that only the whole scene can check: blocks inside the domain, not overlapping, each giving
/// at least one particle, and a particle count the tool can hold.
void checkSceneGeometry(const Scene& s, const Json&, const std::string&) {
  if (s.fluid.blocks.empty() && s.emitters.empty())
    throw SchemaError("/fluid/blocks",
                      "expected [1, inf] entries, got 0 (only a scene with emitters may "
                      "start without fluid)");
  std::vector<std::pair<Vec3d, Vec3d>> bounds;
  for (size_t i = 0; i < s.fluid.blocks.size(); ++i) {
    const std::string path = "/fluid/blocks/" + std::to_string(i);
    Vec3d lo, hi;
    blockBounds(s.fluid.blocks[i], lo, hi);
    if (!insideDomain(s.domain, lo, hi))
      throw SchemaError(path, "block " + vecText(lo) + " - " + vecText(hi) + " is not inside the domain " +
                                  vecText(s.domain.min) + " - " + vecText(s.domain.max));
    for (size_t j = 0; j < bounds.size(); ++j) {
      bool overlap = true;
      for (int a = 0; a < 3; ++a)
        overlap = overlap && lo[a] < bounds[j].second[a] && bounds[j].first[a] < hi[a];
      if (overlap) throw SchemaError(path, "overlaps block " + std::to_string(j));
    }
    bounds.emplace_back(lo, hi);
    Scene single = s;
    single.fluid.blocks = {s.fluid.blocks[i]};
    if (countInitialParticles(single) == 0)
      throw SchemaError(path, fmt::format("block holds no particle at spacing {} m", s.fluid.spacing));
  }
  const size_t n = countInitialParticles(s);
  if (n > kMaxParticles)
    throw SchemaError("/fluid/spacing",
                      fmt::format("spacing {} m gives {} particles, more than the limit of {}",
                                  s.fluid.spacing, n, kMaxParticles));
}

/// The speed alpha c (m/s) of the artificial model's Monaghan term between particles.
double fluidArtificialSpeed(const Scene& s) {
  return s.fluid.artificialViscosity * s.soundSpeed();
}

/// The artificial model's walls: their term is the fluid's Monaghan term rescaled (Scene::
/// wallViscosityMultiple), so walls with a viscosity need a fluid one.
void checkWallViscosity(const Scene& s, const Json&, const std::string&) {
  const Fluid& f = s.fluid;
  if (f.viscosityModel != ViscosityModel::Artificial || f.wallViscosityFactor * f.wallViscositySpeed == 0)
    return;
  if (fluidArtificialSpeed(s) == 0)
    throw SchemaError("/fluid/artificial_viscosity",
                      "expected a number > 0 while the walls have an artificial viscosity "
                      "(wall_viscosity_factor and wall_viscosity_speed > 0); for an inviscid fluid set "
                      "viscosity_model \"none\" or wall_viscosity_factor 0");
}

/// Periodic axes: what the solvers and the seam need (see the "periodic" description).
void checkPeriodic(const Scene& s, const Json&, const std::string&) {
  for (size_t i = 0; i < s.fluid.blocks.size(); ++i)
    if (s.fluid.blocks[i].taylorGreen && !(s.domain.isPeriodic(0) && s.domain.isPeriodic(2)))
      throw SchemaError(fmt::format("/fluid/blocks/{}/taylor_green", i),
                        "a Taylor-Green vortex needs domain.periodic to hold \"x\" and \"z\" (its "
                        "wavelengths are the periods)");
  if (!s.domain.anyPeriodic()) return;
  if (!s.colliders.empty())
    throw SchemaError("/colliders",
                      "colliders are not supported in a periodic domain yet (domain.periodic "
                      "is set); remove the colliders or domain.periodic");
  if (s.domain.isPeriodic(1) && s.gravity[1] != 0)
    throw SchemaError("/gravity", fmt::format("a periodic y axis needs gravity's y component 0, got {} m/s^2 "
                                              "(with no floor the fluid would fall forever)",
                                              s.gravity[1]));
  const double h = s.kernelRadius(), lattice = s.fluid.spacing * s.fluid.packing;
  for (int a : {0, 1, 2}) {
    if (!s.domain.isPeriodic(a)) continue;
    const std::string axis(1, "xyz"[a]);
    const double extent = s.domain.max[a] - s.domain.min[a];
    // The neighbour rows visit the cells either side of a particle's cell; with fewer than 3 cells of
    // size h the two sides would be the same cell across the seam.
    if (periodicCells(extent, h) < 3)
      throw SchemaError("/domain/max", fmt::format("the periodic {} extent {} m is less than 3 kernel radii "
                                                   "(3 h = {} m at spacing {} m)",
                                                   axis, extent, 3 * h, s.fluid.spacing));
    for (size_t i = 0; i < s.fluid.blocks.size(); ++i) {
      Vec3d lo, hi;
      blockBounds(s.fluid.blocks[i], lo, hi);
      if (lo[a] > s.domain.min[a] || hi[a] < s.domain.max[a]) continue;
      const double n = extent / lattice;
      if (std::fabs(n - std::round(n)) > 1e-6)
        throw SchemaError(fmt::format("/fluid/blocks/{}", i),
                          fmt::format("the block spans the periodic {} extent {} m, which is {:.4f} lattice "
                                      "spacings of {} m: expected a whole number (else the seam has a gap "
                                      "or an overlap)",
                                      axis, extent, n, lattice));
    }
  }
}

/// DFSPH's depth cap bounds CFL steps: with fixed steps nothing would read one set in the scene (the
/// default is left out).
void checkDfsphDepthStep(const Scene& s, const Json& raw, const std::string&) {
  static const Json::json_pointer key("/solver/dfsph/depth_step_factor");
  if (s.solver.method == Solver::DFSPH && s.time.mode == TimeStepMode::Fixed && raw.contains(key) &&
      s.solver.dfsph.depthStepFactor > 0)
    throw SchemaError("/solver/dfsph/depth_step_factor",
                      "expected 0 with time.dt_mode \"fixed\" (the cap bounds CFL steps), got " +
                          fmt::format("{}", s.solver.dfsph.depthStepFactor) +
                          "; remove the key or use CFL mode");
}

/// DFSPH's spiky and Wendland C2 densities are solved with the constraint walls only (with push walls the
/// spiky density bursts in the first frame, design.md).
void checkDfsphWalls(const Scene& s, const Json&, const std::string&) {
  if (s.solver.method != Solver::DFSPH) return;
  const DfsphDensityKernel k = s.solver.dfsph.densityKernel;
  if (k != DfsphDensityKernel::Poly6 && s.solver.dfsph.walls != DfsphWalls::Constraints)
    throw SchemaError("/solver/dfsph/density_kernel",
                      fmt::format("expected \"poly6\" with walls \"push\", got \"{}\" (the {} density{} "
                                  "needs walls \"constraints\"); set solver.dfsph.density_kernel to "
                                  "\"poly6\" or solver.dfsph.walls to \"constraints\"",
                                  k == DfsphDensityKernel::Spiky ? "spiky" : "wendland_c2",
                                  k == DfsphDensityKernel::Spiky ? "spiky" : "Wendland C2",
                                  k == DfsphDensityKernel::WendlandC2 ? ", the default," : ""));
}

/// Emitters, kill boxes and open faces: the geometry and the particle limit.
void checkEmittersAndRemoval(const Scene& s, const Json&, const std::string&) {
  if (!s.changesParticleCount()) return;
  for (const DomainFace f : s.domain.open) {
    const int axis = int(f) / 2;
    if (s.domain.isPeriodic(axis))
      throw SchemaError("/domain/open",
                        fmt::format("the {} axis is periodic: it has no face to open", "xyz"[axis]));
  }
  const size_t initial = countInitialParticles(s), limit = size_t(s.limits.maxParticles);
  size_t total = initial;
  if (initial > limit)
    throw SchemaError(
        "/limits/max_particles",
        fmt::format("the fluid blocks hold {} particles, more than limits.max_particles {}", initial, limit));
  for (size_t i = 0; i < s.emitters.size(); ++i) {
    const Emitter& e = s.emitters[i];
    const std::string path = "/emitters/" + std::to_string(i);
    const std::string label =
        e.name.empty() ? "emitter " + std::to_string(i) : fmt::format("emitter {} (\"{}\")", i, e.name);
    // The disc's extent: radius r times sqrt(1 - d_a^2) along each axis a; a volume source's bounds.
    const double len = std::sqrt(e.direction[0] * e.direction[0] + e.direction[1] * e.direction[1] +
                                 e.direction[2] * e.direction[2]);
    Vec3d lo = e.min, hi = e.max;
    if (e.shape != EmitterShape::Box)
      for (int a = 0; a < 3; ++a) {
        const double d = e.direction[a] / len;
        const double reach =
            e.shape == EmitterShape::Sphere ? e.radius : e.radius * std::sqrt(std::max(0.0, 1 - d * d));
        lo[a] = e.center[a] - reach;
        hi[a] = e.center[a] + reach;
      }
    if (!insideDomain(s.domain, lo, hi))
      throw SchemaError(path,
                        fmt::format("{}: the emitter spans {} - {}, not inside the domain {} - {}", label,
                                    vecText(lo), vecText(hi), vecText(s.domain.min), vecText(s.domain.max)));
    const size_t layers = emitterLayers(s, e), points = emitterLayerPoints(s, e).size();
    if (layers > limit || (points > 0 && layers > limit / points) || total + layers * points > limit)
      throw SchemaError(path,
                        fmt::format("{} adds {} layers of {} particles over [{}, {}) s, which brings the "
                                    "scene's largest particle count to {}, more than "
                                    "limits.max_particles {}",
                                    label, layers, points, e.start, e.end,
                                    double(total) + double(layers) * double(points), limit));
    total += layers * points;
  }
}

std::shared_ptr<const Object<Scene>> buildSceneSchema() {
  return makeSchema<Scene>([](Object<Scene>& o) {
    o.integer("version", &Scene::version, 1, "", Range::closed(1, 1), "Scene format version.")
        .text("name", &Scene::name, "", "Shot name shown in logs and the manifest.")
        .child("domain", &Scene::domain, domainSchema(), "The simulation box.")
        .vec3("gravity", &Scene::gravity, {0, -9.81, 0}, "m/s^2", Range::closed(-1e4, 1e4),
              "Gravitational acceleration (+Y is up).")
        .child("fluid", &Scene::fluid, fluidSchema(), "The fluid and its initial blocks.")
        .child("solver", &Scene::solver, solverSchema(), "Pressure solver and its parameters.")
        .child("time", &Scene::time, timeSchema(), "Frames and time step control.")
        .list("colliders", &Scene::colliders, colliderSchema(), 0, kUnbounded, "Solid objects in the fluid.")
        .list("emitters", &Scene::emitters, emitterSchema(), 0, kUnbounded,
              "Nozzles that add fluid while they are active.")
        .list("kill", &Scene::kill, killBoxSchema(), 0, kUnbounded,
              "Boxes that remove the particles entering them.")
        .child("limits", &Scene::limits, limitsSchema(), "Resource limits checked before a run starts.")
        .child("health", &Scene::health, healthSchema(), "Checks that stop a run that blows up.")
        .child("cache", &Scene::cache, cacheSchema(), "What the particle cache stores.")
        .child("surface", &Scene::surface, surfaceSchema(), "Surfacing defaults.")
        .child("render", &Scene::render, renderSchema(), "Render defaults.")
        .check([](const Scene& s, const Json& raw, const std::string& path) {
          checkSceneGeometry(s, raw, path);
          checkWallViscosity(s, raw, path);
          checkPeriodic(s, raw, path);
          checkEmittersAndRemoval(s, raw, path);
          checkDfsphWalls(s, raw, path);
          checkDfsphDepthStep(s, raw, path);
        });
  });
}

/// Lattice count along one axis of [lo, hi]: cell-centred points lo + (i + 0.5) s.
long latticeCount(double lo, double hi, double s) {
  // The small tolerance keeps an extent of exactly k spacings at k points despite rounding.
  return std::max(0L, long(std::floor((hi - lo) / s + 1e-6)));
}

template <class Fn>
void forEachSeed(const Scene& scene, Fn&& fn) {
  const double s = scene.fluid.spacing * scene.fluid.packing;
  for (const FluidBlock& b : scene.fluid.blocks) {
    Vec3d lo, hi;
    blockBounds(b, lo, hi);
    const long nx = latticeCount(lo[0], hi[0], s), ny = latticeCount(lo[1], hi[1], s),
               nz = latticeCount(lo[2], hi[2], s);
    for (long k = 0; k < nz; ++k)
      for (long j = 0; j < ny; ++j)
        for (long i = 0; i < nx; ++i) {
          // Centre the lattice in the block so that the leftover is split evenly on both sides.
          const Vec3d p{lo[0] + (hi[0] - lo[0] - double(nx) * s) / 2 + (double(i) + 0.5) * s,
                        lo[1] + (hi[1] - lo[1] - double(ny) * s) / 2 + (double(j) + 0.5) * s,
                        lo[2] + (hi[2] - lo[2] - double(nz) * s) / 2 + (double(k) + 0.5) * s};
          if (b.shape == Shape::Sphere) {
            double d2 = 0;
            for (int a = 0; a < 3; ++a) d2 += (p[a] - b.center[a]) * (p[a] - b.center[a]);
            if (d2 > b.radius * b.radius) continue;
          }
          fn(p, b);
        }
  }
}

}  // namespace

int periodicCells(double extent, double kernelRadius) {
  // Exact for extents that are whole multiples of h up to rounding (3 h must give 3 cells).
  return std::max(1, int(std::floor(extent / kernelRadius + 1e-9)));
}

bool Domain::isPeriodic(int axis) const {
  if (axis < 0 || axis > 2) return false;
  const PeriodicAxis want = std::array{PeriodicAxis::X, PeriodicAxis::Y, PeriodicAxis::Z}[size_t(axis)];
  return std::find(periodic.begin(), periodic.end(), want) != periodic.end();
}

Vec3d taylorGreenVelocity(const Domain& d, double U, const Vec3d& p) {
  const double lx = d.max[0] - d.min[0], lz = d.max[2] - d.min[2];
  const double ax = 2 * std::numbers::pi * (p[0] - d.min[0]) / lx,
               az = 2 * std::numbers::pi * (p[2] - d.min[2]) / lz;
  return {U * std::sin(ax) * std::cos(az), 0.0, -U * (lz / lx) * std::cos(ax) * std::sin(az)};
}

bool Scene::hasCacheAttribute(CacheAttribute a) const {
  return std::find(cache.attributes.begin(), cache.attributes.end(), a) != cache.attributes.end();
}

double Scene::soundSpeed() const {
  return solver.wcsph.eos == EquationOfState::Tait ? solver.speedOfSound : std::sqrt(solver.wcsph.stiffness);
}

double Scene::dfsphDepthStep() const {
  const double factor = solver.dfsph.depthStepFactor;
  if (solver.method != Solver::DFSPH || time.mode != TimeStepMode::Cfl || factor <= 0)
    return std::numeric_limits<double>::infinity();
  // g H of the column that the walls hold: sum_k |g_k| (max_k - min_k) over the walled axes. Gravity along
  // a periodic axis drives a flow, not a column (no cap where it all does, nor without gravity).
  double gDepth = 0;
  for (int k = 0; k < 3; ++k)
    if (!domain.isPeriodic(k))
      gDepth += std::fabs(gravity[size_t(k)]) * (domain.max[size_t(k)] - domain.min[size_t(k)]);
  if (gDepth <= 0) return std::numeric_limits<double>::infinity();
  return factor * fluid.spacing / std::sqrt(gDepth);
}

double Scene::wallViscosityMultiple() const {
  switch (fluid.viscosityModel) {
    case ViscosityModel::Laplacian:
      return fluid.wallViscosityFactor;
    case ViscosityModel::Artificial: {
      const double fluidSpeed = fluidArtificialSpeed(*this);
      const double wallSpeed = fluid.wallViscosityFactor * fluid.wallViscositySpeed;
      return wallSpeed > 0 && fluidSpeed > 0 ? wallSpeed / fluidSpeed : 0.0;
    }
    case ViscosityModel::None:
      break;
  }
  return 0.0;
}

const Object<Scene>& sceneSchema() {
  static const std::shared_ptr<const Object<Scene>> schema = buildSceneSchema();
  return *schema;
}

size_t countInitialParticles(const Scene& scene) {
  // Count without materialising the particles (validation runs this on every load).
  size_t n = 0;
  const double s = scene.fluid.spacing * scene.fluid.packing;
  for (const FluidBlock& b : scene.fluid.blocks) {
    if (b.shape == Shape::Box) {
      size_t c = 1;
      for (int a = 0; a < 3; ++a) c *= size_t(latticeCount(b.min[a], b.max[a], s));
      n += c;
    } else {
      Scene single = scene;
      single.fluid.blocks = {b};
      forEachSeed(single, [&](const Vec3d&, const FluidBlock&) { ++n; });
    }
    if (n > kMaxParticles) return n;
  }
  return n;
}

bool Domain::isOpen(int axis, int side) const {
  const auto face = DomainFace(axis * 2 + side);
  return std::find(open.begin(), open.end(), face) != open.end();
}

std::array<Vec3d, 2> emitterBasis(const Vec3d& d) {
  // u: d x (the coordinate axis least aligned with d), normalised; w = d x u.
  int least = 0;
  for (int a = 1; a < 3; ++a)
    if (std::fabs(d[a]) < std::fabs(d[least])) least = a;
  Vec3d e{0, 0, 0};
  e[size_t(least)] = 1;
  auto cross = [](const Vec3d& a, const Vec3d& b) {
    return Vec3d{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
  };
  Vec3d u = cross(d, e);
  const double n = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
  for (double& c : u) c /= n;
  return {u, cross(d, u)};
}

namespace {
Vec3d unit(const Vec3d& v) {
  const double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  return {v[0] / n, v[1] / n, v[2] / n};
}
}  // namespace

std::vector<Vec3d> emitterLayerPoints(const Scene& scene, const Emitter& e) {
  const double s = scene.fluid.spacing;
  if (e.shape != EmitterShape::Disc) {
    // A volume source: the cubic lattice of the fluid blocks over its bounds (cell centres, exact fit per
    // axis for a box; centred on the centre for a sphere), every point of the volume.
    std::vector<Vec3d> points;
    if (e.shape == EmitterShape::Box) {
      std::array<long, 3> n{};
      for (int a = 0; a < 3; ++a) n[a] = std::max(1L, long(std::lround((e.max[a] - e.min[a]) / s)));
      for (long k = 0; k < n[2]; ++k)
        for (long j = 0; j < n[1]; ++j)
          for (long i = 0; i < n[0]; ++i) {
            const std::array<long, 3> idx{i, j, k};
            Vec3d p;
            for (int a = 0; a < 3; ++a)
              p[a] = e.min[a] + (double(idx[a]) + 0.5) * (e.max[a] - e.min[a]) / double(n[a]);
            points.push_back(p);
          }
      return points;
    }
    const long n = long(std::floor(e.radius / s + 1e-9));
    const double r2 = (e.radius / s) * (e.radius / s) * (1 + 1e-12);
    for (long k = -n; k <= n; ++k)
      for (long j = -n; j <= n; ++j)
        for (long i = -n; i <= n; ++i)
          if (double(i * i + j * j + k * k) <= r2)
            points.push_back(
                {e.center[0] + s * double(i), e.center[1] + s * double(j), e.center[2] + s * double(k)});
    return points;
  }
  const auto [u, w] = emitterBasis(unit(e.direction));
  const long n = long(std::floor(e.radius / s + 1e-9));
  const double r2 = (e.radius / s) * (e.radius / s) * (1 + 1e-12);
  std::vector<Vec3d> points;
  for (long b = -n; b <= n; ++b)
    for (long a = -n; a <= n; ++a) {
      if (double(a * a + b * b) > r2) continue;
      Vec3d p;
      for (int k = 0; k < 3; ++k) p[k] = e.center[k] + s * (double(a) * u[k] + double(b) * w[k]);
      points.push_back(p);
    }
  return points;
}

size_t emitterLayers(const Scene& scene, const Emitter& e) {
  // Layer k leaves at start + k tau (tau = spacing / speed) and is emitted while that time is before end:
  // the count of k >= 0 with k < (end - start) / tau. The GPU emits no more (sim_emit.comp clamps to it).
  const double x = (e.end - e.start) * e.speed / scene.fluid.spacing;
  return x > 0 ? size_t(std::ceil(x)) : 0;
}

size_t countEmittedParticles(const Scene& scene, const Emitter& e) {
  return emitterLayers(scene, e) * emitterLayerPoints(scene, e).size();
}

size_t maxParticleCount(const Scene& scene) {
  size_t n = countInitialParticles(scene);
  for (const Emitter& e : scene.emitters) n += countEmittedParticles(scene, e);
  return n;
}

SeededParticles seedParticles(const Scene& scene) {
  SeededParticles out;
  const size_t n = countInitialParticles(scene);
  out.position.reserve(n);
  out.velocity.reserve(n);
  forEachSeed(scene, [&](const Vec3d& p, const FluidBlock& b) {
    out.position.push_back({float(p[0]), float(p[1]), float(p[2])});
    Vec3d v = b.velocity;
    if (b.taylorGreen) {
      const Vec3d vortex = taylorGreenVelocity(scene.domain, b.taylorGreen->amplitude, p);
      for (int a = 0; a < 3; ++a) v[a] += vortex[a];
    }
    out.velocity.push_back({float(v[0]), float(v[1]), float(v[2])});
  });
  return out;
}

namespace {

/// Keys of older scene files and where they are declared now (JSON pointers).
const std::vector<std::pair<std::string, std::string>>& movedKeys() {
  static const std::vector<std::pair<std::string, std::string>> moved = {
      {"/solver/eos", "/solver/wcsph/eos"},
      {"/solver/stiffness", "/solver/wcsph/stiffness"},
      {"/solver/gamma", "/solver/wcsph/gamma"},
      {"/time/force_factor", "/solver/wcsph/force_factor"},
      {"/solver/max_density_error", "/solver/dfsph/max_density_error"},
      {"/solver/max_divergence_error", "/solver/dfsph/max_divergence_error"},
      {"/solver/min_iterations", "/solver/dfsph/min_iterations"},
      {"/solver/max_iterations", "/solver/dfsph/max_iterations"},
      {"/solver/min_divergence_iterations", "/solver/dfsph/min_divergence_iterations"},
      {"/solver/jacobi_momentum", "/solver/dfsph/jacobi_momentum"},
      {"/time/fall_factor", "/solver/dfsph/fall_factor"},
  };
  return moved;
}

/// "/solver/eos" -> "solver.eos", for messages about --set paths.
std::string dotted(const std::string& pointer) {
  std::string out = pointer.substr(1);
  std::replace(out.begin(), out.end(), '/', '.');
  return out;
}

/// A choice that decides which other parameters are read: for each of its values, the keys (siblings
/// of the selector in the same object) that only that value reads. Setting the selector by an override
/// drops the keys only the other values read.
struct Selector {
  std::vector<std::string> path;  ///< object holding the selector and its keys
  std::string key;
  std::vector<std::pair<std::string, std::vector<std::string>>> keysOf;  ///< value -> keys only it reads
};

template <class Id>
Selector methodSelector(std::vector<std::string> path, const std::vector<MethodEntry<Id>>& registry) {
  Selector s{std::move(path), "method", {}};
  for (const auto& e : registry)
    s.keysOf.push_back({e.name, e.parameterGroup.empty() ? std::vector<std::string>{}
                                                         : std::vector<std::string>{e.parameterGroup}});
  return s;
}

const std::vector<Selector>& selectors() {
  static const std::vector<Selector> all = {
      methodSelector({"solver"}, pressureSolverRegistry()),
      methodSelector({"surface"}, surfacingMethodRegistry()),
      {{"time"},
       "dt_mode",
       {{"fixed", {"dt"}}, {"cfl", {"cfl_factor", "viscous_factor", "dt_min", "dt_max"}}}},
      {{"fluid"},
       "viscosity_model",
       {{"none", {}},
        {"laplacian", {"viscosity", "wall_viscosity_factor"}},
        {"artificial",
         {"artificial_viscosity", "wall_viscosity_factor", "wall_viscosity_speed", "wall_drag",
          "wall_friction"}}}},
      {{"fluid"}, "wall_drag", {{"viscous", {}}, {"friction", {"wall_friction"}}}},
      {{"solver", "wcsph"}, "eos", {{"linear", {"stiffness"}}, {"tait", {"gamma"}}}},
  };
  return all;
}

/// After an override set `parts` to `value`: if that is a selector, remove the keys that only its other
/// values read from the object holding it.
void dropKeysOfOtherChoices(Json& raw, const std::vector<std::string>& parts, const Json& value) {
  if (!value.is_string()) return;
  for (const Selector& sel : selectors()) {
    std::vector<std::string> full = sel.path;
    full.push_back(sel.key);
    if (full != parts) continue;
    Json* object = &raw;
    for (const auto& segment : sel.path) object = &(*object)[segment];
    std::vector<std::string> kept;
    for (const auto& [choice, keys] : sel.keysOf)
      if (choice == value.get<std::string>()) kept = keys;
    for (const auto& [choice, keys] : sel.keysOf)
      for (const auto& key : keys)
        if (std::find(kept.begin(), kept.end(), key) == kept.end() && object->is_object() &&
            object->contains(key)) {
          logInfo(fmt::format("--set {}={}: {}.{} is not read with it; dropped", fmt::join(full, "."),
                              value.get<std::string>(), fmt::join(sel.path, "."), key));
          object->erase(key);
        }
  }
}

}  // namespace

void migrateSceneJson(Json& raw, const std::string& source) {
  if (!raw.is_object()) return;
  for (const auto& [from, to] : movedKeys()) {
    const Json::json_pointer oldPtr(from), newPtr(to);
    if (!raw.contains(oldPtr)) continue;
    if (raw.contains(newPtr))
      throw InputError(
          fmt::format("{}: {}: given both here and at its new place {}; keep only {}", source, from, to, to));
    const Json::json_pointer parent = newPtr.parent_pointer();
    if (raw.contains(parent) && !raw[parent].is_object()) continue;  // the schema reports the bad parent
    raw[newPtr] = raw[oldPtr];
    raw[oldPtr.parent_pointer()].erase(oldPtr.back());
    logWarning(
        fmt::format("{}: {} has moved to {}; it is read from there now (update the file)", source, from, to));
  }
}

bool applyOverrideIfRead(Json& raw, const std::string& assignment) {
  Json trial = raw;
  applyOverride(trial, assignment);
  std::string pointer = "/";
  for (const char ch : assignment.substr(0, assignment.find('='))) pointer += ch == '.' ? '/' : ch;
  try {
    parseScene(trial, "");
  } catch (const InputError& e) {
    if (std::string(e.what()).find(pointer + ": not read with these settings") != std::string::npos)
      return false;
  }
  raw = std::move(trial);
  return true;
}

void applyOverride(Json& raw, const std::string& assignment) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw InputError("--set " + assignment + ": expected path=value, e.g. fluid.viscosity=0.02");
  std::string path = assignment.substr(0, eq);
  const std::string valueText = assignment.substr(eq + 1);
  Json value = Json::parse(valueText, nullptr, /*allow_exceptions=*/false);
  if (value.is_discarded()) value = valueText;  // bare words are strings: solver.method=dfsph

  migrateSceneJson(raw, "scene");
  for (const auto& [from, to] : movedKeys()) {
    const std::string oldPath = dotted(from), newPath = dotted(to);
    if (path == oldPath || path.rfind(oldPath + ".", 0) == 0) {
      logWarning(fmt::format("--set {}: has moved to {}", oldPath, newPath));
      path = newPath + path.substr(oldPath.size());
    }
  }

  Json* node = &raw;
  std::stringstream segments(path);
  std::string segment;
  std::vector<std::string> parts;
  while (std::getline(segments, segment, '.')) parts.push_back(segment);
  for (size_t i = 0; i < parts.size(); ++i) {
    const std::string& key = parts[i];
    if (key.empty()) throw InputError("--set " + assignment + ": empty path segment");
    const bool last = i + 1 == parts.size();
    if (node->is_array()) {
      const bool numeric = std::all_of(key.begin(), key.end(), [](char c) { return std::isdigit(c); });
      if (!numeric || std::stoul(key) >= node->size())
        throw InputError(fmt::format("--set {}: \"{}\" is not an index of an array of {} entries", assignment,
                                     key, node->size()));
      node = &(*node)[std::stoul(key)];
    } else if (node->is_object() || node->is_null()) {
      node = &(*node)[key];
    } else {
      throw InputError("--set " + assignment + ": \"" + key + "\" is below a value that is not an object");
    }
    if (last) *node = value;
  }
  dropKeysOfOtherChoices(raw, parts, value);
}

Scene parseScene(const Json& raw, const std::string& source) {
  Json migrated = raw;
  migrateSceneJson(migrated, source);
  return schema::readDocument(sceneSchema(), migrated, source);
}

namespace {
// Collider files are named relative to the scene file; the loaded scene holds absolute paths, so that
// the resolved scene (the shot's manifest, a farm job) reads the same files from any directory.
void resolveColliderFiles(Scene& scene, const std::string& scenePath, const std::string& source) {
  const std::filesystem::path base = std::filesystem::absolute(scenePath).parent_path();
  for (size_t i = 0; i < scene.colliders.size(); ++i) {
    Collider& c = scene.colliders[i];
    if (!c.isField()) continue;
    std::filesystem::path f(c.file);
    if (f.is_relative()) f = base / f;
    f = f.lexically_normal();
    std::error_code ec;
    if (!std::filesystem::is_regular_file(f, ec))
      throw InputError(fmt::format("{}: /colliders/{}/file: no such file: {}", source, i, f.string()));
    c.file = f.string();
  }
}
}  // namespace

Scene loadScene(const std::string& path, const std::vector<std::string>& overrides) {
  Json raw = schema::readJsonFile(path, "scene");
  migrateSceneJson(raw, path);
  for (const auto& o : overrides) applyOverride(raw, o);
  const std::string source = overrides.empty() ? path : path + " (with --set overrides)";
  Scene scene = parseScene(raw, source);
  resolveColliderFiles(scene, path, source);
  return scene;
}

Json sceneToJson(const Scene& scene) {
  Json j = sceneSchema().write(scene);
  // Fixed steps read no depth cap, and a scene that sets one with them is refused (checkDfsphDepthStep).
  if (scene.time.mode == TimeStepMode::Fixed && j["solver"].contains("dfsph"))
    j["solver"]["dfsph"].erase("depth_step_factor");
  return j;
}

Json sceneIdentityJson(const Scene& scene) {
  Json j = sceneToJson(scene);
  for (const char* k : {"emitters", "kill"})
    if (j.contains(k) && j[k].empty()) j.erase(k);
  if (j["domain"].contains("open") && j["domain"]["open"].empty()) j["domain"].erase("open");
  if (scene.limits.maxParticles == int(kMaxParticles)) j.erase("limits");
  if (j["fluid"].contains("wall_viscosity_factor") && scene.fluid.wallViscosityFactor == 1.0)
    j["fluid"].erase("wall_viscosity_factor");  // the walls' viscosity before the factor existed
  if (j["fluid"].value("wall_drag", "") == "viscous")
    j["fluid"].erase("wall_drag");  // the walls' term before the choice existed
  const double fluidSpeed = fluidArtificialSpeed(scene);
  if (j["fluid"].contains("wall_viscosity_speed") &&
      std::fabs(scene.fluid.wallViscositySpeed - fluidSpeed) <= 1e-12 * fluidSpeed)
    j["fluid"].erase("wall_viscosity_speed");  // the fluid's alpha c: the runs of caches without the key
  if (j["solver"].contains("dfsph")) {
    Json& dfsph = j["solver"]["dfsph"];
    if (dfsph.value("walls", "") == "push") dfsph.erase("walls");  // the only walls before the choice existed
    if (dfsph.value("density_kernel", "") == "poly6") dfsph.erase("density_kernel");        // likewise
    if (dfsph.value("depth_step_factor", 0.0) == 0.0) dfsph.erase("depth_step_factor");     // likewise
    if (dfsph.value("density_warm_steps", "") == "all") dfsph.erase("density_warm_steps");  // likewise
  }
  for (Json& c : j["colliders"])
    for (Json& k : c["keyframes"])
      if (k.contains("rotation") && k["rotation"] == Json::array({0, 0, 0})) k.erase("rotation");
  return j;
}

std::string sceneReferenceMarkdown() {
  std::vector<schema::FieldDoc> docs;
  sceneSchema().document("", docs);
  std::string out =
      "# Scene format\n\n"
      "<!-- Generated by `sphfx scene --schema` from the declarations in core/src/scene.cpp. Do not edit: "
      "a test fails when this file is stale. -->\n\n"
      "Scenes are JSON files in SI units; +Y is up. Every key is optional (its default is used) unless a "
      "shape needs it; unknown keys are errors. `sphfx scene FILE` prints a scene resolved, and "
      "`--set path=value` overrides any parameter from the command line (`--set "
      "fluid.blocks.0.max=[1,2,1]`).\n\n"
      "| Parameter | Type | Default | Unit | Valid | Description |\n"
      "|---|---|---|---|---|---|\n";
  for (const auto& d : docs) {
    auto cell = [](std::string s) {
      std::string r;
      for (char c : s) r += c == '|' ? std::string("\\|") : std::string(1, c);
      return r;
    };
    out += fmt::format("| `{}` | {} | {} | {} | {} | {} |\n", d.path, d.type, cell(d.defaultValue), d.unit,
                       cell(d.range), cell(d.description));
  }
  return out;
}

}  // namespace sphfx

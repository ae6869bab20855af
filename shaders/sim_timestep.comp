// One invocation per substep, between the force and the integration pass: checks the substep's
// reductions (health), picks dt (fixed or CFL), lands the last substep exactly on the frame time, and
// empties the later indirect dispatches once the frame is reached, so the CPU can queue substeps in
// batches and read back only once per batch.
#include "sph_params.glsl"
layout(local_size_x = 1) in;
// [0, 3n): indirect dispatch arguments; [3n, 6n): their live values. Entry 0 is the integration.
layout(std430, binding = SPHFX_SSBO_SIM_DISPATCH) buffer SimDispatch { uint dispatchArgs[]; };

void closeDispatches(uint firstEntry) {
  for (uint k = firstEntry * 3u; k < simCounts.w * 3u; ++k) dispatchArgs[k] = 0u;
}

bool finite(float x) { return !isnan(x) && !isinf(x); }

float chooseDt(float speed2, float accel2) {
  if (simStep.w > 0.0) return simStep.w;
  float h = simDomainMin.w;
#if defined(SOLVER_DFSPH)
  // Incompressible: the flow alone limits dt (no sound speed). Bender & Koschier's CFL condition bounds
  // the step's displacement by cfl d (d the particle spacing: with h the dam break's front runs at twice
  // the surge speed), including what the non-pressure accelerations add during the step,
  // |v| dt + |a| dt^2 <= cfl d, so that a step from rest (|v| = 0) does not fall further than the
  // pressure solve's linearisation can take back (|v| alone: 0.63 d onto the floor, and the run fails).
  float reach = simStep.x * simDomainMax.w, v = sqrt(speed2), a = sqrt(accel2);
  float dt = a > 0.0 ? 2.0 * reach / (v + sqrt(v * v + 4.0 * a * reach))
                     : (v > 0.0 ? reach / v : simLimits.y);
  // The fall alone, |a| dt^2 <= fall_factor d: larger first steps from rest cost front accuracy at fine
  // spacings.
  if (a > 0.0) dt = min(dt, sqrt(simStep.z * simDomainMax.w / a));
#else
  float dt = simStep.x * h / (simFluid.w + sqrt(speed2));
  if (accel2 > 0.0) dt = min(dt, simStep.z * sqrt(h / sqrt(accel2)));
#endif
#if defined(VISCOSITY_LAPLACIAN)
  // The walls' viscosity is fluid.wall_viscosity_factor times the fluid's (w: 0 without SIM_WALL_VISCOSITY).
  if (simViscosity.x > 0.0) dt = min(dt, simStep.y * h * h / (simViscosity.x * max(1.0, simViscosity.w)));
#endif
  return dt;
}

void main() {
  if (stateDone != 0u) {
    closeDispatches(0u);
    return;
  }
  float speed2 = uintBitsToFloat(stateMaxSpeed2), accel2 = uintBitsToFloat(stateMaxAccel2);
  float rho = uintBitsToFloat(stateMaxDensity);
  uint fail = stateFailure;  // bits a solver pass set during this substep (SIM_FAIL_NEIGHBORS)
  if (!finite(speed2) || !finite(accel2) || !finite(rho)) fail |= SIM_FAIL_NONFINITE;
  if (speed2 > simLimits.w * simLimits.w) fail |= SIM_FAIL_SPEED;
  if (rho > simLimits.z) fail |= SIM_FAIL_DENSITY;
  float dt = chooseDt(speed2, accel2);
  if (simStep.w == 0.0 && !(dt >= simLimits.x)) fail |= SIM_FAIL_DT;
  if (fail != 0u) {
    stateFailure = fail;
    stateFailSubstep = stateSubsteps + 1u;
    stateDone = 1u;
    closeDispatches(0u);
    return;
  }
  // Reset the reductions only on success: on failure the CPU reads them for the error message.
  stateMaxSpeed2 = 0u;
  stateMaxAccel2 = 0u;
  stateMaxDensity = 0u;
#if defined(DFSPH_WARM_FLOW_LIMITED)
  // This substep's constant-density solve (after this pass) starts warm if the last chosen step was the
  // flow's, as its factor and non-pressure passes (before it) read from stateFlowLimited; this step's
  // limit decides the next substep's.
  stateWarmDensity = stateFlowLimited;
  stateWarmSubsteps += stateFlowLimited;
#endif
#if defined(DFSPH_WARM_FLOW_LIMITED) || defined(DFSPH_CAPPED_TOLERANCE)
  // Also this substep's density tolerance (sim_dfsph_reduce.comp).
  stateFlowLimited = simStep.w == 0.0 && dt < simLimits.y ? 1u : 0u;
#endif
  if (simStep.w == 0.0) dt = min(dt, simLimits.y);
  // Land on the frame: the last step takes what remains; when less than two steps remain, split the
  // rest in halves rather than leave a sliver. dt is a float: a dt_max equal to the frame time (e.g.
  // 0.005 s at 200 fps) can round just below the double remainder, and must not split the frame in two.
  double remaining = stateFrameEnd - stateTime;
  bool last = double(dt) >= remaining * (1.0lf - 1e-6lf);
  if (last) dt = float(remaining);
  else if (2.0lf * double(dt) > remaining) dt = float(remaining * 0.5lf);
  stateDt = dt;
  stateTime = last ? stateFrameEnd : stateTime + double(dt);
  stateSubsteps += 1u;
  stateDtSum += double(dt);
  stateDtLow = min(stateDtLow, dt);
  stateDtHigh = max(stateDtHigh, dt);
  if (last) {
    stateDone = 1u;
    closeDispatches(1u);  // keep this substep's integration
  }
}

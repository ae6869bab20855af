#pragma once
/// @file boundary_akinci2012.h
/// @brief Boundary handling with Akinci et al. 2012's boundary samples, "Versatile rigid-fluid coupling
/// for incompressible SPH": the domain walls and the colliders are sampled by boundary particles with a
/// volume weight psi_b (kg), so that a fluid particle at a wall sees a full neighbourhood (density,
/// pressure force, friction). Unlike Akinci's single surface layer with psi = rho0 / sum_k W_bk, the
/// samples continue the fluid's lattice kernel-radius deep into the solid with psi_b = the mass of their
/// lattice cell: exact rest density at flat walls and corners without any fudge factor. Moving colliders
/// carry their velocity. Solvers read the cell-sorted samples through the same grid ranges as the fluid.

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "dispatch_gate.h"
#include "neighbor_grid.h"
#include "sphfx/core/collider_geometry.h"
#include "sphfx/core/scene.h"
#include "sphfx/gpu/gpu_buffer.h"
#include "sphfx/gpu/shader_program.h"

namespace sphfx::sim {

/// Boundary samples at rest: position and psi, and the body (kWallBody or a collider index).
struct BoundarySamples {
  static constexpr uint32_t kWallBody = 0xffffffffu;
  std::vector<std::array<float, 4>> rest;  ///< xyz, w = psi (kg)
  std::vector<uint32_t> body;
  size_t size() const { return rest.size(); }
};

/// Layers of boundary samples: ceil(h / spacing), enough that a fluid particle on the wall plane sees
/// solid samples over its whole kernel support.
int boundaryLayers(const Scene& scene);

/// The signed distance fields of the scene's mesh and vdb colliders, by collider index (analytic
/// colliders: an empty field).
using ColliderFields = std::vector<ColliderField>;

/// Builds (or, with a `shotDir`, reads back from colliderFieldPath()) the fields of the scene's mesh and
/// vdb colliders at colliderFieldSpec(); logs each one's voxel count and time.
/// @throws InputError, IoError as buildColliderField.
ColliderFields buildColliderFields(const Scene& scene, const std::string& shotDir = "");

/// Samples the domain walls (a shell outside the domain, none on the faces of periodic axes) and every
/// collider (a shell inside it, at rest) on a lattice about one fluid spacing apart, boundaryLayers()
/// deep. Mesh and vdb colliders take the cell centres of their bounds' lattice whose distance is in
/// (-layers * spacing, 0] from `fields`, which must hold theirs. Deterministic.
BoundarySamples sampleBoundaries(const Scene& scene, const ColliderFields& fields = {});

/// Logs a warning when a walled axis that a fluid block reaches is not a whole number of fluid spacings: the
/// wall samples then sit on a lattice that fits the domain exactly (a step other than the spacing), and the
/// fluid next to those walls starts off its rest density and splashes in the first frames.
void warnIfWallLatticeMisfits(const Scene& scene);

class BoundaryAkinci2012 {
 public:
  /// Uploads the samples and colliders, builds the programs; static scenes sort the samples once
  /// here. Needs a current context. @throws GLError.
  BoundaryAkinci2012(const Scene& scene, const ColliderFields& fields, DispatchGate& gate,
                     const GridSpec& grid, const ShaderDefines& defines);

  /// Moves the collider samples to the current substep's start time and re-sorts them (GPU work;
  /// nothing for scenes without colliders).
  void update() const;
  /// Places and sorts every sample for the current time (static scenes: once, here). GPU work.
  void prepare() const;
  /// Binds the sorted samples and their cell ranges for the solver passes, and the colliders.
  void bind() const;
  uint32_t count() const { return count_; }
  /// The dispatch gate's entry over the samples (one invocation per sample).
  uint32_t gateEntry() const { return entry_; }
  bool moving() const { return moving_; }
  /// The samples placed for the latest update(), sorted by cell: xyz and psi, and velocity (tests).
  const GpuBuffer& positions() const { return pos_; }
  const GpuBuffer& velocities() const { return vel_; }

 private:
  void sort() const;

  const DispatchGate* gate_;
  uint32_t count_;
  bool moving_;
  GpuBuffer rest_, body_, unsortedPos_, unsortedVel_, pos_, vel_, colliders_, keys_, field_;
  std::unique_ptr<NeighborGrid> grid_;
  ShaderProgram update_;
  uint32_t entry_;
};

}  // namespace sphfx::sim

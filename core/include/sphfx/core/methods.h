#pragma once
/// @file methods.h
/// @brief The registries of interchangeable methods: pressure solvers and surfacing methods.
///
/// Each method is named once, here: its scene name, a one-line description, and the key of its own
/// parameter group in the scene (`solver.dfsph`, `surface.anisotropic`; empty when it has none). The
/// scene schema's enums and generated docs, the CLI's choices and the manifests all read these tables;
/// each stage maps the ids to its implementations (sim: makePressureSolver, surfacing: the rasterizers)
/// and its tests check that every registered method has one.

#include <string>
#include <utility>
#include <vector>

#include "sphfx/core/error.h"

namespace sphfx {

enum class Solver { WCSPH, DFSPH };
enum class SurfaceMethod { Spheres, ZhuBridson, Anisotropic };

template <class Id>
struct MethodEntry {
  Id id;
  std::string name;            ///< scene and command-line name, e.g. "dfsph"
  std::string description;     ///< one line, with the paper it implements
  std::string parameterGroup;  ///< key of the method's parameter object in the scene, or empty
};

/// WCSPH and DFSPH (the scene's solver.method).
const std::vector<MethodEntry<Solver>>& pressureSolverRegistry();
/// spheres, zhu-bridson and anisotropic (the scene's surface.method, `sphfx surface --method`).
const std::vector<MethodEntry<SurfaceMethod>>& surfacingMethodRegistry();

/// The entry of `id`. @throws Error if `id` is not registered (a programming error).
template <class Id>
const MethodEntry<Id>& methodEntry(const std::vector<MethodEntry<Id>>& registry, Id id) {
  for (const auto& e : registry)
    if (e.id == id) return e;
  throw Error("method id without a registry entry");
}

/// The names of a registry, in its order.
template <class Id>
std::vector<std::string> methodNames(const std::vector<MethodEntry<Id>>& registry) {
  std::vector<std::string> names;
  for (const auto& e : registry) names.push_back(e.name);
  return names;
}

/// (name, id) pairs for the schema's enum declarations.
template <class Id>
std::vector<std::pair<std::string, Id>> methodChoices(const std::vector<MethodEntry<Id>>& registry) {
  std::vector<std::pair<std::string, Id>> choices;
  for (const auto& e : registry) choices.emplace_back(e.name, e.id);
  return choices;
}

/// "name: description; ..." for a parameter's documentation.
template <class Id>
std::string methodDescriptions(const std::vector<MethodEntry<Id>>& registry) {
  std::string out;
  for (const auto& e : registry) out += (out.empty() ? "" : "; ") + ("\"" + e.name + "\": " + e.description);
  return out;
}

}  // namespace sphfx

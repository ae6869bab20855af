#pragma once
/// @file manifest.h
/// @brief The shot manifest, SHOT/manifest.json: what each stage did (scene resolved, frames written,
/// timings). Stages update their own section under a file lock and rewrite the file atomically.

#include <functional>
#include <nlohmann/json.hpp>
#include <string>

namespace sphfx {

using ManifestJson = nlohmann::ordered_json;

constexpr int kManifestVersion = 1;

std::string manifestPath(const std::string& shotDir);

/// The manifest, or an empty object with "manifest_version" set if the shot has none yet.
/// @throws InputError if the file exists but is not valid JSON.
ManifestJson readManifest(const std::string& shotDir);

/// Reads, lets `edit` change, and atomically rewrites the manifest, holding an exclusive lock so that
/// stages running at once (e.g. surfacing while simulating) do not lose each other's updates.
/// @throws IoError, InputError.
void updateManifest(const std::string& shotDir, const std::function<void(ManifestJson&)>& edit);

}  // namespace sphfx

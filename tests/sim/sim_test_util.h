#pragma once
// Shared helpers of the simulation tests: a GL context per the SPHFX_GL backend, small scenes.
#include <gtest/gtest.h>

#include <cstdlib>
#include <memory>
#include <string>

#include "sphfx/core/gl_context.h"
#include "sphfx/core/scene.h"

namespace sphfx::test {

inline std::unique_ptr<GLContext> makeContext() {
  const char* name = std::getenv("SPHFX_GL");
  return GLContext::create({parseGLBackend(name ? name : "auto"), false});
}

/// A scene from JSON text with the given overrides.
inline Scene sceneFromJson(const std::string& text) {
  return parseScene(schema::Json::parse(text), "test");
}

}  // namespace sphfx::test

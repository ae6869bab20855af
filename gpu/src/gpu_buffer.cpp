#include "sphfx/gpu/gpu_buffer.h"

#include <fmt/format.h>

#include <utility>

#include "sphfx/core/error.h"
#include "sphfx/gpu/gl.h"
#include "sphfx/gpu/gl_context.h"

namespace sphfx {

GpuBuffer::GpuBuffer(size_t bytes) {
  resize(bytes);
}

GpuBuffer::~GpuBuffer() {
  release();
}

void GpuBuffer::release() {
  if (texture_) glDeleteTextures(1, &texture_);
  if (id_) glDeleteBuffers(1, &id_);
  texture_ = id_ = 0;
}

GpuBuffer::GpuBuffer(GpuBuffer&& other) noexcept
    : id_(std::exchange(other.id_, 0)),
      bytes_(std::exchange(other.bytes_, 0)),
      texture_(std::exchange(other.texture_, 0)),
      textureFormat_(std::exchange(other.textureFormat_, 0)),
      textureBytes_(std::exchange(other.textureBytes_, 0)) {}

GpuBuffer& GpuBuffer::operator=(GpuBuffer&& other) noexcept {
  if (this != &other) {
    release();
    id_ = std::exchange(other.id_, 0);
    bytes_ = std::exchange(other.bytes_, 0);
    texture_ = std::exchange(other.texture_, 0);
    textureFormat_ = std::exchange(other.textureFormat_, 0);
    textureBytes_ = std::exchange(other.textureBytes_, 0);
  }
  return *this;
}

void GpuBuffer::resize(size_t bytes) {
  if (id_ && bytes == bytes_) return;
  if (!id_) glGenBuffers(1, &id_);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, id_);
  // Never zero bytes: a zero-sized store cannot be bound, and empty scenes are legal in tests.
  glBufferData(GL_SHADER_STORAGE_BUFFER, GLsizeiptr(bytes ? bytes : 4), nullptr, GL_DYNAMIC_COPY);
  bytes_ = bytes;
  glCheck("GpuBuffer::resize");
}

void GpuBuffer::upload(const void* data, size_t bytes, size_t offset) {
  if (bytes == 0) return;
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, id_);
  glBufferSubData(GL_SHADER_STORAGE_BUFFER, GLintptr(offset), GLsizeiptr(bytes), data);
  glCheck("GpuBuffer::upload");
}

void GpuBuffer::download(void* data, size_t bytes, size_t offset) const {
  if (bytes == 0) return;
  // Shader writes must be visible to the read-back.
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, id_);
  glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, GLintptr(offset), GLsizeiptr(bytes), data);
  glCheck("GpuBuffer::download");
}

void GpuBuffer::fill(uint32_t value) {
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, id_);
  glClearBufferData(GL_SHADER_STORAGE_BUFFER, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &value);
  glCheck("GpuBuffer::fill");
}

void GpuBuffer::bindStorage(uint32_t binding) const {
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding, id_);
}

void GpuBuffer::bindUniform(uint32_t binding) const {
  glBindBufferBase(GL_UNIFORM_BUFFER, binding, id_);
}

namespace {

size_t texelBytes(uint32_t format) {
  switch (format) {
    case GL_RGBA32F:
      return 16;
    case GL_RG32F:
      return 8;
    case GL_R32F:
    case GL_R32UI:
      return 4;
    default:
      throw GLError(fmt::format("GpuBuffer::bindTexture: unsupported texel format 0x{:x}", format));
  }
}

}  // namespace

size_t maxTextureBufferTexels() {
  GLint limit = 0;
  glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &limit);
  return size_t(limit);
}

void GpuBuffer::bindTexture(uint32_t unit, uint32_t format) const {
  if (!texture_) glGenTextures(1, &texture_);
  glActiveTexture(GL_TEXTURE0 + unit);
  glBindTexture(GL_TEXTURE_BUFFER, texture_);
  if (format != textureFormat_ || bytes_ != textureBytes_) {
    const size_t texels = bytes_ / texelBytes(format);
    const size_t limit = maxTextureBufferTexels();
    if (texels > limit)
      throw GLError(fmt::format(
          "a buffer of {} texels is larger than this GL's GL_MAX_TEXTURE_BUFFER_SIZE ({})", texels, limit));
    glTexBuffer(GL_TEXTURE_BUFFER, format, id_);
    textureFormat_ = format;
    textureBytes_ = bytes_;
  }
  glActiveTexture(GL_TEXTURE0);
  glCheck("GpuBuffer::bindTexture");
}

}  // namespace sphfx

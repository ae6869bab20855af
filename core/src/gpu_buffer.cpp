#include "sphfx/core/gpu_buffer.h"

#include <utility>

#include "sphfx/core/gl.h"
#include "sphfx/core/gl_context.h"

namespace sphfx {

GpuBuffer::GpuBuffer(size_t bytes) {
  resize(bytes);
}

GpuBuffer::~GpuBuffer() {
  if (id_) glDeleteBuffers(1, &id_);
}

GpuBuffer::GpuBuffer(GpuBuffer&& other) noexcept
    : id_(std::exchange(other.id_, 0)), bytes_(std::exchange(other.bytes_, 0)) {}

GpuBuffer& GpuBuffer::operator=(GpuBuffer&& other) noexcept {
  if (this != &other) {
    if (id_) glDeleteBuffers(1, &id_);
    id_ = std::exchange(other.id_, 0);
    bytes_ = std::exchange(other.bytes_, 0);
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

}  // namespace sphfx
